/* The argument lists of the ray-throughput kernels (bench/kernels/rays.cl),
 * in the form of the host/kernel contract's (kernels/shared_types.h): each
 * kernel declares its parameters with LV_KERNEL_PARAMS(its list) and
 * bench/rays.c binds them by the same list. */
#ifndef LV_BENCH_RAYS_ARGS_H
#define LV_BENCH_RAYS_ARGS_H

#include "../../kernels/shared_types.h"

/* One argument a line, by hand (the formatter would fold the lists). */
/* clang-format off */

/* One ray through the centre of every pixel. */
#define LV_RAYS_PRIMARY_ARGS(X, SEP)                  \
    X(lv_rays_primary, VALUE, lv_camera, camera) SEP() \
    X(lv_rays_primary, BUFFER, float4, rays)

/* lv_rays_trace_closest and lv_rays_trace_any: `count` rays in, a hit
 * record each out. The two share the list, named after the first. */
#define LV_RAYS_TRACE_ARGS(X, SEP)                     \
    X(lv_rays_trace, SCENE, , scene) SEP()             \
    X(lv_rays_trace, BUFFER, const float4, rays) SEP() \
    X(lv_rays_trace, VALUE, lv_u32, count) SEP()       \
    X(lv_rays_trace, BUFFER, uint4, hits)

/* A diffuse and a shadow ray from each primary hit. */
#define LV_RAYS_SECONDARY_ARGS(X, SEP)                             \
    X(lv_rays_secondary, SCENE, , scene) SEP()                     \
    X(lv_rays_secondary, BUFFER, const float4, primary) SEP()      \
    X(lv_rays_secondary, BUFFER, const uint4, primary_hits) SEP()  \
    X(lv_rays_secondary, BUFFER, const uint, hit_pixels) SEP()     \
    X(lv_rays_secondary, VALUE, lv_u32, count) SEP()               \
    X(lv_rays_secondary, VALUE, float, offset) SEP()               \
    X(lv_rays_secondary, VALUE, lv_u32, emissive_count) SEP()      \
    X(lv_rays_secondary, BUFFER, float4, diffuse) SEP()            \
    X(lv_rays_secondary, BUFFER, float4, shadow)

/* clang-format on */

LV_ARG_INDICES(LV_RAYS_PRIMARY_ARGS, lv_rays_primary);
LV_ARG_INDICES(LV_RAYS_TRACE_ARGS, lv_rays_trace);
LV_ARG_INDICES(LV_RAYS_SECONDARY_ARGS, lv_rays_secondary);

#endif
