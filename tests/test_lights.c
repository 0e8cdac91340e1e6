/* Direct lighting against closed forms: scenes built in memory from quads,
 * rendered by the path tracer at max depth 2 (direct light only) or 1
 * (emitters seen directly), and compared with what the light sources give
 * analytically on a Lambertian plane:
 *   point light   L = (a / pi) I cos(theta) / d^2, and inverse-square;
 *   spot light    the same times the glTF cone falloff, squared;
 *   area light    (a / pi) Le E with E from Lambert's polygon formula, and
 *                 one-sided emission seen from the front and the back;
 *   texture       albedo per texel block = factor x srgb_to_linear(texel);
 *   seeds         a large emitter (MIS matters) gives one mean for two seeds.
 * The analytic side follows the camera of kernels/camera.h (ray through the
 * pixel position, box filter jittered uniformly inside the pixel), so each
 * pixel is compared with the average of the closed form over its footprint. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "harness.h"

#define PI 3.14159265358979323846

/* ---- small vector helpers (double precision for the closed forms) ---- */

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void normalize3(double v[3])
{
    double len = sqrt(dot3(v, v));
    for (int k = 0; k < 3; k++) v[k] /= len;
}

static double srgb_to_linear(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* ---- scenes from quads ---- */

typedef struct {
    float p[4][3];  /* corners, counter-clockwise seen from the front face */
    float uv[4][2]; /* texture coordinates at the corners */
    uint32_t material;
} quad;

/* Zeroed memory, or the test program ends with a FAIL line. */
static void *must_alloc(size_t bytes)
{
    void *p = calloc(1, bytes ? bytes : 1);
    if (!p) {
        printf("FAIL test_lights: out of memory\n");
        exit(1);
    }
    return p;
}

static void *copy_of(const void *data, size_t bytes)
{
    void *p = must_alloc(bytes);
    if (bytes) memcpy(p, data, bytes);
    return p;
}

/* A scene of quads (two triangles each, sharing corners 0 and 2) with the
 * given materials and punctual lights; the scene owns copies of everything. */
static void quad_scene(const quad *quads, size_t quad_count, const lvcl_material_desc *materials,
                       size_t material_count, const lv_punctual_light *lights, size_t light_count, lvcl_scene *s)
{
    memset(s, 0, sizeof *s);
    s->vertex_count = 4 * quad_count;
    s->triangle_count = 2 * quad_count;
    s->positions = must_alloc(12 * quad_count * sizeof(float));
    s->normals = must_alloc(12 * quad_count * sizeof(float)); /* unused: no LV_TRI_HAS_NORMALS */
    s->uvs = must_alloc(8 * quad_count * sizeof(float));
    s->indices = must_alloc(6 * quad_count * sizeof(uint32_t));
    s->tri_material = must_alloc(2 * quad_count * sizeof(uint32_t));
    s->tri_flags = must_alloc(2 * quad_count * sizeof(uint32_t));
    static const uint32_t corners[6] = {0, 1, 2, 0, 2, 3};
    for (size_t q = 0; q < quad_count; q++) {
        for (int c = 0; c < 4; c++) {
            memcpy(&s->positions[3 * (4 * q + c)], quads[q].p[c], 3 * sizeof(float));
            memcpy(&s->uvs[2 * (4 * q + c)], quads[q].uv[c], 2 * sizeof(float));
        }
        for (int i = 0; i < 6; i++) s->indices[6 * q + i] = (uint32_t)(4 * q + corners[i]);
        for (int t = 0; t < 2; t++) {
            s->tri_material[2 * q + t] = quads[q].material;
            s->tri_flags[2 * q + t] = LV_TRI_HAS_UVS; /* shading uses the true (geometric) normal */
        }
    }
    s->materials = copy_of(materials, material_count * sizeof *materials);
    s->material_count = material_count;
    s->punctuals = light_count ? copy_of(lights, light_count * sizeof *lights) : NULL;
    s->punctual_count = light_count;
}

/* A horizontal square of half-size `half` centred on (x, y) at height z,
 * facing up (+z) or down; uv (0,0) at its (-x, +y) corner and (1,1) at its
 * (+x, -y) corner, so seen from above with +y up the texture is upright. */
static quad horizontal_quad(double x, double y, double z, double half, int facing_up, uint32_t material)
{
    quad q = {.material = material};
    const double cx[4] = {-1, 1, 1, -1}, cy[4] = {-1, -1, 1, 1}; /* counter-clockwise seen from above */
    for (int c = 0; c < 4; c++) {
        int k = facing_up ? c : 3 - c; /* reversed winding faces down */
        q.p[c][0] = (float)(x + half * cx[k]);
        q.p[c][1] = (float)(y + half * cy[k]);
        q.p[c][2] = (float)z;
        q.uv[c][0] = (float)(0.5 * (cx[k] + 1));
        q.uv[c][1] = (float)(0.5 * (1 - cy[k]));
    }
    return q;
}

/* Lambertian in lvcl's mapping (host/scene/materials.c): specular 0 selects the
 * pure diffuse BSDF instead of the plastic layer. */
static lvcl_material_desc lambertian(float albedo)
{
    lvcl_material_desc m = {0};
    for (int k = 0; k < 3; k++) m.base_color[k] = albedo;
    m.base_color[3] = 1.0f;
    m.base_color_texture = -1;
    m.roughness = 1.0f;
    m.ior = 1.5f;
    m.specular = 0.0f;
    m.attenuation_color[0] = m.attenuation_color[1] = m.attenuation_color[2] = 1.0f;
    m.attenuation_distance = INFINITY;
    m.double_sided = 1;
    return m;
}

/* A black, one-sided emitter of radiance le. */
static lvcl_material_desc emitter(float le)
{
    lvcl_material_desc m = lambertian(0.0f);
    m.emissive[0] = m.emissive[1] = m.emissive[2] = le;
    m.double_sided = 0;
    return m;
}

static lv_punctual_light point_light(double x, double y, double z, const double intensity[3])
{
    lv_punctual_light l = {0};
    l.position[0] = (float)x;
    l.position[1] = (float)y;
    l.position[2] = (float)z;
    l.type = LV_PUNCTUAL_POINT;
    l.direction[2] = -1.0f;
    l.cos_outer = -1.0f;
    l.cos_inner = 1.0f;
    for (int k = 0; k < 3; k++) l.intensity[k] = (float)intensity[k];
    return l;
}

/* ---- the camera, as kernels/camera.h and host/scene/camera.c make it ---- */

typedef struct {
    lvcl_camera_desc cam;
    int width, height;
} view;

/* A square image looking straight down (-z) or up (+z) from (x, y, z),
 * with +y up in the image either way; right = up x back. */
static view vertical_view(double x, double y, double z, int looking_down, double yfov_degrees, int size)
{
    view v = {.width = size, .height = size};
    lvcl_camera_desc *c = &v.cam;
    c->present = 1;
    c->position[0] = (float)x;
    c->position[1] = (float)y;
    c->position[2] = (float)z;
    c->up[1] = 1.0f;
    c->back[2] = looking_down ? 1.0f : -1.0f;
    c->right[0] = looking_down ? 1.0f : -1.0f;
    c->yfov = (float)(yfov_degrees * PI / 180.0);
    c->aspect = 1.0f;
    return v;
}

/* The ray through image position (px, py) in pixels (pixel x spans [x, x+1)). */
static void camera_ray(const view *v, double px, double py, double origin[3], double dir[3])
{
    const lvcl_camera_desc *c = &v->cam;
    double half_h = tan(0.5 * c->yfov), half_w = half_h * v->width / v->height;
    double sx = 2.0 * px / v->width - 1.0, sy = 1.0 - 2.0 * py / v->height;
    for (int k = 0; k < 3; k++) {
        origin[k] = c->position[k];
        dir[k] = -c->back[k] + sx * half_w * c->right[k] + sy * half_h * c->up[k];
    }
    normalize3(dir);
}

/* Where the ray meets the ground plane z = 0; 0 if it does not. */
static int hit_ground(const double o[3], const double d[3], double p[3])
{
    if (!(d[2] * o[2] < 0.0)) return 0;
    double t = -o[2] / d[2];
    for (int k = 0; k < 3; k++) p[k] = o[k] + t * d[k];
    p[2] = 0.0;
    return 1;
}

/* Sub-samples per pixel side for the closed forms' pixel averages. */
#define SUB 8

/* The ground point seen through sub-sample (i, j) of pixel (x, y). */
static int subsample_ground(const view *v, int x, int y, int i, int j, double p[3])
{
    double o[3], d[3];
    camera_ray(v, x + (i + 0.5) / SUB, y + (j + 0.5) / SUB, o, d);
    return hit_ground(o, d, p);
}

/* Radiance leaving ground point p toward the camera (Lambertian: any direction). */
typedef double (*ground_radiance)(const void *ctx, const double p[3]);

/* Mean and standard deviation of f over what pixel (x, y) sees. The pixel
 * filter jitters uniformly inside the pixel, so the mean is the value the
 * pixel converges to; when the estimator is otherwise exact (punctual
 * lights) sd / sqrt(spp) is the noise the jitter leaves. */
static void pixel_stats(const view *v, int x, int y, ground_radiance f, const void *ctx, double *mean, double *sd)
{
    double sum = 0.0, sum2 = 0.0;
    for (int j = 0; j < SUB; j++)
        for (int i = 0; i < SUB; i++) {
            double p[3], l = 0.0;
            if (subsample_ground(v, x, y, i, j, p)) l = f(ctx, p);
            sum += l;
            sum2 += l * l;
        }
    *mean = sum / (SUB * SUB);
    *sd = sqrt(fmax(0.0, sum2 / (SUB * SUB) - *mean * *mean));
}

/* ---- rendering ---- */

/* Renders `scene` (consumed) through a session; returns the w x h x 3
 * image, or NULL after a FAIL line. */
static float *render(const char *what, lvcl_scene *scene, unsigned seed, int max_depth, const view *v, int spp)
{
    lvcl_status st = {0};
    lvcl_session *s = NULL;
    lvcl_session_config cfg = {.device = getenv("LVCL_TEST_DEVICE"), .seed = seed, .max_depth = max_depth, .fast_math = 1};
    lvcl_render_result r = {0};
    lvcl_pass_settings ps = {.spp = spp};
    scene->camera = v->cam;
    if (lvcl_session_open(scene, &cfg, &s, &st) || lvcl_session_render_pt(s, v->width, v->height, &ps, &r, &st)) {
        CHECK(what, 0, "render failed: %s", st.message);
        lvcl_session_close(s);
        return NULL;
    }
    lvcl_session_close(s);
    return r.rgb;
}

static float pixel(const float *rgb, const view *v, int x, int y, int c)
{
    return rgb[3 * ((size_t)y * v->width + x) + c];
}

/* ---- closed forms on the ground plane (normal +z) ---- */

/* The glTF spot cone as kernels/lights.h states it: smooth between the
 * outer and inner cosines, squared. */
static double spot_falloff(const lv_punctual_light *l, const double from_light[3])
{
    if (l->type != LV_PUNCTUAL_SPOT) return 1.0;
    double axis[3] = {l->direction[0], l->direction[1], l->direction[2]};
    double a = (dot3(axis, from_light) - l->cos_outer) / fmax(0.001, (double)l->cos_inner - l->cos_outer);
    a = fmin(1.0, fmax(0.0, a));
    return a * a;
}

typedef struct {
    const lv_punctual_light *light;
    double albedo;
} punctual_ground;

/* (a / pi) x falloff x cos(theta) / d^2 per unit intensity. */
static double punctual_radiance(const void *ctx, const double p[3])
{
    const punctual_ground *g = ctx;
    double to_light[3], d2 = 0.0;
    for (int k = 0; k < 3; k++) {
        to_light[k] = g->light->position[k] - p[k];
        d2 += to_light[k] * to_light[k];
    }
    double d = sqrt(d2);
    double from_light[3] = {-to_light[0] / d, -to_light[1] / d, -to_light[2] / d};
    double cos_theta = to_light[2] / d;
    if (cos_theta <= 0.0) return 0.0;
    return g->albedo / PI * spot_falloff(g->light, from_light) * cos_theta / d2;
}

/* Irradiance at p (normal +z) from a polygon of unit radiance, by Lambert's
 * formula E = sum_i theta_i / 2 (n . unit(r_(i+1) x r_i)), theta_i the angle
 * between r_i and r_(i+1), the directions from p to the corners. Corners
 * come in the emitter's front-face order, counter-clockwise as seen from p
 * in front of it; for that order r_(i+1) x r_i (not r_i x r_(i+1)) gives a
 * positive E. (Checked: a unit square 1 m above p gives E = 0.7523, the
 * closed form for a rectangle 4 x 0.05987 pi.) */
static double polygon_irradiance(const float corners[][3], int n, const double p[3])
{
    double e = 0.0;
    for (int i = 0; i < n; i++) {
        const float *a = corners[i], *b = corners[(i + 1) % n];
        double ra[3] = {a[0] - p[0], a[1] - p[1], a[2] - p[2]};
        double rb[3] = {b[0] - p[0], b[1] - p[1], b[2] - p[2]};
        normalize3(ra);
        normalize3(rb);
        double g[3];
        cross3(rb, ra, g);
        normalize3(g);
        double theta = acos(fmin(1.0, fmax(-1.0, dot3(ra, rb))));
        e += 0.5 * theta * g[2];
    }
    return e;
}

typedef struct {
    const quad *light;
    double albedo, le;
} area_ground;

static double area_radiance(const void *ctx, const double p[3])
{
    const area_ground *g = ctx;
    return g->albedo / PI * g->le * polygon_irradiance(g->light->p, 4, p);
}

/* ---- the tests ---- */

/* The ground: a large Lambertian square facing up, material 0. */
static quad ground(void)
{
    return horizontal_quad(0, 0, 0, 20, 1, 0);
}

/* Pixel-by-pixel comparison with a closed form times intensity[c]. Each
 * channel may be off by 1% plus five standard deviations of the jitter
 * noise plus `abs_floor` x intensity[c] (for float rounding where the closed
 * form is near 0). Only pixels `select` accepts (NULL: all) count. */
typedef int (*pixel_filter)(const view *v, int x, int y, const void *ctx);

typedef struct {
    int compared, failed;   /* pixels compared, channel values out of tolerance */
    double worst;           /* largest error over its tolerance */
    double worst_ref, worst_got, worst_tol;
    int worst_x, worst_y;
    double max_rel;         /* largest relative error where ref > 1% of the largest ref */
} comparison;

static comparison compare_pixels(const float *rgb, const view *v, int spp, ground_radiance f, const void *ctx,
                                 const double intensity[3], double abs_floor, pixel_filter select, const void *select_ctx)
{
    comparison r = {.worst = -1.0};
    double max_ref = 0.0;
    for (int pass = 0; pass < 2; pass++) /* the first pass finds the largest ref */
        for (int y = 0; y < v->height; y++)
            for (int x = 0; x < v->width; x++) {
                if (select && !select(v, x, y, select_ctx)) continue;
                double mean, sd;
                pixel_stats(v, x, y, f, ctx, &mean, &sd);
                if (pass == 0) {
                    for (int c = 0; c < 3; c++) max_ref = fmax(max_ref, mean * intensity[c]);
                    continue;
                }
                r.compared++;
                for (int c = 0; c < 3; c++) {
                    double ref = mean * intensity[c], got = pixel(rgb, v, x, y, c), err = fabs(got - ref);
                    double tol = 0.01 * ref + 5.0 * sd * intensity[c] / sqrt(spp) + abs_floor * intensity[c];
                    if (!(err <= tol)) r.failed++;
                    if (ref > 0.01 * max_ref) r.max_rel = fmax(r.max_rel, err / ref);
                    double score = tol > 0.0 ? err / tol : err > 0.0 ? INFINITY : 0.0;
                    if (!(score <= r.worst)) {
                        r.worst = score;
                        r.worst_ref = ref;
                        r.worst_got = got;
                        r.worst_tol = tol;
                        r.worst_x = x;
                        r.worst_y = y;
                    }
                }
            }
    return r;
}

static void print_comparison(const char *what, const comparison *r)
{
    printf("  %s: %d pixels, largest relative error %.4f; closest to tolerance (%.0f%% of it) at (%d,%d): "
           "%.6g rendered, %.6g analytic\n",
           what, r->compared, r->max_rel, 100.0 * r->worst, r->worst_x, r->worst_y, r->worst_got, r->worst_ref);
}

/* 1. A point light off the image centre (also catching flipped image axes)
 * over a Lambertian plane, coloured intensity, every pixel. */
static void test_point_light(void)
{
    const double albedo = 0.6, intensity[3] = {10.0, 6.0, 3.0};
    const int spp = 1024;
    view v = vertical_view(0, 0, 4, 1, 60, 32);
    lv_punctual_light light = point_light(0.4, -0.3, 1.0, intensity);
    quad q = ground();
    lvcl_material_desc m = lambertian((float)albedo);
    lvcl_scene scene;
    quad_scene(&q, 1, &m, 1, &light, 1, &scene);
    const char *name = "point light: every pixel of a Lambertian plane is (a/pi) I cos/d^2 within 1% + noise";
    float *rgb = render(name, &scene, 1, 2, &v, spp);
    if (!rgb) return;
    punctual_ground g = {&light, albedo};
    comparison r = compare_pixels(rgb, &v, spp, punctual_radiance, &g, intensity, 0.0, NULL, NULL);
    print_comparison("point light", &r);
    CHECK(name, r.failed == 0, "%d channel values off; worst at (%d,%d): %.6g rendered, %.6g analytic +- %.3g",
          r.failed, r.worst_x, r.worst_y, r.worst_got, r.worst_ref, r.worst_tol);
    free(rgb);
}

/* The pixel straight below a point light at `height`, seen through a
 * narrow view so its footprint is nearly a point. */
static double radiance_below(double height, double albedo, double intensity)
{
    const double i3[3] = {intensity, intensity, intensity};
    view v = vertical_view(0, 0, 4, 1, 4, 9);
    lv_punctual_light light = point_light(0, 0, height, i3);
    quad q = ground();
    lvcl_material_desc m = lambertian((float)albedo);
    lvcl_scene scene;
    quad_scene(&q, 1, &m, 1, &light, 1, &scene);
    float *rgb = render("inverse square", &scene, 2, 2, &v, 16);
    if (!rgb) return NAN;
    double l = pixel(rgb, &v, 4, 4, 0);
    free(rgb);
    return l;
}

static void test_inverse_square(void)
{
    const double albedo = 0.5, intensity = 8.0;
    double l1 = radiance_below(1.0, albedo, intensity), l2 = radiance_below(2.0, albedo, intensity);
    double expect1 = albedo / PI * intensity; /* d = 1, cos = 1 */
    printf("  inverse square: below the light %.5f at height 1 (analytic %.5f), %.5f at height 2, ratio %.4f\n", l1,
           expect1, l2, l1 / l2);
    CHECK("point light: radiance straight below is a I / (pi h^2) within 1%", fabs(l1 - expect1) < 0.01 * expect1,
          "%.5f rendered, %.5f analytic", l1, expect1);
    CHECK("point light: doubling the height quarters the radiance (within 1%)", fabs(l1 / l2 - 4.0) < 0.04,
          "%.5f at height 1, %.5f at height 2: ratio %.4f", l1, l2, l1 / l2);
}

/* Which part of a spot's cone a pixel sees: all of its sub-samples inside
 * the inner cone, all outside the outer cone (with a margin, so the
 * renderer's jitter cannot reach the falloff), or otherwise in between. */
enum { SPOT_INSIDE, SPOT_BETWEEN, SPOT_OUTSIDE };

static int spot_zone(const view *v, int x, int y, const lv_punctual_light *l)
{
    int inside = 1, outside = 1;
    double axis[3] = {l->direction[0], l->direction[1], l->direction[2]};
    for (int j = 0; j < SUB; j++)
        for (int i = 0; i < SUB; i++) {
            double p[3], d[3];
            if (!subsample_ground(v, x, y, i, j, p)) return SPOT_BETWEEN;
            for (int k = 0; k < 3; k++) d[k] = p[k] - l->position[k];
            normalize3(d);
            double c = dot3(axis, d);
            if (c <= l->cos_inner + 0.005) inside = 0;
            if (c >= l->cos_outer - 0.01) outside = 0;
        }
    return inside ? SPOT_INSIDE : outside ? SPOT_OUTSIDE : SPOT_BETWEEN;
}

typedef struct {
    const lv_punctual_light *light;
    int zone;
} zone_filter;

static int in_zone(const view *v, int x, int y, const void *ctx)
{
    const zone_filter *z = ctx;
    return spot_zone(v, x, y, z->light) == z->zone;
}

/* 2. A tilted spot light: its cones cut ellipses out of the plane; pixels
 * inside, between and outside the cones are checked separately. */
static void test_spot_light(void)
{
    const double albedo = 0.7, intensity[3] = {12.0, 12.0, 12.0};
    const int spp = 1024;
    view v = vertical_view(0, 0, 4, 1, 60, 64);
    lv_punctual_light light = point_light(0.2, 0.1, 1.5, intensity);
    double axis[3] = {0.2, -0.1, -1.0};
    normalize3(axis);
    light.type = LV_PUNCTUAL_SPOT;
    for (int k = 0; k < 3; k++) light.direction[k] = (float)axis[k];
    light.cos_inner = (float)cos(20.0 * PI / 180.0);
    light.cos_outer = (float)cos(40.0 * PI / 180.0);
    quad q = ground();
    lvcl_material_desc m = lambertian((float)albedo);
    lvcl_scene scene;
    quad_scene(&q, 1, &m, 1, &light, 1, &scene);
    float *rgb = render("spot light", &scene, 3, 2, &v, spp);
    if (!rgb) return;

    punctual_ground g = {&light, albedo};
    static const char *zone_names[3] = {"inside", "between", "outside"};
    static const char *check_names[3] = {
        "spot light: inside the inner cone the point-light formula holds within 1% + noise",
        "spot light: between the cones radiance follows the squared glTF falloff within 1% + noise",
        "spot light: outside the outer cone radiance is exactly 0"};
    for (int zone = 0; zone < 3; zone++) {
        zone_filter zf = {&light, zone};
        /* Near the outer cone the falloff is ~0 and a jittered sample may
         * graze it where no sub-sample does: allow 1e-6 per unit intensity
         * (peak ~0.1). Outside, the tolerance is 0: exactly black. */
        double abs_floor = zone == SPOT_OUTSIDE ? 0.0 : 1e-6;
        comparison r = compare_pixels(rgb, &v, spp, punctual_radiance, &g, intensity, abs_floor, in_zone, &zf);
        char what[64];
        snprintf(what, sizeof what, "spot light, %s", zone_names[zone]);
        print_comparison(what, &r);
        CHECK(check_names[zone], r.failed == 0 && r.compared >= 50,
              "%d channel values of %d pixels off; worst at (%d,%d): %.6g rendered, %.6g analytic +- %.3g", r.failed,
              r.compared, r.worst_x, r.worst_y, r.worst_got, r.worst_ref, r.worst_tol);
    }
    free(rgb);
}

/* The emitter of the area-light tests: a square of half-size `half` at
 * height `h` above the origin, facing down at the ground (material 1). */
static void ground_and_emitter(double half, double h, double albedo, double le, quad *quads, lvcl_scene *scene)
{
    quads[0] = ground();
    quads[1] = horizontal_quad(0, 0, h, half, 0, 1);
    lvcl_material_desc m[2] = {lambertian((float)albedo), emitter((float)le)};
    quad_scene(quads, 2, m, 2, NULL, 0, scene);
}

/* Mean over the image of the rendered radiance, of the closed form, and
 * the standard error of the rendered mean (from the pixel-to-pixel scatter
 * of the residuals: each pixel is an independent estimate). */
typedef struct {
    double rendered, analytic, std_error;
} image_means;

static image_means mean_against(const float *rgb, const view *v, ground_radiance f, const void *ctx)
{
    image_means m = {0};
    double sum_res2 = 0.0;
    int n = v->width * v->height;
    for (int y = 0; y < v->height; y++)
        for (int x = 0; x < v->width; x++) {
            double ref, sd;
            pixel_stats(v, x, y, f, ctx, &ref, &sd);
            double got = pixel(rgb, v, x, y, 0);
            m.rendered += got;
            m.analytic += ref;
            sum_res2 += (got - ref) * (got - ref);
        }
    m.rendered /= n;
    m.analytic /= n;
    m.std_error = sqrt(sum_res2 / n / n);
    return m;
}

/* 3. A small square emitter 1 m above the plane: the plane straight below
 * (seen from a camera between the two, which blocks nothing) has mean
 * radiance (a/pi) Le E. */
static void test_area_light(void)
{
    const double albedo = 0.5, le = 4.0, half = 0.5, h = 1.0;
    quad quads[2];
    lvcl_scene scene;
    ground_and_emitter(half, h, albedo, le, quads, &scene);
    view v = vertical_view(0, 0, 0.5, 1, 30, 16);
    const char *name = "area light: plane below is (a/pi) Le E(Lambert polygon) within 1%";
    float *rgb = render(name, &scene, 4, 2, &v, 512);
    if (!rgb) return;
    area_ground g = {&quads[1], albedo, le};
    image_means m = mean_against(rgb, &v, area_radiance, &g);
    double origin[3] = {0, 0, 0};
    printf("  area light: E/Le at the centre %.5f; mean %.5f rendered, %.5f analytic (standard error %.5f)\n",
           polygon_irradiance(quads[1].p, 4, origin), m.rendered, m.analytic, m.std_error);
    CHECK(name, fabs(m.rendered - m.analytic) < 0.01 * m.analytic, "mean %.5f rendered, %.5f analytic (%.2f%%)",
          m.rendered, m.analytic, 100.0 * (m.rendered / m.analytic - 1.0));
    free(rgb);
}

/* Largest and smallest channel value of the image. */
static void image_range(const float *rgb, const view *v, double *lo, double *hi)
{
    *lo = INFINITY;
    *hi = -INFINITY;
    for (size_t i = 0; i < (size_t)v->width * v->height * 3; i++) {
        *lo = fmin(*lo, rgb[i]);
        *hi = fmax(*hi, rgb[i]);
    }
}

/* The emitter seen directly (max depth 1), filling the whole view: Le
 * exactly from below (its front), 0 from above (its back). */
static void test_emitter_sides(void)
{
    const double le = 4.0;
    static const char *names[2] = {"area light: its front face shows Le exactly",
                                   "area light: its back face is black"};
    for (int from_front = 1; from_front >= 0; from_front--) {
        quad quads[2];
        lvcl_scene scene;
        ground_and_emitter(0.5, 1.0, 0.5, le, quads, &scene);
        /* 0.5 m from the emitter, a 60-degree view spans +-0.29 m: all emitter. */
        view v = vertical_view(0, 0, from_front ? 0.5 : 1.5, !from_front, 60, 16);
        const char *name = names[from_front ? 0 : 1];
        float *rgb = render(name, &scene, 5, 1, &v, 4);
        if (!rgb) continue;
        double lo, hi, want = from_front ? le : 0.0;
        image_range(rgb, &v, &lo, &hi);
        printf("  emitter seen from its %s: pixels in [%g, %g], expected %g\n", from_front ? "front" : "back", lo, hi,
               want);
        CHECK(name, fabs(lo - want) <= 1e-6 * le && fabs(hi - want) <= 1e-6 * le, "pixels in [%g, %g], expected %g",
              lo, hi, want);
        free(rgb);
    }
}

/* 4. Texture: an 8 x 8 texture of 2 x 2 blocks of 4 x 4 equal texels, on a
 * 2 m square under a point light. Bilinear filtering is constant where all
 * four texels it blends lie in one block; there the rendered radiance over
 * the closed form for albedo 1 is factor x srgb_to_linear(texel). */
#define TEX 8
#define BLOCK 4

static const uint8_t block_rgb[2][2][3] = {
    {{255, 128, 0}, {30, 200, 90}}, /* row 0: the top of the image (v = 0) */
    {{128, 128, 128}, {8, 60, 250}}, /* 8 lies on the linear segment of sRGB */
};

/* The block (row * 2 + column) whose texels bilinear lookup at (u, v)
 * blends, or -1 where it blends texels of two blocks or wraps around. */
static int texture_block(double u, double v)
{
    double x = u * TEX - 0.5, y = v * TEX - 0.5;
    int x0 = (int)floor(x), y0 = (int)floor(y);
    if (x0 < 0 || y0 < 0 || x0 + 1 >= TEX || y0 + 1 >= TEX) return -1;
    if (x0 / BLOCK != (x0 + 1) / BLOCK || y0 / BLOCK != (y0 + 1) / BLOCK) return -1;
    return (y0 / BLOCK) * 2 + x0 / BLOCK;
}

/* The block all of a pixel's footprint sees, or -1 (uv from the quad of
 * horizontal_quad(0, 0, 0, 1, ...): u = (x + 1) / 2, v = (1 - y) / 2). */
static int pixel_block(const view *v, int x, int y)
{
    int block = -2;
    for (int j = 0; j < SUB; j++)
        for (int i = 0; i < SUB; i++) {
            double p[3];
            if (!subsample_ground(v, x, y, i, j, p) || fabs(p[0]) >= 1.0 || fabs(p[1]) >= 1.0) return -1;
            int b = texture_block(0.5 * (p[0] + 1.0), 0.5 * (1.0 - p[1]));
            if (b < 0 || (block != -2 && b != block)) return -1;
            block = b;
        }
    return block;
}

static void test_texture(void)
{
    const double factor = 0.8, intensity[3] = {9.0, 9.0, 9.0};
    lvcl_texture_data tex = {TEX, TEX, must_alloc(TEX * TEX * 4)};
    for (int y = 0; y < TEX; y++)
        for (int x = 0; x < TEX; x++) {
            uint8_t *t = &tex.rgba[4 * (y * TEX + x)];
            memcpy(t, block_rgb[y / BLOCK][x / BLOCK], 3);
            t[3] = 255;
        }
    quad q = horizontal_quad(0, 0, 0, 1, 1, 0);
    lvcl_material_desc m = lambertian((float)factor);
    m.base_color_texture = 0;
    lv_punctual_light light = point_light(0.1, 0.2, 3.0, intensity);
    lvcl_scene scene;
    quad_scene(&q, 1, &m, 1, &light, 1, &scene);
    scene.textures = copy_of(&tex, sizeof tex);
    scene.texture_count = 1;
    view v = vertical_view(0, 0, 2.5, 1, 40, 32); /* sees +-0.91 m of the 2 m square */
    float *rgb = render("texture", &scene, 6, 2, &v, 64);
    if (!rgb) return;

    /* Per block and channel: sum of rendered / closed form at albedo 1. */
    double ratio[4][3] = {{0}};
    int count[4] = {0};
    punctual_ground g = {&light, 1.0};
    for (int y = 0; y < v.height; y++)
        for (int x = 0; x < v.width; x++) {
            int b = pixel_block(&v, x, y);
            if (b < 0) continue;
            double mean, sd;
            pixel_stats(&v, x, y, punctual_radiance, &g, &mean, &sd);
            for (int c = 0; c < 3; c++) ratio[b][c] += pixel(rgb, &v, x, y, c) / (mean * intensity[c]);
            count[b]++;
        }
    for (int b = 0; b < 4; b++) {
        const uint8_t *texel = block_rgb[b / 2][b % 2];
        char name[160];
        snprintf(name, sizeof name,
                 "texture: block at row %d column %d has albedo factor x srgb_to_linear(%d,%d,%d) within 1%%", b / 2,
                 b % 2, texel[0], texel[1], texel[2]);
        double got[3], want[3];
        int ok = count[b] >= 20;
        for (int c = 0; c < 3; c++) {
            got[c] = count[b] ? ratio[b][c] / count[b] : 0.0;
            want[c] = factor * srgb_to_linear(texel[c] / 255.0);
            ok &= fabs(got[c] - want[c]) <= 0.01 * want[c] + 1e-5;
        }
        printf("  texture block %d: %d pixels, albedo %.5f %.5f %.5f rendered, %.5f %.5f %.5f expected\n", b,
               count[b], got[0], got[1], got[2], want[0], want[1], want[2]);
        CHECK(name, ok, "%d pixels: albedo (%.5f, %.5f, %.5f) rendered, (%.5f, %.5f, %.5f) expected", count[b],
              got[0], got[1], got[2], want[0], want[1], want[2]);
    }
    free(rgb);
}

/* 5. A large emitter close over the plane, where BSDF sampling and light
 * sampling both matter under MIS: two seeds agree within noise, and both
 * match the closed form. */
static void test_seeds_agree(void)
{
    const double albedo = 0.5, le = 1.0;
    image_means m[2];
    for (int i = 0; i < 2; i++) {
        quad quads[2];
        lvcl_scene scene;
        ground_and_emitter(2.0, 0.5, albedo, le, quads, &scene);
        area_ground g = {&quads[1], albedo, le};
        view v = vertical_view(0, 0, 0.25, 1, 60, 16);
        float *rgb = render("large emitter", &scene, 100 + 17 * i, 2, &v, 256);
        if (!rgb) return;
        m[i] = mean_against(rgb, &v, area_radiance, &g);
        free(rgb);
    }
    double diff = m[0].rendered - m[1].rendered;
    double sigma = sqrt(m[0].std_error * m[0].std_error + m[1].std_error * m[1].std_error);
    printf("  large emitter: mean %.5f (seed 100), %.5f (seed 117), analytic %.5f; standard errors %.5f, %.5f\n",
           m[0].rendered, m[1].rendered, m[0].analytic, m[0].std_error, m[1].std_error);
    CHECK("large emitter: two seeds give the same mean within 4 standard errors", fabs(diff) < 4.0 * sigma,
          "%.5f and %.5f differ by %.5f, standard error of the difference %.5f", m[0].rendered, m[1].rendered, diff,
          sigma);
    int ok = 1;
    for (int i = 0; i < 2; i++) ok &= fabs(m[i].rendered - m[i].analytic) < 0.01 * m[i].analytic;
    CHECK("large emitter: both seeds match (a/pi) Le E within 1%", ok, "%.5f and %.5f rendered, %.5f analytic",
          m[0].rendered, m[1].rendered, m[0].analytic);
}

int main(void)
{
    lvcl_device_prepare_environment();
    test_point_light();
    test_inverse_square();
    test_spot_light();
    test_area_light();
    test_emitter_sides();
    test_texture();
    test_seeds_agree();
    CHECK_EXIT();
}
