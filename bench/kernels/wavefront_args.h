/* The argument lists of the wavefront path tracer's kernels
 * (bench/kernels/wavefront.cl), in the host/kernel contract's form
 * (kernels/shared_types.h); bench/wavefront.c binds them by the same lists.
 *
 * A path's state is kept structure-of-arrays, one entry per path:
 *   ray_origin (origin.xyz, tmax), ray_dir (dir.xyz, as_float(skip)),
 *   ray_skip_inst, beta (beta.xyz, prev_pdf),
 *   radiance (radiance.xyz, as_float(prev_delta)), depth (depth,
 *   as_uint(eta_scale)), rng, pixel,
 *   chain_from (chain.from, chain.pdf), chain_dir (chain.dir,
 *   as_float(chain.scatters)).
 * A shadow ray is kept at its path's index: shadow_origin (origin.xyz,
 * as_float(tri)), shadow_dir (d.xyz, as_float(inst)), shadow_li (li, mis),
 * shadow_chain (light, see_through, chain_key, 0). */
#ifndef LV_BENCH_WAVEFRONT_ARGS_H
#define LV_BENCH_WAVEFRONT_ARGS_H

#include "../../kernels/shared_types.h"

/* One argument a line, by hand (the formatter would fold the lists). */
/* clang-format off */

#define LV_WF_PATH_ARGS(X, SEP, kernel)            \
    X(kernel, BUFFER, float4, ray_origin) SEP()    \
    X(kernel, BUFFER, float4, ray_dir) SEP()       \
    X(kernel, BUFFER, uint, ray_skip_inst) SEP()   \
    X(kernel, BUFFER, float4, beta) SEP()          \
    X(kernel, BUFFER, float4, radiance) SEP()      \
    X(kernel, BUFFER, uint2, depth) SEP()          \
    X(kernel, BUFFER, uint4, rng) SEP()            \
    X(kernel, BUFFER, uint, pixel) SEP()           \
    X(kernel, BUFFER, float4, chain_from) SEP()    \
    X(kernel, BUFFER, float4, chain_dir)

#define LV_WF_SHADOW_ARGS(X, SEP, kernel)          \
    X(kernel, BUFFER, float4, shadow_origin) SEP() \
    X(kernel, BUFFER, float4, shadow_dir) SEP()    \
    X(kernel, BUFFER, float4, shadow_li) SEP()     \
    X(kernel, BUFFER, uint4, shadow_chain)

/* A camera ray for each pixel of the list; queue[i] = i. */
#define LV_WF_GENERATE_ARGS(X, SEP)                \
    X(lv_wf_generate, SCENE, , scene) SEP()        \
    LV_PIXEL_ARGS(X, SEP, lv_wf_generate) SEP()    \
    LV_WF_PATH_ARGS(X, SEP, lv_wf_generate) SEP()  \
    X(lv_wf_generate, BUFFER, uint, queue)

/* The closest hit of the rays of the `count` paths in queue. */
#define LV_WF_INTERSECT_ARGS(X, SEP)                          \
    X(lv_wf_intersect, SCENE, , scene) SEP()                  \
    X(lv_wf_intersect, BUFFER, const uint, queue) SEP()       \
    X(lv_wf_intersect, VALUE, lv_u32, count) SEP()            \
    X(lv_wf_intersect, BUFFER, const float4, ray_origin) SEP() \
    X(lv_wf_intersect, BUFFER, const float4, ray_dir) SEP()   \
    X(lv_wf_intersect, BUFFER, const uint, ray_skip_inst) SEP() \
    X(lv_wf_intersect, BUFFER, float4, hit) SEP()             \
    X(lv_wf_intersect, BUFFER, uint, hit_inst)

/* One vertex of each queued path (lv_path_shade): the paths that go on
 * are appended to next_queue, those with a light sample to shadow_queue
 * (counters[0] and [1] count them). */
#define LV_WF_SHADE_ARGS(X, SEP)                          \
    X(lv_wf_shade, SCENE, , scene) SEP()                  \
    X(lv_wf_shade, BUFFER, const uint, queue) SEP()       \
    X(lv_wf_shade, VALUE, lv_u32, count) SEP()            \
    X(lv_wf_shade, VALUE, lv_u32, see_through) SEP()      \
    LV_WF_PATH_ARGS(X, SEP, lv_wf_shade) SEP()            \
    X(lv_wf_shade, BUFFER, const float4, hit) SEP()       \
    X(lv_wf_shade, BUFFER, const uint, hit_inst) SEP()    \
    LV_WF_SHADOW_ARGS(X, SEP, lv_wf_shade) SEP()          \
    X(lv_wf_shade, BUFFER, uint, next_queue) SEP()        \
    X(lv_wf_shade, BUFFER, uint, shadow_queue) SEP()      \
    X(lv_wf_shade, BUFFER, uint, counters)

/* The queued shadow rays: the light of each clear one joins its path's. */
#define LV_WF_SHADOW_PASS_ARGS(X, SEP)                    \
    X(lv_wf_shadow, SCENE, , scene) SEP()                 \
    X(lv_wf_shadow, BUFFER, const uint, shadow_queue) SEP() \
    X(lv_wf_shadow, VALUE, lv_u32, count) SEP()           \
    LV_WF_SHADOW_ARGS(X, SEP, lv_wf_shadow) SEP()         \
    X(lv_wf_shadow, BUFFER, float4, radiance)

/* Each finished path's radiance into its pixel's sums. */
#define LV_WF_FINISH_ARGS(X, SEP)                         \
    X(lv_wf_finish, VALUE, lv_u32, count) SEP()           \
    X(lv_wf_finish, BUFFER, const uint, pixel) SEP()      \
    X(lv_wf_finish, BUFFER, const float4, radiance) SEP() \
    X(lv_wf_finish, BUFFER, float4, sum) SEP()            \
    X(lv_wf_finish, BUFFER, float, sum_sq)

/* clang-format on */

LV_ARG_INDICES(LV_WF_GENERATE_ARGS, lv_wf_generate);
LV_ARG_INDICES(LV_WF_INTERSECT_ARGS, lv_wf_intersect);
LV_ARG_INDICES(LV_WF_SHADE_ARGS, lv_wf_shade);
LV_ARG_INDICES(LV_WF_SHADOW_PASS_ARGS, lv_wf_shadow);
LV_ARG_INDICES(LV_WF_FINISH_ARGS, lv_wf_finish);

#endif
