/* The argument lists of the test kernels (tests/kernels/unit_tests.cl), in
 * the form of the host/kernel contract's (kernels/shared_types.h): each
 * kernel declares its parameters with LV_KERNEL_PARAMS(its list), and the
 * tests bind them by the same list (tests/harness.h, or an
 * LVCL_DEFINE_BINDER of their own), every index from LV_ARG. */
#ifndef LV_TEST_ARGS_H
#define LV_TEST_ARGS_H

#include "../../kernels/shared_types.h"

/* One argument a line, by hand (the formatter would fold the lists). */
/* clang-format off */

/* Histogram of uniform directions over the 2 n^2 bins of the direction map. */
#define T_DIRECTION_HISTOGRAM_ARGS(X, SEP)              \
    X(t_direction_histogram, VALUE, lv_u32, n) SEP()        \
    X(t_direction_histogram, VALUE, lv_u32, per_item) SEP() \
    X(t_direction_histogram, BUFFER, uint, counts)

/* Directions drawn inside each bin mapped back to it; counts the misses. */
#define T_DIRECTION_ROUNDTRIP_ARGS(X, SEP)              \
    X(t_direction_roundtrip, VALUE, lv_u32, n) SEP()        \
    X(t_direction_roundtrip, VALUE, lv_u32, per_item) SEP() \
    X(t_direction_roundtrip, BUFFER, uint, misses)

/* Monte Carlo moments of `count` (BSDF config, viewing direction) pairs. */
#define T_BSDF_MOMENTS_ARGS(X, SEP)                                             \
    X(t_bsdf_moments, BUFFER, const float, config) SEP() /* 8 floats per BSDF */ \
    X(t_bsdf_moments, VALUE, lv_u32, count) SEP()                               \
    X(t_bsdf_moments, BUFFER, const float4, wos) SEP()                          \
    X(t_bsdf_moments, VALUE, lv_u32, n_wo) SEP()                                \
    X(t_bsdf_moments, VALUE, lv_u32, samples) SEP()                             \
    X(t_bsdf_moments, BUFFER, float, out)

/* What the ray kernels start with: the scene, then `count` rays of 8
 * floats (origin xyz, tmax, direction xyz, unused). */
#define T_RAYS_IN_ARGS(X, SEP, kernel)        \
    X(kernel, SCENE, , scene) SEP()           \
    X(kernel, BUFFER, const float, rays) SEP() \
    X(kernel, VALUE, lv_u32, count)

/* t_trace, t_surface and t_trace_brute_force: the rays, then 4 result
 * floats per ray. The three share the list, named after t_trace. */
#define T_TRACE_ARGS(X, SEP)               \
    T_RAYS_IN_ARGS(X, SEP, t_trace) SEP()  \
    X(t_trace, BUFFER, float, results)

/* t_offset_rays: the rays, a re-shoot record per ray, 4 result floats per ray. */
#define T_OFFSET_RAYS_ARGS(X, SEP)                        \
    T_RAYS_IN_ARGS(X, SEP, t_offset_rays) SEP()           \
    X(t_offset_rays, BUFFER, const float4, reshoot) SEP() \
    X(t_offset_rays, BUFFER, float, results)

/* The radiance the kernels read from every bin of one stored cell. */
#define T_BIN_RADIANCE_ARGS(X, SEP)              \
    X(t_bin_radiance, VOLUME, , volume) SEP()    \
    X(t_bin_radiance, VALUE, lv_u32, slot) SEP() \
    X(t_bin_radiance, BUFFER, float4, radiance)

/* The bin table of n x n bins per hemisphere (lv_fill_bin_table). */
#define T_BIN_TABLE_ARGS(X, SEP)              \
    X(t_bin_table, VALUE, lv_u32, n) SEP()        \
    X(t_bin_table, BUFFER, float, table)

/* Per pair of normals (shading xyz, geometric xyz; 8 floats): the sum over
 * the bins of their mean cosine times their solid angle, from the table,
 * from the bins' central directions, and by dense quadrature. */
#define T_BIN_COSINE_ARGS(X, SEP)                      \
    X(t_bin_cosine, VALUE, lv_u32, n) SEP()                \
    X(t_bin_cosine, BUFFER, const float, table) SEP()      \
    X(t_bin_cosine, BUFFER, const float4, normals) SEP()   \
    X(t_bin_cosine, VALUE, lv_u32, count) SEP()            \
    X(t_bin_cosine, BUFFER, float4, sums)

/* The guide of one cell (volume/guide.h) over the bins' luminance (padded
 * by LV_BIN_GROUP) for the normals (shading, geometric): per work-item,
 * per_item uniform directions' pdf times 4 pi (its mean is the pdf's
 * integral), per_item guide samples counted per bin, and how many samples
 * came back with a density other than lv_guide_pdf's, or none. */
#define T_GUIDE_SAMPLING_ARGS(X, SEP)                          \
    X(t_guide_sampling, VALUE, lv_u32, n) SEP()                \
    X(t_guide_sampling, BUFFER, const float, table) SEP()      \
    X(t_guide_sampling, BUFFER, const float, luminance) SEP()  \
    X(t_guide_sampling, BUFFER, const float4, normals) SEP()   \
    X(t_guide_sampling, VALUE, lv_u32, per_item) SEP()         \
    X(t_guide_sampling, BUFFER, uint, counts) SEP()            \
    X(t_guide_sampling, BUFFER, float4, results)

/* Directions toward candidate lights (kernels/light/light_directions.h):
 * `count` triangles (three corners each, the first's w the front sign)
 * with `weights`, seen from `point`. Per work-item, over per_item uniform
 * directions: the sum and the sum of squares of their density times 4 pi,
 * and how many have a density; over per_item samples: the sum of 1 / pdf,
 * how many came back with a density other than lv_light_directions_pdf's,
 * how many failed, and the sum of 1 / pdf^2. */
#define T_LIGHT_DIRECTIONS_ARGS(X, SEP)                          \
    X(t_light_directions, BUFFER, const float4, corners) SEP()   \
    X(t_light_directions, BUFFER, const float, weights) SEP()    \
    X(t_light_directions, VALUE, lv_u32, count) SEP()            \
    X(t_light_directions, BUFFER, const float4, point) SEP()     \
    X(t_light_directions, VALUE, lv_u32, per_item) SEP()         \
    X(t_light_directions, BUFFER, float4, results)

/* The first `dims` numbers of the camera streams (pixel, sample) for
 * `pixels` pixels and `samples` samples each, pixel-major. */
#define T_CAMERA_STREAMS_ARGS(X, SEP)                \
    X(t_camera_streams, VALUE, lv_u32, seed) SEP()       \
    X(t_camera_streams, VALUE, lv_u32, samples) SEP()    \
    X(t_camera_streams, VALUE, lv_u32, dims) SEP()       \
    X(t_camera_streams, BUFFER, float, out)

/* Per slot and axis: the gather's stored axis sum (then lv_axis_of of the
 * axis's normal), and the sum computed afresh (then lv_axis_of of a normal
 * tilted from it), a float4 each. */
#define T_AXIS_SUMS_ARGS(X, SEP)                                \
    X(t_axis_sums, VOLUME, , volume) SEP()                      \
    X(t_axis_sums, BUFFER, const float, bin_table) SEP()        \
    X(t_axis_sums, BUFFER, const float, fine_bin_table) SEP()   \
    X(t_axis_sums, BUFFER, const float, axis_sums) SEP()        \
    X(t_axis_sums, BUFFER, float4, out)

/* One work-item tallies segments (per segment two float4: origin and
 * length in metres, unit direction and weight) one after another, each
 * as concentrated light if `concentrated`, and writes per segment and
 * axis the luminance of lv_axis_sum of the slot at the segment's middle
 * after it, then the same of the bins' sum with mean cosines alone. */
#define T_AXIS_CORRECTION_ARGS(X, SEP)                            \
    X(t_axis_correction, VOLUME, , volume) SEP()                  \
    X(t_axis_correction, BUFFER, const float, bin_table) SEP()    \
    X(t_axis_correction, BUFFER, const float, fine_bin_table) SEP() \
    X(t_axis_correction, BUFFER, const float4, segments) SEP()    \
    X(t_axis_correction, VALUE, lv_u32, count) SEP()              \
    X(t_axis_correction, VALUE, lv_u32, concentrated) SEP()       \
    X(t_axis_correction, BUFFER, float, out)

/* Per point (xyz), the largest offset along each axis of `draws` jittered
 * lookups round it (lv_jitter_lookup, the normal +y), in cells. */
#define T_JITTER_LOOKUP_ARGS(X, SEP)                        \
    X(t_jitter_lookup, VOLUME, , volume) SEP()              \
    X(t_jitter_lookup, BUFFER, const float4, points) SEP()  \
    X(t_jitter_lookup, VALUE, lv_u32, count) SEP()          \
    X(t_jitter_lookup, VALUE, lv_u32, draws) SEP()          \
    X(t_jitter_lookup, BUFFER, float4, out)

/* clang-format on */

LV_ARG_INDICES(T_AXIS_SUMS_ARGS, t_axis_sums);
LV_ARG_INDICES(T_AXIS_CORRECTION_ARGS, t_axis_correction);
LV_ARG_INDICES(T_JITTER_LOOKUP_ARGS, t_jitter_lookup);
LV_ARG_INDICES(T_DIRECTION_HISTOGRAM_ARGS, t_direction_histogram);
LV_ARG_INDICES(T_DIRECTION_ROUNDTRIP_ARGS, t_direction_roundtrip);
LV_ARG_INDICES(T_BSDF_MOMENTS_ARGS, t_bsdf_moments);
LV_ARG_INDICES(T_TRACE_ARGS, t_trace);
LV_ARG_INDICES(T_OFFSET_RAYS_ARGS, t_offset_rays);
LV_ARG_INDICES(T_BIN_RADIANCE_ARGS, t_bin_radiance);
LV_ARG_INDICES(T_BIN_TABLE_ARGS, t_bin_table);
LV_ARG_INDICES(T_BIN_COSINE_ARGS, t_bin_cosine);
LV_ARG_INDICES(T_GUIDE_SAMPLING_ARGS, t_guide_sampling);
LV_ARG_INDICES(T_LIGHT_DIRECTIONS_ARGS, t_light_directions);
LV_ARG_INDICES(T_CAMERA_STREAMS_ARGS, t_camera_streams);

/* lv_cos_sin of each angle in phis, (cos, sin) per angle. */
#define T_COS_SIN_ARGS(X, SEP) X(t_cos_sin, BUFFER, const float, phis) SEP() X(t_cos_sin, BUFFER, float, out)
LV_ARG_INDICES(T_COS_SIN_ARGS, t_cos_sin);

/* lv_sample_vmf: per_item directions for each case (mu.xyz, kappa), each
 * with lv_vmf_pdf there (w.xyz, pdf), case by case. */
#define T_VMF_ARGS(X, SEP)                       \
    X(t_vmf, BUFFER, const float4, cases) SEP()  \
    X(t_vmf, VALUE, lv_u32, per_item) SEP()      \
    X(t_vmf, BUFFER, float4, out)
LV_ARG_INDICES(T_VMF_ARGS, t_vmf);

#endif
