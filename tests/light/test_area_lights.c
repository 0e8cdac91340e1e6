/* Area lights against closed forms: quads rendered by the path tracer at
 * max depth 2 (direct light only) or 1 (emitters seen directly):
 *   area light    the plane below has mean radiance (a / pi) Le E, E from
 *                 Lambert's polygon formula;
 *   sides         one-sided emission shows Le from the front, black behind;
 *   seeds         a large emitter (MIS matters) gives one mean for two seeds;
 *   unequal lamps two lamps of radiance 1:25 and 1:1000 (two materials, so
 *                 light samples pick them by odds that are not their power's
 *                 share: tests/light/test_light_table.c) give the sum of
 *                 their closed forms.
 * The closed forms and the scenes are in closed_forms.h. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "closed_forms.h"

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

/* 1. A small square emitter 1 m above the plane: the plane straight below
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
    static const char *names[2] = {"area light: its front face shows Le exactly", "area light: its back face is black"};
    for (int from_front = 1; from_front >= 0; from_front--) {
        quad quads[2];
        lvcl_scene scene;
        ground_and_emitter(0.5, 1.0, 0.5, le, quads, &scene);
        /* 0.5 m from the emitter, a 60-degree view spans +-0.29 m: all emitter. */
        view v = vertical_view(0, 0, from_front ? 0.5 : 1.5, !from_front, 60, 16);
        const char *name = names[from_front ? 0 : 1];
        float *rgb = render(name, &scene, 5, 1, &v, 4);
        double lo, hi, want = from_front ? le : 0.0;
        image_range(rgb, &v, &lo, &hi);
        printf("  emitter seen from its %s: pixels in [%g, %g], expected %g\n", from_front ? "front" : "back", lo, hi,
               want);
        CHECK(name, fabs(lo - want) <= 1e-6 * le && fabs(hi - want) <= 1e-6 * le, "pixels in [%g, %g], expected %g", lo,
              hi, want);
        free(rgb);
    }
}

/* 2. A large emitter close over the plane, where BSDF sampling and light
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

/* The ground lit by the two lamps of `g` together. */
static double two_lamps_radiance(const void *ctx, const double p[3])
{
    const area_ground *g = ctx;
    return area_radiance(&g[0], p) + area_radiance(&g[1], p);
}

/* 4. A dim lamp over the ground seen and a lamp `ratio` times brighter off
 * to the side: the mean is the sum of their closed forms within 1%. */
static void test_unequal_lamps(void)
{
    const double albedo = 0.5, ratios[] = {25, 1000};
    for (int i = 0; i < 2; i++) {
        const double le[2] = {1.0, ratios[i]};
        quad quads[3] = {ground(), horizontal_quad(0, 0, 1.0, 0.4, 0, 1), horizontal_quad(2.5, 0, 1.5, 0.1, 0, 2)};
        lvcl_material_desc m[3] = {lambertian((float)albedo), emitter((float)le[0]), emitter((float)le[1])};
        lvcl_scene scene;
        quad_scene(quads, 3, m, 3, NULL, 0, &scene);
        view v = vertical_view(0, 0, 0.5, 1, 40, 16);
        float *rgb = render("unequal lamps", &scene, 7, 2, &v, 512);
        area_ground g[2] = {{&quads[1], albedo, le[0]}, {&quads[2], albedo, le[1]}};
        image_means r = mean_against(rgb, &v, two_lamps_radiance, g);
        printf("  unequal lamps 1:%g: mean %.5f rendered, %.5f analytic (standard error %.5f)\n", ratios[i], r.rendered,
               r.analytic, r.std_error);
        CHECK("unequal lamps: the ground's mean is the sum of both lamps' closed forms within 1%",
              fabs(r.rendered - r.analytic) < 0.01 * r.analytic, "1:%g: %.5f rendered, %.5f analytic (%.2f%%)",
              ratios[i], r.rendered, r.analytic, 100.0 * (r.rendered / r.analytic - 1.0));
        free(rgb);
    }
}

int main(void)
{
    lvcl_device_prepare_environment();
    test_area_light();
    test_emitter_sides();
    test_seeds_agree();
    test_unequal_lamps();
    CHECK_EXIT();
}
