/* Point and spot lights against closed forms: quads rendered by the path
 * tracer at max depth 2 (direct light only), compared pixel by pixel with
 * what the light gives on a Lambertian plane:
 *   point light   L = (a / pi) I cos(theta) / d^2, and inverse-square;
 *   spot light    the same times the glTF cone falloff, squared;
 *   directional   (a / pi) E cos(theta), in pt and read from the light
 *                 volume (lv-all);
 *   texture       under a point light, albedo per texel block =
 *                 factor x srgb_to_linear(texel), and where texels of
 *                 different colours blend, their linear values blended.
 * The closed forms and the scenes are in closed_forms.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "closed_forms.h"

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

/* 3. Texture: an 8 x 8 texture of 2 x 2 blocks of 4 x 4 equal texels, on a
 * 2 m square under a point light. Bilinear filtering is constant where all
 * four texels it blends lie in one block; there the rendered radiance over
 * the closed form for albedo 1 is factor x srgb_to_linear(texel). */
#define TEX 8
#define BLOCK 4

static const uint8_t block_rgb[2][2][3] = {
    {{255, 128, 0}, {30, 200, 90}},  /* row 0: the top of the image (v = 0) */
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

/* The 2 m square Lambertian plane of albedo factor x texture tex (its
 * texels taken over), under light. */
static lvcl_scene textured_plane(const lvcl_texture_data *tex, double factor, const lv_punctual_light *light)
{
    quad q = horizontal_quad(0, 0, 0, 1, 1, 0);
    lvcl_material_desc m = lambertian((float)factor);
    m.base_color_texture = 0;
    lvcl_scene scene;
    quad_scene(&q, 1, &m, 1, light, 1, &scene);
    scene.textures = copy_of(tex, sizeof *tex);
    scene.texture_count = 1;
    return scene;
}

static double srgb_to_linear(double c)
{
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
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
    lv_punctual_light light = point_light(0.1, 0.2, 3.0, intensity);
    lvcl_scene scene = textured_plane(&tex, factor, &light);
    view v = vertical_view(0, 0, 2.5, 1, 40, 32); /* sees +-0.91 m of the 2 m square */
    float *rgb = render("texture", &scene, 6, 2, &v, 64);

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
        printf("  texture block %d: %d pixels, albedo %.5f %.5f %.5f rendered, %.5f %.5f %.5f expected\n", b, count[b],
               got[0], got[1], got[2], want[0], want[1], want[2]);
        CHECK(name, ok, "%d pixels: albedo (%.5f, %.5f, %.5f) rendered, (%.5f, %.5f, %.5f) expected", count[b], got[0],
              got[1], got[2], want[0], want[1], want[2]);
    }
    free(rgb);
}

/* 4. Texture filtering blends light: an 8 x 8 texture whose red is a
 * checker of texels 0 and 255, green stripes of 0 and 255 and blue 128,
 * under a point light. Every lookup blends texels of different colours, so
 * each pixel converges to factor x the bilinear blend of the texels' linear
 * values, averaged over what it sees, times the closed form. Blending the
 * sRGB-encoded values and decoding the blend (as lvcl did until 2026-12-07)
 * gave 0.50 of that for the red checker and 0.63 for the green stripes: a
 * 50:50 mix of 0 and 255 reads 0.21, not 0.5. */
typedef struct {
    punctual_ground g;
    const float *linear; /* TEX x TEX x 3 */
    int channel;
    int quadrant;      /* read as KHR_texture_transform's example: the lower left quadrant turned */
    double scale, at;  /* else the UVs times scale, plus at (scale 0: as they are) */
    unsigned sampling; /* LV_WRAP_* per axis, LV_TEXTURE_NEAREST */
} textured_ground;

/* Texel i of TEX wrapped as glTF's samplers do: repeat, clamp to the edge,
 * or mirrored repeat (period 2 TEX, the second half backwards). */
static int wrapped(int i, unsigned mode)
{
    if (mode == LV_WRAP_CLAMP) return i < 0 ? 0 : i >= TEX ? TEX - 1 : i;
    int period = mode == LV_WRAP_MIRROR ? 2 * TEX : TEX, k = ((i % period) + period) % period;
    return k < TEX ? k : period - 1 - k;
}

/* Channel c of the linear texels at (u, v): the bilinear blend of the four
 * nearest texel centres, or the texel holding (u, v) where `sampling` asks
 * for nearest filtering, wrapped as it says. */
static double texture_at(const float *linear, int c, double u, double v, unsigned sampling)
{
    unsigned wu = sampling & 3u, wv = sampling >> LV_WRAP_V_SHIFT & 3u;
    if (sampling & LV_TEXTURE_NEAREST)
        return linear[3 * (wrapped((int)floor(v * TEX), wv) * TEX + wrapped((int)floor(u * TEX), wu)) + c];
    double x = u * TEX - 0.5, y = v * TEX - 0.5, fx = floor(x), fy = floor(y), ax = x - fx, ay = y - fy;
    double t[2][2];
    for (int j = 0; j < 2; j++)
        for (int i = 0; i < 2; i++)
            t[j][i] = linear[3 * (wrapped((int)fy + j, wv) * TEX + wrapped((int)fx + i, wu)) + c];
    return (1 - ay) * ((1 - ax) * t[0][0] + ax * t[0][1]) + ay * ((1 - ax) * t[1][0] + ax * t[1][1]);
}

/* The texture coordinates t reads ground point p at. */
static void ground_uv(const textured_ground *t, const double p[3], double *u, double *v)
{
    *u = 0.5 * (p[0] + 1.0), *v = 0.5 * (1.0 - p[1]);
    if (t->quadrant) { /* the plane shows texels [0, 1/2] x [1/2, 1], turned a quarter clockwise */
        double w = *u;
        *u = 0.5 * *v;
        *v = 1.0 - 0.5 * w;
    } else if (t->scale != 0) {
        *u = t->scale * *u + t->at, *v = t->scale * *v + t->at;
    }
}

static double textured_radiance(const void *ctx, const double p[3])
{
    const textured_ground *t = ctx;
    double u, v;
    ground_uv(t, p, &u, &v);
    return punctual_radiance(&t->g, p) * texture_at(t->linear, t->channel, u, v, t->sampling);
}

/* Whether all that pixel (x, y) sees, and a sixteenth of a pixel round
 * it, lies in one texel: where nearest filtering steps from texel to texel
 * inside a pixel, the closed form's 8 x 8 sub-samples average the step too
 * coarsely to compare. */
static int one_texel(const view *v, int x, int y, const void *ctx)
{
    const textured_ground *t = ctx;
    int first = -1;
    for (int j = -1; j <= SUB; j++)
        for (int i = -1; i <= SUB; i++) {
            double p[3], u, w;
            if (!subsample_ground(v, x, y, i, j, p)) return 0;
            ground_uv(t, p, &u, &w);
            int texel = wrapped((int)floor(w * TEX), t->sampling >> LV_WRAP_V_SHIFT & 3u) * TEX +
                wrapped((int)floor(u * TEX), t->sampling & 3u);
            if (first >= 0 && texel != first) return 0;
            first = texel;
        }
    return 1;
}

/* A TEX x TEX texture and its texels' linear values: where `gradient`,
 * red growing along x and green along y; else a red checker of 0 and 255
 * and green stripes of 0 and 255 (every lookup blends); blue 128. */
static lvcl_texture_data make_texture(int gradient, float linear[TEX * TEX * 3])
{
    lvcl_texture_data tex = {TEX, TEX, must_alloc(TEX * TEX * 4)};
    for (int y = 0; y < TEX; y++)
        for (int x = 0; x < TEX; x++) {
            uint8_t *t = &tex.rgba[4 * (y * TEX + x)];
            t[0] = gradient ? (uint8_t)(20 + 33 * x) : (x + y) % 2 ? 255 : 0;
            t[1] = gradient ? (uint8_t)(20 + 33 * y) : x % 2 ? 255 : 0;
            t[2] = 128;
            t[3] = 255;
            for (int c = 0; c < 3; c++) linear[3 * (y * TEX + x) + c] = (float)srgb_to_linear(t[c] / 255.0);
        }
    return tex;
}

static void test_texture_blend(void)
{
    const double factor = 0.8, intensity[3] = {9.0, 9.0, 9.0};
    const int spp = 256;
    float linear[TEX * TEX * 3];
    lvcl_texture_data tex = make_texture(0, linear);
    lv_punctual_light light = point_light(0.1, 0.2, 3.0, intensity);
    lvcl_scene scene = textured_plane(&tex, factor, &light);
    view v = vertical_view(0, 0, 2.5, 1, 40, 32);
    float *rgb = render("texture blend", &scene, 7, 2, &v, spp);
    double got[3] = {0}, want[3] = {0};
    for (int c = 0; c < 3; c++) {
        textured_ground t = {{&light, factor}, linear, c, 0, 0, 0, 0};
        for (int y = 0; y < v.height; y++)
            for (int x = 0; x < v.width; x++) {
                double mean, sd;
                pixel_stats(&v, x, y, textured_radiance, &t, &mean, &sd);
                got[c] += pixel(rgb, &v, x, y, c);
                want[c] += mean * intensity[c];
            }
    }
    printf("  texture blend: image sums over the closed form's %.4f %.4f %.4f\n", got[0] / want[0], got[1] / want[1],
           got[2] / want[2]);
    int ok = 1;
    for (int c = 0; c < 3; c++) ok &= fabs(got[c] / want[c] - 1.0) < 0.01;
    CHECK("texture: bilinear filtering blends the texels' linear colours (image sum per channel within 1%)", ok,
          "image sums over the closed form: %.4f %.4f %.4f", got[0] / want[0], got[1] / want[1], got[2] / want[2]);
    free(rgb);
}

/* 6. How a texture is read, pixel by pixel and per channel against the
 * closed form read at the same texels, on a texture whose red grows along
 * x and green along y: KHR_texture_transform, its specification's example
 * (offset (0, 1), a quarter turn, scale 1/2: "the lower left quadrant of
 * the source image, rotated clockwise 90 degrees"); and glTF's samplers,
 * the UVs spread over -0.7 to 1.8 so that every wrap mode shows: clamp to
 * the edge with nearest filtering, and mirrored repeat along u with repeat
 * along v. A flipped rotation put 2,048 values off; the samplers read as
 * repeat and bilinear, 1,058 of 1,587 and 672 of 3,072. */
static void check_texture_reads(const char *name, int quadrant, double scale, double at, unsigned sampling)
{
    const double factor = 0.8, intensity[3] = {9.0, 9.0, 9.0};
    const int spp = 256;
    float linear[TEX * TEX * 3];
    lvcl_texture_data tex = make_texture(1, linear);
    lv_punctual_light light = point_light(0.1, 0.2, 3.0, intensity);
    lvcl_scene scene = textured_plane(&tex, factor, &light);
    const float r = 1.5707963267948966f,
                turned[6] = {0.5f * cosf(r), 0.5f * sinf(r), 0, -0.5f * sinf(r), 0.5f * cosf(r), 1},
                spread[6] = {(float)scale, 0, (float)at, 0, (float)scale, (float)at};
    scene.materials[0].has_uv_transform = 1;
    memcpy(scene.materials[0].uv_transform, quadrant ? turned : spread, sizeof turned);
    scene.materials[0].texture_sampling = sampling;
    view v = vertical_view(0, 0, 2.5, 1, 40, 32);
    float *rgb = render(name, &scene, 8, 2, &v, spp);
    int off = 0, compared = 0, worst_x = 0, worst_y = 0;
    double worst = 0;
    for (int c = 0; c < 3; c++) {
        textured_ground t = {{&light, factor}, linear, c, quadrant, quadrant ? 0 : scale, at, sampling};
        for (int y = 0; y < v.height; y++)
            for (int x = 0; x < v.width; x++) {
                if ((sampling & LV_TEXTURE_NEAREST) && !one_texel(&v, x, y, &t)) continue;
                compared++;
                double mean, sd;
                pixel_stats(&v, x, y, textured_radiance, &t, &mean, &sd);
                double want = mean * intensity[c], got = pixel(rgb, &v, x, y, c);
                double tol = 0.01 * want + 4.0 * sd * intensity[c] / sqrt(spp) + 1e-6;
                if (fabs(got - want) > tol) off++;
                if (fabs(got - want) / tol > worst) worst = fabs(got - want) / tol, worst_x = x, worst_y = y;
            }
    }
    printf("  %s: %d of %d channel values off; the worst at (%d,%d), %.2f of its tolerance\n", name, off, compared,
           worst_x, worst_y, worst);
    char check[240];
    snprintf(check, sizeof check, "%s: every pixel within 1%% + noise", name);
    CHECK(check, off == 0 && compared >= v.width * v.height,
          "%d of %d channel values off; the worst at (%d,%d), %.2f of its tolerance", off, compared, worst_x, worst_y,
          worst);
    free(rgb);
}

static void test_texture_reads(void)
{
    check_texture_reads("texture: KHR_texture_transform's example reads the lower left quadrant turned", 1, 0, 0, 0);
    check_texture_reads("texture: clamped to the edge, nearest filtering", 0, 2.5, -0.7,
                        LV_WRAP_CLAMP | LV_WRAP_CLAMP << LV_WRAP_V_SHIFT | LV_TEXTURE_NEAREST);
    check_texture_reads("texture: mirrored repeat along u, repeat along v", 0, 2.5, -0.7,
                        LV_WRAP_MIRROR | LV_WRAP_REPEAT << LV_WRAP_V_SHIFT);
}

/* 5. A directional light (a sun, glTF's "directional"): on a Lambertian
 * plane every point gets the same irradiance, E cos(theta), so every pixel
 * is (a / pi) E cos(theta), with no noise (the light sample is exact). And
 * read back from the light volume (lv-all: the sun's own light from its
 * particles, which leave a disc as wide as the scene's sphere): the same
 * mean, within the volume's noise, whatever the disc's size, which the
 * particles' weights must undo. */
static double sun_cos;

static double sun_radiance(const void *ctx, const double p[3])
{
    (void)p;
    return *(const double *)ctx / PI * sun_cos;
}

/* The plane of half-size `half` under a sun, and where pane_z > 0 a thin
 * glass pane as wide over it at that height. */
static lvcl_scene sun_scene(double albedo, const double irradiance[3], const double travel[3], double half,
                            double pane_z)
{
    lv_punctual_light light = point_light(0, 0, 0, irradiance);
    light.type = LV_PUNCTUAL_DIRECTIONAL;
    for (int k = 0; k < 3; k++) light.direction[k] = (float)travel[k];
    quad q[2] = {horizontal_quad(0, 0, 0, half, 1, 0), horizontal_quad(0, 0, pane_z, half, 0, 1)};
    lvcl_material_desc m[2] = {lambertian((float)albedo), lambertian(1.0f)};
    m[1].transmission = 1.0f; /* no volume: a thin pane */
    lvcl_scene scene;
    quad_scene(q, pane_z > 0 ? 2 : 1, m, 2, &light, 1, &scene);
    return scene;
}

static void test_directional_light(void)
{
    double albedo = 0.6, irradiance[3] = {3.0, 2.0, 1.0}, travel[3] = {0.3, -0.2, -1.0};
    normalize3(travel);
    sun_cos = -travel[2];
    view v = vertical_view(0, 0, 3, 1, 40, 32);
    lvcl_scene scene = sun_scene(albedo, irradiance, travel, 5.0, 0);
    const char *name = "directional light: every pixel of a Lambertian plane is (a/pi) E cos(theta)";
    float *rgb = render(name, &scene, 4, 2, &v, 16);
    comparison r = compare_pixels(rgb, &v, 16, sun_radiance, &albedo, irradiance, 0.0, NULL, NULL);
    print_comparison("directional light", &r);
    CHECK(name, r.failed == 0 && r.compared == v.width * v.height,
          "%d channel values off; worst at (%d,%d): %.6g rendered, %.6g analytic +- %.3g", r.failed, r.worst_x,
          r.worst_y, r.worst_got, r.worst_ref, r.worst_tol);
    free(rgb);

    /* lv-all on planes of two sizes (the disc's area grows with them). */
    for (int big = 0; big < 2; big++) {
        lvcl_scene s = sun_scene(albedo, irradiance, travel, big ? 20.0 : 2.0, 0);
        s.camera = v.cam;
        lvcl_render_request req = harness_request(LVCL_MODE_LV_ALL, v.width, 16, 16, 400000);
        lvcl_session_config cfg = {.seed = 5, .max_depth = 2, .fast_math = 1};
        lvcl_render_result out = {0};
        lvcl_status st = {0};
        char what[160];
        snprintf(what, sizeof what, "directional light, lv-all, plane %g m wide: mean within 3%% of (a/pi) E cos",
                 big ? 40.0 : 4.0);
        if (harness_render_with(&s, &cfg, &req, &out, &st)) {
            CHECK(what, 0, "render: %s", st.message);
            continue;
        }
        double mean[3] = {0}, worst = 0;
        for (int i = 0; i < v.width * v.height; i++)
            for (int c = 0; c < 3; c++) mean[c] += out.rgb[3 * i + c] / (v.width * v.height);
        for (int c = 0; c < 3; c++) worst = fmax(worst, fabs(mean[c] / (albedo / PI * sun_cos * irradiance[c]) - 1));
        printf("  directional light, lv-all, plane %g m: mean over the closed form off by %.4f\n", big ? 40.0 : 4.0,
               worst);
        CHECK(what, worst < 0.03, "off by %.4f", worst);
        free(out.rgb);
    }
}

/* 7. A sun through a window pane (thin glass over the plane, above the
 * camera): no path can meet a sun, so only a light sample that goes on
 * through the pane finds it. With paths of three segments the plane gets
 * the sun's light times the pane's transmittance 1 - 2R / (1 + R) (R the
 * Fresnel reflectance at the sun's angle), in pt and in lv, whose particle
 * trace then leaves that light to the light samples; without the sample
 * going on, pt's plane was black. */
static double fresnel_dielectric(double cos_i, double eta)
{
    double sin_t2 = (1 - cos_i * cos_i) / (eta * eta), cos_t = sqrt(1 - sin_t2);
    double rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t), rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5 * (rs * rs + rp * rp);
}

static void test_sun_through_pane(void)
{
    double albedo = 0.6, irradiance[3] = {3.0, 2.0, 1.0}, travel[3] = {0.3, -0.2, -1.0};
    normalize3(travel);
    sun_cos = -travel[2];
    double r = fresnel_dielectric(sun_cos, 1.5), transmit = 1 - 2 * r / (1 + r), want = albedo * transmit;
    view v = vertical_view(0, 0, 2.5, 1, 40, 32);
    for (int lv = 0; lv < 2; lv++) {
        lvcl_scene s = sun_scene(albedo, irradiance, travel, 6.0, 3.0);
        s.camera = v.cam;
        lvcl_render_request req = harness_request(lv ? LVCL_MODE_LV : LVCL_MODE_PT, v.width, 256, 16, 200000);
        req.see_through = 1;
        lvcl_session_config cfg = {.seed = 9, .max_depth = 3, .fast_math = 1};
        lvcl_render_result out = {0};
        lvcl_status st = {0};
        char what[200];
        snprintf(what, sizeof what,
                 "sun through a pane, %s: the plane's mean within 1%% of (a/pi) E cos(theta) (1 - 2R/(1+R))",
                 lv ? "lv" : "pt");
        if (harness_render_with(&s, &cfg, &req, &out, &st)) {
            CHECK(what, 0, "render: %s", st.message);
            continue;
        }
        double worst = 0;
        for (int c = 0; c < 3; c++) {
            double mean = 0;
            for (int i = 0; i < v.width * v.height; i++) mean += out.rgb[3 * i + c] / (v.width * v.height);
            worst = fmax(worst, fabs(mean / (want / PI * sun_cos * irradiance[c]) - 1));
        }
        printf("  sun through a pane (transmittance %.4f), %s: mean over the closed form off by %.4f\n", transmit,
               lv ? "lv" : "pt", worst);
        CHECK(what, worst < 0.01, "off by %.4f", worst);
        free(out.rgb);
    }
}

int main(void)
{
    lvcl_device_prepare_environment();
    test_point_light();
    test_inverse_square();
    test_spot_light();
    test_texture();
    test_texture_blend();
    test_texture_reads();
    test_directional_light();
    test_sun_through_pane();
    CHECK_EXIT();
}
