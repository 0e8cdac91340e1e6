#include "closed_forms.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- scenes from quads ---- */

void *must_alloc(size_t bytes)
{
    void *p = calloc(1, bytes ? bytes : 1);
    if (!p) {
        printf("FAIL light tests: out of memory\n");
        exit(1);
    }
    return p;
}

void *copy_of(const void *data, size_t bytes)
{
    void *p = must_alloc(bytes);
    if (bytes) memcpy(p, data, bytes);
    return p;
}

void quad_scene(const quad *quads, size_t quad_count, const lvcl_material_desc *materials, size_t material_count,
                const lv_punctual_light *lights, size_t light_count, lvcl_scene *s)
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

quad horizontal_quad(double x, double y, double z, double half, int facing_up, uint32_t material)
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

lvcl_material_desc lambertian(float albedo)
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

lvcl_material_desc emitter(float le)
{
    lvcl_material_desc m = lambertian(0.0f);
    m.emissive[0] = m.emissive[1] = m.emissive[2] = le;
    m.double_sided = 0;
    return m;
}

lv_punctual_light point_light(double x, double y, double z, const double intensity[3])
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

/* ---- the camera, as kernels/scene/camera.h and host/scene/camera.c make it ---- */

view vertical_view(double x, double y, double z, int looking_down, double yfov_degrees, int size)
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

int subsample_ground(const view *v, int x, int y, int i, int j, double p[3])
{
    double o[3], d[3];
    camera_ray(v, x + (i + 0.5) / SUB, y + (j + 0.5) / SUB, o, d);
    return hit_ground(o, d, p);
}

void pixel_stats(const view *v, int x, int y, ground_radiance f, const void *ctx, double *mean, double *sd)
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

float *render(const char *what, lvcl_scene *scene, unsigned seed, int max_depth, const view *v, int spp)
{
    lvcl_status st = {0};
    lvcl_session *s = NULL;
    lvcl_session_config cfg = {
        .device = getenv("LVCL_TEST_DEVICE"), .seed = seed, .max_depth = max_depth, .fast_math = 1};
    lvcl_render_result r = {0};
    lvcl_pass_settings ps = {.spp = spp};
    scene->camera = v->cam;
    if (lvcl_session_open(scene, &cfg, &s, &st) || lvcl_session_render_pt(s, v->width, v->height, &ps, &r, &st)) {
        printf("FAIL %s: render failed: %s\n", what, st.message);
        exit(1);
    }
    lvcl_session_close(s);
    return r.rgb;
}

float pixel(const float *rgb, const view *v, int x, int y, int c)
{
    return rgb[3 * ((size_t)y * v->width + x) + c];
}

/* ---- closed forms on the ground plane (normal +z) ---- */

/* The glTF spot cone as kernels/light/lights.h states it: smooth between the
 * outer and inner cosines, squared. */
static double spot_falloff(const lv_punctual_light *l, const double from_light[3])
{
    if (l->type != LV_PUNCTUAL_SPOT) return 1.0;
    double axis[3] = {l->direction[0], l->direction[1], l->direction[2]};
    double a = (dot3(axis, from_light) - l->cos_outer) / fmax(0.001, (double)l->cos_inner - l->cos_outer);
    a = fmin(1.0, fmax(0.0, a));
    return a * a;
}

double punctual_radiance(const void *ctx, const double p[3])
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
double polygon_irradiance(const float corners[][3], int n, const double p[3])
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

double area_radiance(const void *ctx, const double p[3])
{
    const area_ground *g = ctx;
    return g->albedo / PI * g->le * polygon_irradiance(g->light->p, 4, p);
}

quad ground(void)
{
    return horizontal_quad(0, 0, 0, 20, 1, 0);
}

comparison compare_pixels(const float *rgb, const view *v, int spp, ground_radiance f, const void *ctx,
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
                        r.worst = score, r.worst_ref = ref, r.worst_got = got, r.worst_tol = tol;
                        r.worst_x = x, r.worst_y = y;
                    }
                }
            }
    return r;
}

void print_comparison(const char *what, const comparison *r)
{
    printf("  %s: %d pixels, largest relative error %.4f; closest to tolerance (%.0f%% of it) at (%d,%d): "
           "%.6g rendered, %.6g analytic\n",
           what, r->compared, r->max_rel, 100.0 * r->worst, r->worst_x, r->worst_y, r->worst_got, r->worst_ref);
}
