/* Support for the direct-lighting tests (tests/light/test_point_lights.c,
 * test_area_lights.c): scenes built in memory from quads, rendered by the
 * path tracer, and the closed forms the light sources give on a Lambertian
 * ground plane. The analytic side follows the camera of kernels/scene/camera.h
 * (ray through the pixel position, box filter jittered uniformly inside the
 * pixel), so each pixel is compared with the average of the closed form
 * over its footprint. */
#ifndef LVCL_TEST_CLOSED_FORMS_H
#define LVCL_TEST_CLOSED_FORMS_H

#include <math.h>

#include "../harness.h"

#define PI 3.14159265358979323846

/* ---- small vector helpers (double precision for the closed forms) ---- */

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void cross3(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static inline void normalize3(double v[3])
{
    double len = sqrt(dot3(v, v));
    for (int k = 0; k < 3; k++) v[k] /= len;
}

/* ---- scenes from quads ---- */

typedef struct {
    float p[4][3];  /* corners, counter-clockwise seen from the front face */
    float uv[4][2]; /* texture coordinates at the corners */
    uint32_t material;
} quad;

/* Zeroed memory, or the test program ends with a FAIL line. */
void *must_alloc(size_t bytes);
/* A must_alloc copy of `bytes` of data. */
void *copy_of(const void *data, size_t bytes);

/* A scene of quads (two triangles each, sharing corners 0 and 2) with the
 * given materials and punctual lights; the scene owns copies of everything. */
void quad_scene(const quad *quads, size_t quad_count, const lvcl_material_desc *materials, size_t material_count,
                const lv_punctual_light *lights, size_t light_count, lvcl_scene *s);

/* A horizontal square of half-size `half` centred on (x, y) at height z,
 * facing up (+z) or down; uv (0,0) at its (-x, +y) corner and (1,1) at its
 * (+x, -y) corner, so seen from above with +y up the texture is upright. */
quad horizontal_quad(double x, double y, double z, double half, int facing_up, uint32_t material);

/* Lambertian in lvcl's mapping (host/scene/materials.c): specular 0 selects the
 * pure diffuse BSDF instead of the plastic layer. */
lvcl_material_desc lambertian(float albedo);
/* A black, one-sided emitter of radiance le. */
lvcl_material_desc emitter(float le);

/* A point light of `intensity` (candela per channel) at (x, y, z). */
lv_punctual_light point_light(double x, double y, double z, const double intensity[3]);

/* The ground: a large Lambertian square facing up, material 0. */
quad ground(void);

/* ---- the camera, as kernels/scene/camera.h and host/scene/camera.c make it ---- */

typedef struct {
    lvcl_camera_desc cam;
    int width, height;
} view;

/* A square image looking straight down (-z) or up (+z) from (x, y, z),
 * with +y up in the image either way; right = up x back. */
view vertical_view(double x, double y, double z, int looking_down, double yfov_degrees, int size);

/* Sub-samples per pixel side for the closed forms' pixel averages. */
#define SUB 8

/* The ground point seen through sub-sample (i, j) of pixel (x, y). */
int subsample_ground(const view *v, int x, int y, int i, int j, double p[3]);

/* Radiance leaving ground point p toward the camera (Lambertian: any direction). */
typedef double (*ground_radiance)(const void *ctx, const double p[3]);

/* Mean and standard deviation of f over what pixel (x, y) sees. The pixel
 * filter jitters uniformly inside the pixel, so the mean is the value the
 * pixel converges to; when the estimator is otherwise exact (punctual
 * lights) sd / sqrt(spp) is the noise the jitter leaves. */
void pixel_stats(const view *v, int x, int y, ground_radiance f, const void *ctx, double *mean, double *sd);

/* ---- rendering ---- */

/* Renders `scene` (consumed) with the path tracer at `max_depth` through a
 * session; returns the w x h x 3 image (to free). A failure ends the test
 * program with a FAIL line naming `what`. */
float *render(const char *what, lvcl_scene *scene, unsigned seed, int max_depth, const view *v, int spp);

/* Channel c of pixel (x, y) of a rendered image. */
float pixel(const float *rgb, const view *v, int x, int y, int c);

/* ---- closed forms on the ground plane (normal +z) ---- */

typedef struct {
    const lv_punctual_light *light;
    double albedo;
} punctual_ground;

/* (a / pi) x falloff x cos(theta) / d^2 per unit intensity. */
double punctual_radiance(const void *ctx, const double p[3]);

/* Irradiance at p (normal +z) from polygon `corners` (n of them, in the
 * emitter's front-face order) of unit radiance, by Lambert's formula. */
double polygon_irradiance(const float corners[][3], int n, const double p[3]);

typedef struct {
    const quad *light;
    double albedo, le;
} area_ground;

/* (a / pi) Le E for the area light of `g`. */
double area_radiance(const void *ctx, const double p[3]);

/* ---- comparing images with closed forms ---- */

/* Pixel-by-pixel comparison with a closed form times intensity[c]. Each
 * channel may be off by 1% plus five standard deviations of the jitter
 * noise plus `abs_floor` x intensity[c] (for float rounding where the closed
 * form is near 0). Only pixels `select` accepts (NULL: all) count. */
typedef int (*pixel_filter)(const view *v, int x, int y, const void *ctx);

typedef struct {
    int compared, failed; /* pixels compared, channel values out of tolerance */
    double worst;         /* largest error over its tolerance */
    double worst_ref, worst_got, worst_tol;
    int worst_x, worst_y;
    double max_rel; /* largest relative error where ref > 1% of the largest ref */
} comparison;

comparison compare_pixels(const float *rgb, const view *v, int spp, ground_radiance f, const void *ctx,
                          const double intensity[3], double abs_floor, pixel_filter select, const void *select_ctx);

/* Prints a comparison's summary line. */
void print_comparison(const char *what, const comparison *r);

#endif
