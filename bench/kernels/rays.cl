/* Ray-throughput benchmark kernels, built into lvcl-bench only (bench/rays.c, workloads in bench/RAYS.md of the
 * shared notes): rays are generated into buffers by one set of kernels and
 * traced by another, so tracing can be timed on its own and the same rays
 * handed to another tracer.
 *
 * Buffer layouts (mirrored in bench/rays.h):
 *   ray: two float4 per ray, (origin.xyz, tmax) and (dir.xyz, 0); dir is unit.
 *   hit: one uint4 per ray, (as_uint(t), prim_id, leaf triangle, 0); on a
 *        miss prim_id and the leaf triangle are LV_NO_HIT and t is tmax.
 *        prim_id is the glTF-order index that checksums use; the leaf index
 *        lets the secondary-ray kernel find the triangle's vertices. */
/* The layers these kernels use, in kernels/lvcl.h's order. */
#include "../../kernels/util/geometry.h"
#include "../../kernels/util/rng.h"
#include "../../kernels/util/sampling.h"
#include "../../kernels/scene_buffers.h"
#include "rays_args.h"
#include "../../kernels/bvh/traverse.h"
#include "../../kernels/scene/camera.h"

inline lv_ray lv_rays_load(__global const float4 *rays, uint i)
{
    float4 a = rays[2 * i], b = rays[2 * i + 1];
    /* The workloads offset their origins and skip nothing, as another
     * tracer given the same rays would. */
    return lv_ray_make(a.xyz, b.xyz, a.w, LV_NO_HIT, LV_NO_HIT);
}

inline void lv_rays_store(__global float4 *rays, uint i, float3 origin, float3 dir, float tmax)
{
    rays[2 * i] = (float4)(origin, tmax);
    rays[2 * i + 1] = (float4)(dir, 0.0f);
}

/* One ray through the centre of every pixel, row 0 at the top. */
__kernel void lv_rays_primary(LV_KERNEL_PARAMS(LV_RAYS_PRIMARY_ARGS))
{
    uint i = get_global_id(0);
    if (i >= camera.width * camera.height) return;
    lv_ray r = lv_camera_ray(camera, i % camera.width, i / camera.width, (float2)(0.5f, 0.5f));
    lv_rays_store(rays, i, r.origin, r.dir, r.tmax);
}

inline void lv_rays_trace(const lv_scene *sc, __global const float4 *rays, uint i, int any_hit, __global uint4 *hits)
{
    lv_hit h = lv_trace(sc, lv_rays_load(rays, i), any_hit);
    uint prim = h.tri == LV_NO_HIT ? LV_NO_HIT : lv_triangle_record(sc, h.tri).prim_id;
    hits[i] = (uint4)(as_uint(h.t), prim, h.tri, 0u);
}

__kernel void lv_rays_trace_closest(LV_KERNEL_PARAMS(LV_RAYS_TRACE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= count) return;
    lv_rays_trace(&sc, rays, i, 0, hits);
}

__kernel void lv_rays_trace_any(LV_KERNEL_PARAMS(LV_RAYS_TRACE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= count) return;
    lv_rays_trace(&sc, rays, i, 1, hits);
}

/* From the primary hit of pixel hit_pixels[i]: a cosine-distributed diffuse
 * ray and a shadow ray to a point on an emissive triangle, both leaving from
 * p + offset * n with n the geometric normal facing the incoming ray. The
 * emissive triangles are the first `emissive_count` entries of the light
 * table (area lights come before punctual ones); one is chosen uniformly,
 * not by power, so that another tracer's harness need not know the
 * materials. Random numbers are keyed by (seed, pixel), as in the renderer. */
__kernel void lv_rays_secondary(LV_KERNEL_PARAMS(LV_RAYS_SECONDARY_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= count) return;
    uint pixel = hit_pixels[i];
    lv_ray r = lv_rays_load(primary, pixel);
    uint4 h = primary_hits[pixel];

    float3 v0, v1, v2;
    lv_tri_corners(&sc, h.z, &v0, &v1, &v2);
    float3 n = normalize(cross(v1 - v0, v2 - v0));
    if (dot(n, r.dir) > 0.0f) n = -n;
    float3 o = r.origin + as_float(h.x) * r.dir + offset * n;

    lv_rng rng = lv_rng_make(sc.info.seed, pixel, 0u);
    float3 d = lv_to_world(lv_frame_make(n), lv_sample_cosine_hemisphere(lv_rng_next2(&rng)));
    lv_rays_store(diffuse, i, o, d, LV_FAR);

    if (emissive_count == 0) return;
    uint pick = min((uint)(lv_rng_next(&rng) * (float)emissive_count), emissive_count - 1u);
    float3 l0, l1, l2;
    lv_tri_corners(&sc, sc.lights[pick].index, &l0, &l1, &l2);
    float2 b = lv_sample_triangle(lv_rng_next2(&rng));
    float3 target = (1.0f - b.x - b.y) * l0 + b.x * l1 + b.y * l2;
    float3 to = target - o;
    float dist = length(to);
    lv_rays_store(shadow, i, o, dist > 0.0f ? to / dist : n, 0.999f * dist);
}
