/* The particle trace (paper section 4.1): particles leave the lights with
 * equal shares of the emitted power, scatter by the surfaces' BSDFs and end
 * by Russian roulette; every straight segment adds power x track length to
 * the cells it crosses, in the bin of its direction (eq. 5). Tallies are
 * integer atomics, so the result does not depend on the order of work. */
#include "light_volume.h"
#include "path.h"

/* Different from every pixel stream of the camera passes. */
#define LV_PARTICLE_STREAM 0x9e3779b9u

/* Importance carried across a surface whose shading normal is not its
 * geometric one picks up |wo.ns| |wi.ng| / (|wo.ng| |wi.ns|) (Veach 1997,
 * section 5.3): without it particles would not carry the power that the
 * shading-normal BSDF of radiance transport implies. 1 without normals. */
inline float lv_shading_normal_adjoint(const lv_surface *s, float3 wo, float3 wi)
{
    if (all(s->ns == s->ng)) return 1.0f;
    float num = fabs(dot(wo, s->ns)) * fabs(dot(wi, s->ng));
    float den = fabs(dot(wo, s->ng)) * fabs(dot(wi, s->ns));
    return den > 0.0f ? num / den : 0.0f;
}

__kernel void lv_particle_trace(LV_KERNEL_PARAMS(LV_PARTICLE_TRACE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint id = get_global_id(0);
    if (id >= count) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid); /* its lit volumes are not known yet: the trace does not read them */
    lv_rng rng = lv_rng_make(sc.info.seed ^ LV_PARTICLE_STREAM, first + id, 0u);

    lv_emission_sample es;
    float2 ul = lv_rng_next2(&rng), ud = lv_rng_next2(&rng);
    if (!lv_sample_emission(&sc, ul, ud, lv_rng_next(&rng), &es)) return;
    float3 throughput = es.weight;
    uint segments = 0, visibility_rays = 0;
    lv_ray r = lv_ray_make(es.origin, es.dir, LV_FAR, es.instance, es.triangle);
    for (uint depth = 1; depth <= sc.info.max_depth; depth++) {
        lv_hit h = lv_trace(&sc, r, 0);
        segments++;
        lv_surface s;
        float3 sigma = (float3)(0.0f);
        __global const lv_material *m = 0;
        if (h.tri != LV_NO_HIT) {
            s = lv_surface_at(&sc, r, h);
            m = &sc.materials[s.material];
#ifdef LV_FEATURE_GLASS
            if (m->bsdf == LV_BSDF_GLASS && !s.front) sigma = LV_F3(m->attenuation);
#endif
        }
        /* Emitted light (the first segment) is left to shadow rays in lv mode. */
        int tallied = depth > 1 || store_emitted;
        if (tallied)
            lv_tally_segment(&grid, r.origin, r.dir, 0.0f, h.t, lv_direction_bin(r.dir, grid.g.dirs),
                             throughput * inv_total_particles, sigma);
        if (tallied && grid.g.subcells && h.tri != LV_NO_HIT) {
            /* Just off the hit on the side the particle came from, its light
             * reached: off along the normal, by more than a lit point's
             * rounding (1/512 subcell per axis), so even a grazing hit's
             * point stays on that side. */
            float3 toward = dot(r.dir, s.ng) < 0.0f ? s.ng : -s.ng;
            lv_offer_lit_point(&grid, s.p + toward * (0.02f * grid.g.cell_size / (float)grid.g.subcells), &rng);
            if (lv_rng_next(&rng) < grid.g.visibility_rate)
                visibility_rays += lv_sample_subcell_visibility(&grid, &sc, s.p, r.origin, &rng);
        }
        if (h.tri == LV_NO_HIT || depth == sc.info.max_depth) break;
        throughput *= exp(-sigma * h.t);

        lv_frame f;
        if (!lv_shading_frame(&sc, &s, r.dir, &f)) break;
        lv_bsdf b = lv_surface_bsdf(&sc, &s);
        float3 wo = lv_to_local(f, -r.dir);
        float3 ng_out = dot(r.dir, s.ng) < 0.0f ? s.ng : -s.ng;
        lv_bsdf_sample bs;
        float3 u = (float3)(lv_rng_next2(&rng), lv_rng_next(&rng));
        if (!lv_bsdf_sample_dir(&b, wo, u, LV_IMPORTANCE, &bs)) break;
        float3 wi = lv_to_world(f, bs.wi);
        int reflected = dot(wi, ng_out) > 0.0f;
        if (reflected != (bs.wi.z * wo.z > 0.0f)) break;
        throughput *= bs.weight * lv_shading_normal_adjoint(&s, -r.dir, wi);
        if (!lv_finite3(throughput) || lv_max3(throughput) <= 0.0f) break;
        if (depth >= LV_RR_DEPTH) {
            /* Relative to the particle's starting power, so that bright
             * lights' particles are not culled for being bright. */
            float q = fmin(lv_max3(throughput) / lv_max3(es.weight), 0.95f);
            if (lv_rng_next(&rng) >= q) break;
            throughput /= q;
        }
        r = lv_ray_make(lv_offset_origin(s.p, reflected ? ng_out : -ng_out, sc.info.scene_scale), wi, LV_FAR, h.inst, h.tri);
    }
    atomic_add(&ray_counts[0], segments);
    atomic_add(&ray_counts[1], visibility_rays);
}

/* Every stored cell's lit volume, once the trace is done: lookups read one
 * number instead of walking the subcell record. */
__kernel void lv_lit_volumes(LV_KERNEL_PARAMS(LV_LIT_VOLUMES_ARGS))
{
    uint slot = get_global_id(0);
    if (slot >= grid_info.slot_count) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    lit_volume[slot] = lv_cell_lit_volume(&grid, slot);
}

/* The central direction of every bin, for gathers that visit them all. */
__kernel void lv_bin_directions(LV_KERNEL_PARAMS(LV_BIN_DIRECTIONS_ARGS))
{
    uint bin = get_global_id(0);
    if (bin < 2u * n * n) directions[bin] = (float4)(lv_bin_direction(bin, n, (float2)(0.5f, 0.5f)), 0.0f);
}
