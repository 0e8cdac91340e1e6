/* The path tracer split into wavefront stages (generate, intersect, shade,
 * shadow, finish), each a kernel over a queue of paths, for lvcl-bench
 * wavefront (bench/wavefront.c) to time against the megakernel lv_pt_pass
 * (kernels/passes/pt.cl). Both run the same lv_path_shade on the same
 * random streams, so they make the same image; only where the work runs
 * differs. Paths are appended to queues with
 * atomics, in no fixed order; a path's numbers depend only on its own
 * state, so the image does not depend on that order. */
#include "../../kernels/lvcl.h"
#include "wavefront_args.h"

inline lv_path lv_wf_load(uint i, __global const float4 *ray_origin, __global const float4 *ray_dir,
                          __global const uint *ray_skip_inst, __global const float4 *beta,
                          __global const float4 *radiance, __global const uint2 *depth,
                          __global const float4 *chain_from, __global const float4 *chain_dir)
{
    lv_path p;
    float4 o = ray_origin[i], d = ray_dir[i], b = beta[i], l = radiance[i], cf = chain_from[i], cd = chain_dir[i];
    p.ray = lv_ray_make(o.xyz, d.xyz, o.w, ray_skip_inst[i], as_uint(d.w));
    p.beta = b.xyz;
    p.prev_pdf = b.w;
    p.radiance = l.xyz;
    p.prev_delta = as_int(l.w);
    p.depth = depth[i].x;
    p.eta_scale = as_float(depth[i].y);
    p.rough = 0u; /* only guided paths count them and keep a level */
    p.level = 0.0f;
    p.chain.from = cf.xyz;
    p.chain.pdf = cf.w;
    p.chain.dir = cd.xyz;
    p.chain.scatters = as_uint(cd.w);
    return p;
}

inline void lv_wf_store(uint i, const lv_path *p, __global float4 *ray_origin, __global float4 *ray_dir,
                        __global uint *ray_skip_inst, __global float4 *beta, __global float4 *radiance,
                        __global uint2 *depth, __global float4 *chain_from, __global float4 *chain_dir)
{
    ray_origin[i] = (float4)(p->ray.origin, p->ray.tmax);
    ray_dir[i] = (float4)(p->ray.dir, as_float(p->ray.skip));
    ray_skip_inst[i] = p->ray.skip_inst;
    beta[i] = (float4)(p->beta, p->prev_pdf);
    radiance[i] = (float4)(p->radiance, as_float(p->prev_delta));
    depth[i] = (uint2)(p->depth, as_uint(p->eta_scale));
    chain_from[i] = (float4)(p->chain.from, p->chain.pdf);
    chain_dir[i] = (float4)(p->chain.dir, as_float(p->chain.scatters));
}

inline uint4 lv_wf_rng_pack(lv_rng r)
{
    return (uint4)(r.key, r.counter, r.shift, r.sample);
}

inline lv_rng lv_wf_rng_unpack(uint4 v)
{
    lv_rng r;
    r.key = v.x;
    r.counter = v.y;
    r.shift = v.z;
    r.sample = v.w;
    return r;
}

__kernel void lv_wf_generate(LV_KERNEL_PARAMS(LV_WF_GENERATE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint i = get_global_id(0);
    if (i >= pixel_count) return;
    lv_camera_sample cs = lv_camera_sample_next(camera, sc.info.seed, pixel_list, first_pixel, first_sample, sum);
    lv_path p = lv_path_start(cs.ray);
    lv_wf_store(i, &p, ray_origin, ray_dir, ray_skip_inst, beta, radiance, depth, chain_from, chain_dir);
    rng[i] = lv_wf_rng_pack(cs.rng);
    pixel[i] = cs.pixel;
    queue[i] = i;
}

__kernel void lv_wf_intersect(LV_KERNEL_PARAMS(LV_WF_INTERSECT_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= count) return;
    uint i = queue[get_global_id(0)];
    float4 o = ray_origin[i], d = ray_dir[i];
    lv_hit h = lv_trace(&sc, lv_ray_make(o.xyz, d.xyz, o.w, ray_skip_inst[i], as_uint(d.w)), 0);
    hit[i] = (float4)(h.t, h.b1, h.b2, as_float(h.tri));
    hit_inst[i] = h.inst;
}

/* Appends i to a queue (where flag is set) with one global atomic per
 * work-group, as GPUs want (a global atomic per path serializes on one
 * counter there; untested on a GPU). On PoCL it measured the same as an
 * atomic per path. Every work-item of the kernel must call it, at the
 * same point: it has barriers. */
inline void lv_wf_append(int flag, uint i, __global uint *queue, volatile __global uint *counter,
                         volatile __local uint *local_count, volatile __local uint *local_base)
{
    if (get_local_id(0) == 0) *local_count = 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    uint slot = flag ? atomic_inc(local_count) : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    if (get_local_id(0) == 0) *local_base = atomic_add(counter, *local_count);
    barrier(CLK_LOCAL_MEM_FENCE);
    if (flag) queue[*local_base + slot] = i;
}

__kernel void lv_wf_shade(LV_KERNEL_PARAMS(LV_WF_SHADE_ARGS))
{
    __local uint local_count, local_base;
    LV_SCENE_OPEN(sc);
    /* No early return: every work-item reaches the appends' barriers. */
    int active = get_global_id(0) < count;
    uint i = active ? queue[get_global_id(0)] : 0u;
    int more = 0, has_shadow = 0;
    if (active) {
        lv_path p = lv_wf_load(i, ray_origin, ray_dir, ray_skip_inst, beta, radiance, depth, chain_from, chain_dir);
        lv_rng r = lv_wf_rng_unpack(rng[i]);
        float4 hv = hit[i];
        lv_hit h;
        h.t = hv.x;
        h.b1 = hv.y;
        h.b2 = hv.z;
        h.tri = as_uint(hv.w);
        h.inst = hit_inst[i];
        lv_shadow_ray shadow;
        more = lv_path_shade(&sc, 0, &p, h, &r, sc.info.max_depth, see_through, &shadow, &has_shadow);
        lv_wf_store(i, &p, ray_origin, ray_dir, ray_skip_inst, beta, radiance, depth, chain_from, chain_dir);
        rng[i] = lv_wf_rng_pack(r);
        if (has_shadow) {
            shadow_origin[i] = (float4)(shadow.origin, as_float(shadow.tri));
            shadow_dir[i] = (float4)(shadow.d, as_float(shadow.inst));
            shadow_li[i] = (float4)(shadow.li, shadow.mis);
            shadow_chain[i] = (uint4)(shadow.light, shadow.see_through, shadow.chain_key, 0u);
        }
    }
    lv_wf_append(has_shadow, i, shadow_queue, &counters[1], &local_count, &local_base);
    lv_wf_append(more, i, next_queue, &counters[0], &local_count, &local_base);
}

__kernel void lv_wf_shadow(LV_KERNEL_PARAMS(LV_WF_SHADOW_PASS_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= count) return;
    uint i = shadow_queue[get_global_id(0)];
    float4 o = shadow_origin[i], d = shadow_dir[i], li = shadow_li[i];
    uint4 chain = shadow_chain[i];
    lv_shadow_ray r;
    r.origin = o.xyz;
    r.d = d.xyz;
    r.tri = as_uint(o.w);
    r.inst = as_uint(d.w);
    r.li = li.xyz;
    r.mis = li.w;
    r.light = chain.x;
    r.see_through = chain.y;
    r.chain_key = chain.z;
    radiance[i].xyz += lv_shadow_ray_light(&sc, &r);
}

__kernel void lv_wf_finish(LV_KERNEL_PARAMS(LV_WF_FINISH_ARGS))
{
    uint i = get_global_id(0);
    if (i >= count) return;
    float3 l = radiance[i].xyz;
    lv_camera_sample_add(sum, sum_sq, pixel[i], lv_finite3(l) ? l : (float3)(0.0f));
}
