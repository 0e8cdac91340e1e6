/* One particle's path (paper section 4.1): it leaves a light with an equal
 * share of the emitted power, scatters by the surfaces' BSDFs and ends by
 * Russian roulette; every straight segment adds power x track length to
 * the cells it crosses, in the bin of its direction (eq. 5). */
#ifndef LV_INTEGRATOR_PARTICLE_TRACE_H
#define LV_INTEGRATOR_PARTICLE_TRACE_H

#include "../light/lights.h"
#include "../volume/direction_map.h"
#include "../volume/segment.h"
#include "../volume/subcells.h"
#include "see_through.h"

/* Rays a particle cast, for the statistics. */
typedef struct {
    uint segments;
    uint visibility_rays;
} lv_particle_rays;

/* A view probe (host/render/session_view.c): per slot, its number among
 * the regions the camera sees, or LV_EMPTY_CELL; per such region and light
 * group, the light the particles bring to surfaces there, straight from
 * the lights and after scattering, in units of 2^-20 of the lights' power. */
typedef struct {
    __global const uint *slots;
    __global long *light;
    uint groups; /* 0: no probe */
} lv_view_probe;

/* Adds the light a particle of the light group `group` and weight
 * `throughput` (power over the lights' total), arriving along dir after
 * `depth` segments, brings to surface point p: to the region in front of
 * p on its side, where the camera sees that. Integers, so that the sums
 * are the same on every device and in every order. */
inline void lv_view_add(const lv_grid *grid, const lv_view_probe *v, uint group, float3 p, float3 dir, uint depth,
                        float3 throughput)
{
    uint slot = lv_grid_slot_at(grid, p - dir * (0.01f * grid->g.cell_size));
    uint seen = slot == LV_EMPTY_CELL ? LV_EMPTY_CELL : v->slots[slot];
    float units = lv_luminance(throughput) * 0x1p20f;
    if (seen == LV_EMPTY_CELL || !(units >= 1.0f)) return;
    lv_tally_atomic_add(&v->light[2u * (seen * v->groups + group) + (depth > 1u ? 1u : 0u)],
                        (long)fmin(units, 0x1p40f));
}

/* Adds segment r, which carried `weight` (power over total power) up to
 * hit h (surface s, if any) through a medium of absorption sigma, to the
 * volume (its light concentrated where `concentrated`, the bin tables, is
 * not null, and in the lobes where `lobe`: lv_tally_segment); at a hit
 * also offers a lit point and may cast a visibility ray. Returns the
 * visibility rays cast. */
inline uint lv_particle_deposit(const lv_scene *sc, const lv_grid *grid, lv_ray r, lv_hit h, const lv_surface *s,
                                float3 weight, float3 sigma, const lv_bin_tables *concentrated, int lobe, lv_rng *rng)
{
    uint fine = lv_direction_bin(r.dir, 2u * grid->g.dirs);
    int offers = grid->g.subcells && h.tri != LV_NO_HIT && !grid->restarted_only;
    /* The lit point and the visibility ray draw from a stream of their
     * own: how many numbers a visibility ray takes depends on the cell's
     * regions, which refining changes, and a retrace must walk each
     * particle as it first went. */
    lv_rng side = lv_rng_keyed(lv_rng_fork_key(rng));
    /* Just off the hit on the side the particle came from, its light
     * reached: off along the normal, by more than a lit point's rounding
     * (1/512 subcell per axis), so even a grazing hit's point stays on
     * that side. */
    float3 lit = (float3)(0.0f);
    lv_lit_offer offer = {LV_NO_ENTRY, 0u};
    if (offers) {
        float3 toward = dot(r.dir, s->ng) < 0.0f ? s->ng : -s->ng;
        lit = s->p + toward * (0.02f * grid->g.cell_size / (float)grid->g.subcells);
        offer = lv_lit_point_offer(grid, lit, &side);
    }
    lv_tally_segment(grid, r.origin, r.dir, 0.0f, h.t, (uint2)(lv_coarse_bin(fine, grid->g.dirs), fine), weight, sigma,
                     concentrated, lobe);
    if (!offers) return 0u;
    lv_lit_point_keep(grid, offer);
    /* Both go to the region of the lit point, the hit's side of the surface. */
    if (lv_rng_next(&side) < grid->g.visibility_rate)
        return lv_sample_subcell_visibility(grid, sc, s->p, lit, r.origin, &side);
    return 0u;
}

/* Traces one particle, drawing from rng, into grid (tables: its bin
 * tables). store_emitted: tally the first segment (emitted light) too,
 * which lv mode leaves to shadow rays. see_through: leave out light seen
 * through glass (see_through.h), which lv mode's gather finds itself; its
 * segments still mark the subcells they pass. view: a view probe
 * (lv_view_add) or none. */
inline lv_particle_rays lv_trace_particle(const lv_scene *sc, const lv_grid *grid, const lv_bin_tables *tables,
                                          lv_rng *rng, uint store_emitted, uint see_through, const lv_view_probe *view)
{
    int specular_only = 1; /* every scatter so far a delta lobe: the light is still concentrated */
    int through_glass = 1; /* and every one at a surface where no gather reads the volume, turning light only
                            * inside glass (see_through.h) */
    lv_particle_rays n = {0u, 0u};
    lv_emission_sample es;
    float2 ul = lv_rng_next2(rng), ud = lv_rng_next2(rng);
    if (!lv_sample_emission(sc, ul, ud, lv_rng_next(rng), &es)) return n;
    uint group = view->groups ? sc->lights[es.light].group : 0u;
    const lv_walk walk = {LV_IMPORTANCE, LV_ROULETTE_ON, es.weight};
    float3 throughput = es.weight;
    lv_ray r = lv_ray_make(es.origin, es.dir, LV_FAR, es.instance, es.triangle);
    for (uint depth = 1; depth <= sc->info.max_depth; depth++) {
        lv_hit h = lv_trace(sc, r, 0);
        n.segments++;
        lv_surface s;
        __global const lv_material *m = 0;
        float3 sigma = (float3)(0.0f);
        if (h.tri != LV_NO_HIT) {
            s = lv_surface_at(sc, r, h);
            m = &sc->materials[s.material];
            if (lv_inside_glass(m, &s)) sigma = LV_F3(m->attenuation);
        }
        if (depth > 1 || store_emitted) {
            /* Light seen through glass is light samples' to find (with
             * see_through) or the guide's lights' share's: never a lobe's. */
            int seen = through_glass && lv_seen_through(sc, es.light, es.dir, r.origin, r.dir, depth - 1u);
            int left_out = see_through && seen;
            n.visibility_rays +=
                lv_particle_deposit(sc, grid, r, h, &s, left_out ? (float3)(0.0f) : throughput, sigma,
                                    specular_only && !left_out ? tables : 0, specular_only && !seen, rng);
        }
        if (h.tri == LV_NO_HIT || depth == sc->info.max_depth) break;
        throughput *= exp(-sigma * h.t);
        if (view->groups) lv_view_add(grid, view, group, s.p, r.dir, depth, throughput);

        lv_shading sh;
        if (!lv_shading_at(sc, &s, r.dir, &sh)) break;
        lv_bsdf_sample bs;
        if (!lv_scatter(sc, &s, h, &sh, walk, depth, rng, &throughput, &r, &bs)) break;
        specular_only = specular_only && bs.delta;
        through_glass = through_glass && lv_still_seen_through(m, &s, bs.delta, r.dir, es.dir);
    }
    return n;
}

#endif
