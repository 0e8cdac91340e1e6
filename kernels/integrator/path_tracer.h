/* The reference path tracer: unidirectional, next-event estimation with
 * MIS (direct_light.h), lamps seen through glass by both (see_through.h),
 * Russian roulette, Beer-Lambert absorption inside glass. Depth counts
 * path segments as Mitsuba's max_depth does: 1 shows only emitters seen
 * directly, 2 adds direct lighting. */
#ifndef LV_INTEGRATOR_PATH_TRACER_H
#define LV_INTEGRATOR_PATH_TRACER_H

#include "see_through.h"

/* A path between two segments: all a wavefront keeps of it from one
 * kernel to the next. */
typedef struct {
    lv_ray ray;           /* the next segment */
    float3 beta;          /* throughput up to its origin */
    float3 radiance;      /* gathered so far */
    float prev_pdf;       /* density of the BSDF sample that made ray */
    float eta_scale;      /* the 1/eta'^2 of the refractions so far (roulette's reference, scatter.h) */
    int prev_delta;       /* ray came from a delta lobe or the camera: no MIS */
    uint depth;           /* ray's number among the segments, from 1 */
    uint rough;           /* rough surfaces passed (guided paths' guide serves the first LV_GUIDE_VERTICES) */
    lv_glass_chain chain; /* the delta scatters since the last vertex that sampled lights */
    float level;          /* guided paths: the volume's light at the first rough surface with any (lv_guide_roulette) */
} lv_path;

inline lv_path lv_path_start(lv_ray r)
{
    lv_path p;
    p.ray = r;
    p.beta = (float3)(1.0f);
    p.radiance = (float3)(0.0f);
    p.prev_pdf = 0.0f;
    p.eta_scale = 1.0f;
    p.prev_delta = 1; /* the camera ray counts as a delta sample */
    p.depth = 1u;
    p.rough = 0u;
    p.level = 0.0f;
    p.chain = lv_glass_chain_start((float3)(0.0f), r.dir, 0.0f, 0);
    return p;
}

/* One vertex of path p at hit h of its ray: the emission found there, the
 * absorption on the way, a light sample (*shadow, where it returns with
 * *has_shadow set; lv_shadow_ray_light says what it brings, beta
 * included) and the next ray. Returns whether the path goes on.
 * see_through: light samples go on through glass (see_through.h).
 * With a guide (not null: --mode guided) the next ray at a rough surface
 * comes from the mixture of BSDF and guide. Always inlined, so that a null
 * guide folds away and each caller keeps its own copy (with a second
 * caller in its program, Intel's compiler stopped inlining it and the
 * megakernel ran 4x slower: bench/wavefront.c). */
__attribute__((always_inline)) inline int lv_path_shade(const lv_scene *sc, const lv_guide *guide, lv_path *p, lv_hit h,
                                                        lv_rng *rng, uint max_depth, int see_through,
                                                        lv_shadow_ray *shadow, int *has_shadow)
{
    lv_walk walk = {LV_RADIANCE, LV_ROULETTE_ON, (float3)(p->eta_scale)};
    *has_shadow = 0;
    if (h.tri == LV_NO_HIT) return 0;
    lv_surface s = lv_surface_at(sc, p->ray, h);
    __global const lv_material *m = &sc->materials[s.material];
    float3 le = LV_F3(m->emission);
    if (s.front && lv_max3(le) > 0.0f)
        p->radiance += p->beta * le *
            (p->prev_delta ? lv_glass_chain_weight(sc, &p->chain, h, p->ray.dir, s.ng)
                           : lv_emission_weight(sc, h, p->ray.dir, s.ng, p->prev_pdf, 0));
    if (lv_inside_glass(m, &s)) p->beta *= exp(-LV_F3(m->attenuation) * h.t);
    if (p->depth == max_depth) return 0;

    lv_shading sh;
    if (!lv_shading_at(sc, &s, p->ray.dir, &sh)) return 0;
    /* The guide serves the surfaces whose light the volume may answer for
     * in lv mode (rough, opaque, no delta lobe), the first few on a path. */
    int rough = guide && lv_bsdf_gathers(sh.b.type, sh.b.alpha);
    uint slot = rough
        ? lv_guide_slot(guide, lv_leave_point(s.p, s.arrived, sh.ng_out, -p->ray.dir, h.t, sc->info.scene_scale),
                        sh.ng_out)
        : LV_EMPTY_CELL;
    lv_guide_vertex gv;
    int guided = rough && p->rough < LV_GUIDE_VERTICES && lv_guide_at(guide, slot, s.p, sh.f.n, sh.ng_out, &gv);
    p->rough += rough ? 1u : 0u;
    if (rough) walk.reference *= lv_guide_roulette(guide, slot, &p->level);
    if (p->depth + 1 <= max_depth && lv_bsdf_has_lobe(&sh.b) &&
        lv_light_sample_ray(sc, &s, h, &sh, guided ? &gv : 0, rng, shadow)) {
        shadow->li = p->beta * shadow->li;
        /* The light reached through glass must stay within max_depth. */
        shadow->see_through = see_through ? min((uint)LV_SEE_THROUGH_MAX, max_depth - p->depth - 1u) : 0u;
        shadow->chain_key = lv_rng_fork_key(rng);
        *has_shadow = 1;
    }
    lv_bsdf_sample bs;
    if (guided ? !lv_guided_scatter(sc, &s, h, &sh, &gv, walk, p->depth, rng, &p->beta, &p->ray, &bs)
               : !lv_scatter(sc, &s, h, &sh, walk, p->depth, rng, &p->beta, &p->ray, &bs))
        return 0;
    p->prev_pdf = bs.pdf;
    p->eta_scale *= bs.eta_scale;
    p->prev_delta = bs.delta;
    if (bs.delta) lv_glass_chain_step(&p->chain, m, &s, p->ray.dir);
    else p->chain = lv_glass_chain_start(s.p, p->ray.dir, bs.pdf, see_through);
    p->depth++;
    return 1;
}

/* Radiance arriving along r at its origin: the megakernel, one path from
 * start to end in one work-item; guide and see_through as lv_path_shade's. */
inline float3 lv_path_trace(const lv_scene *sc, const lv_guide *guide, lv_ray r, lv_rng *rng, uint max_depth,
                            int see_through)
{
    lv_path p = lv_path_start(r);
    int more = 1;
    while (more) {
        lv_shadow_ray shadow;
        int has_shadow;
        more = lv_path_shade(sc, guide, &p, lv_trace(sc, p.ray, 0), rng, max_depth, see_through, &shadow, &has_shadow);
        if (has_shadow) p.radiance += lv_shadow_ray_light(sc, &shadow);
    }
    return lv_finite3(p.radiance) ? p.radiance : (float3)(0.0f);
}

#endif
