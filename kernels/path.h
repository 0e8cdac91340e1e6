/* Unidirectional path tracing: next-event estimation with multiple
 * importance sampling (power heuristic) for area lights, plain NEE for
 * punctual lights, Russian roulette, Beer-Lambert absorption inside glass.
 * Depth counts path segments as Mitsuba's max_depth does: 1 shows only
 * emitters seen directly, 2 adds direct lighting. */
#ifndef LV_PATH_H
#define LV_PATH_H

#include "scene/camera.h"
#include "light/lights.h"
#include "volume/lookup.h"
#include "util/rng.h"

/* Paths longer than this many segments may end by Russian roulette. */
#define LV_RR_DEPTH 5

/* Direct light at surface s from one light sample, MIS-weighted against
 * BSDF sampling. ng_out is the geometric normal on the
 * side wo leaves from. */
inline float3 lv_direct_light(const lv_scene *sc, const lv_surface *s, lv_hit h, const lv_bsdf *b, lv_frame f,
                              float3 wo, float3 ng_out, lv_rng *rng)
{
    lv_light_sample ls;
    float3 u = (float3)(lv_rng_next2(rng), lv_rng_next(rng));
    if (!lv_sample_light(sc, s->p, u, &ls)) return (float3)(0.0f);
    float3 wi = lv_to_local(f, ls.wi);
    float pdf;
    float3 fcos = lv_bsdf_eval(b, wo, wi, LV_RADIANCE, &pdf);
    if (lv_max3(fcos) <= 0.0f) return (float3)(0.0f);
    /* Leave from the side of the surface the light is on. */
    float3 n_side = dot(ls.wi, ng_out) >= 0.0f ? ng_out : -ng_out;
    if (!lv_bsdf_transmits(b->type) && dot(ls.wi, ng_out) <= 0.0f) return (float3)(0.0f);
    float3 origin = lv_offset_origin(s->p, n_side, sc->info.scene_scale);
    float3 d = ls.target - origin;
    if (lv_occluded(sc, origin, d, 0.9999f, h.inst, h.tri)) return (float3)(0.0f);
    float w = ls.delta ? 1.0f : lv_power_heuristic(ls.pdf, pdf);
    return fcos * ls.li * (w / ls.pdf);
}

/* How the final gather reads the light volume (NULL: plain path tracing). */
typedef struct {
    lv_grid grid;
    __global const float4 *bin_directions; /* central direction of each bin */
    uint flags;      /* LV_GATHER_* */
    float threshold; /* a BSDF ray hitting closer than this continues as a path */
} lv_gather;

#define LV_GATHER_ALL 1u       /* the volume holds all light, emitted too: no shadow rays */
#define LV_GATHER_INTEGRATE 2u /* integrate the BSDF over every bin instead of sampling one */

inline int lv_gather_here(const lv_bsdf *b)
{
    return lv_bsdf_gathers(b->type, b->alpha);
}

/* The BSDF-weighted sum of the volume's radiance over every bin of the cell
 * at p (each bin read at its central direction); ng_out is the geometric
 * normal on the side wo leaves from. */
inline float3 lv_gather_integrate(const lv_gather *g, const lv_bsdf *b, lv_frame f, float3 wo, float3 ng_out, float3 p)
{
    uint slot = lv_grid_slot_at(&g->grid, p);
    if (slot == LV_EMPTY_CELL) return (float3)(0.0f);
    /* A Lambertian surface's f cos is base / pi times cos: sum the tallies
     * weighted by cos alone and apply the rest once (most gathers). */
    int lambert = b->type == LV_BSDF_DIFFUSE;
    if (lambert && wo.z <= 0.0f) return (float3)(0.0f);
    float3 sum = (float3)(0.0f);
    __global const long *tallies = lv_tally_bin(&g->grid, slot, 0u); /* a slot's bins are consecutive */
    for (uint bin = 0; bin < g->grid.g.bins; bin++) {
        /* Light arriving from wi travels along -wi. The gather runs on
         * reflecting surfaces only; a direction the shading normal allows
         * but the true surface does not would read light leaving the
         * surface itself. */
        float3 wiw = -g->bin_directions[bin].xyz;
        float3 wi = lv_to_local(f, wiw);
        if (wi.z <= 0.0f || dot(wiw, ng_out) <= 0.0f) continue;
        float3 fcos = lambert ? (float3)(wi.z) : lv_bsdf_eval(b, wo, wi, LV_RADIANCE, 0);
        if (lv_max3(fcos) > 0.0f) sum += fcos * lv_bin_tally(tallies + 3 * bin);
    }
    if (lambert) sum *= b->base * LV_INV_PI;
    return sum * (lv_tally_to_radiance(&g->grid, g->grid.lit_volume[slot]) * lv_bin_solid_angle(g->grid.g.dirs));
}

/* What the ray just traced owes the light volume once it lands. */
#define LV_LOOKUP_NONE 0
#define LV_LOOKUP_READ 1    /* a far hit reads the volume in the ray's direction */
#define LV_LOOKUP_CORRECT 2 /* a near hit takes back the volume's share: the path answers instead */

/* Radiance arriving along ray r at its origin, by path tracing or, with a
 * gather, by the light volume at the first rough surface (paper section 5).
 * There shadow rays give direct light (unless the volume holds all light)
 * and the volume, read at a jittered point around the surface, the rest.
 * The paper's way (sampled) follows one BSDF ray: if it meets a rough
 * surface closer than the threshold the path goes on, otherwise the
 * volume's bin in its direction answers. The integrating way sums the BSDF
 * over every bin and still follows one BSDF ray: where that ray hits close,
 * the path's radiance replaces the volume's for its direction, so near
 * geometry (corners, contact shadows), which a cell average cannot resolve,
 * is path traced as in the paper while far light stays noise-free. */
inline float3 lv_path_radiance(const lv_scene *sc, lv_ray r, lv_rng *rng, uint max_depth, const lv_gather *g)
{
    float3 radiance = (float3)(0.0f);
    float3 beta = (float3)(1.0f);
    float prev_pdf = 0.0f;
    int prev_delta = 1; /* the camera ray counts as a delta sample: no MIS */
    int all_light = g && (g->flags & LV_GATHER_ALL);
    int lookup = LV_LOOKUP_NONE;
    float3 lookup_point = (float3)(0.0f);
    int lookup_lit = 0; /* the volume at lookup_point holds light that reaches the surface */
    for (uint depth = 1; depth <= max_depth; depth++) {
        lv_hit h = lv_trace(sc, r, 0);
        lv_surface s;
        __global const lv_material *m = 0;
        /* A near hit continues the path only on a rough surface: a specular
         * one would lead on to caustics, which the volume holds already. */
        int far = h.tri == LV_NO_HIT;
        if (h.tri != LV_NO_HIT) {
            s = lv_surface_at(sc, r, h);
            m = &sc->materials[s.material];
            far = lookup != LV_LOOKUP_NONE && (h.t > g->threshold || !lv_bsdf_gathers(m->bsdf, m->alpha));
            float3 le = LV_F3(m->emission);
            if (s.front && lv_max3(le) > 0.0f && !(all_light && !prev_delta)) {
                float w = prev_delta ? 1.0f : lv_power_heuristic(prev_pdf, lv_light_pdf(sc, h, r.dir, s.ng));
                radiance += beta * le * w;
            }
        }
        if (lookup != LV_LOOKUP_NONE) {
            /* Light arriving from r.dir travels along -r.dir. */
            float3 volume = lookup_lit ? beta * lv_volume_radiance(&g->grid, lookup_point, -r.dir) : (float3)(0.0f);
            if (far) {
                if (lookup == LV_LOOKUP_READ) radiance += volume;
                break;
            }
            if (lookup == LV_LOOKUP_CORRECT) radiance -= volume;
            lookup = LV_LOOKUP_NONE;
        }
        if (h.tri == LV_NO_HIT) break;
#ifdef LV_FEATURE_GLASS
        /* The segment just traced ran inside a glass volume. */
        if (m->bsdf == LV_BSDF_GLASS && !s.front) beta *= exp(-LV_F3(m->attenuation) * h.t);
#endif
        if (depth == max_depth) break;

        lv_frame f;
        if (!lv_shading_frame(sc, &s, r.dir, &f)) break;
        lv_bsdf b = lv_surface_bsdf(sc, &s);
        float3 wo = lv_to_local(f, -r.dir);
        float3 ng_out = dot(r.dir, s.ng) < 0.0f ? s.ng : -s.ng;
        int gather = g && lv_gather_here(&b);
        int integrate = gather && (g->flags & LV_GATHER_INTEGRATE);
        int lit_here = gather && lv_lookup_point(&g->grid, sc, s.p, ng_out, rng, &lookup_point);

        if (depth + 1 <= max_depth && lv_bsdf_has_lobe(&b) && !all_light)
            radiance += beta * lv_direct_light(sc, &s, h, &b, f, wo, ng_out, rng);
        if (integrate) {
            if (lit_here) radiance += beta * lv_gather_integrate(g, &b, f, wo, ng_out, lookup_point);
            if (all_light) break; /* no threshold: the volume answers for every direction */
        }

        lv_bsdf_sample bs;
        float3 u = (float3)(lv_rng_next2(rng), lv_rng_next(rng));
        if (!lv_bsdf_sample_dir(&b, wo, u, LV_RADIANCE, &bs)) break;
        float3 wi = lv_to_world(f, bs.wi);
        /* Reject directions that the shading normal allows but the true
         * surface does not (reflection into it, transmission out of it). */
        int reflected = dot(wi, ng_out) > 0.0f;
        if (reflected != (bs.wi.z * wo.z > 0.0f)) break;
        beta *= bs.weight;
        prev_pdf = bs.pdf;
        prev_delta = bs.delta;
        if (!lv_finite3(beta) || lv_max3(beta) <= 0.0f) break;
        if (gather) {
            if (all_light) { /* no threshold: the volume answers at once */
                if (lit_here) radiance += beta * lv_volume_radiance(&g->grid, lookup_point, -wi);
                break;
            }
            lookup = integrate ? LV_LOOKUP_CORRECT : LV_LOOKUP_READ;
            lookup_lit = lit_here;
        } else if (depth >= LV_RR_DEPTH) {
            float q = fmin(lv_max3(beta), 0.95f);
            if (lv_rng_next(rng) >= q) break;
            beta /= q;
        }
        r = lv_ray_make(lv_offset_origin(s.p, reflected ? ng_out : -ng_out, sc->info.scene_scale), wi, LV_FAR, h.inst, h.tri);
    }
    return lv_finite3(radiance) ? radiance : (float3)(0.0f);
}

#endif
