/* Unidirectional path tracing: next-event estimation with multiple
 * importance sampling (power heuristic) for area lights, plain NEE for
 * punctual lights, Russian roulette, Beer-Lambert absorption inside glass.
 * Depth counts path segments as Mitsuba's max_depth does: 1 shows only
 * emitters seen directly, 2 adds direct lighting. */
#ifndef LV_PATH_H
#define LV_PATH_H

#include "camera.h"
#include "lights.h"
#include "rng.h"

/* Paths longer than this many segments may end by Russian roulette. */
#define LV_RR_DEPTH 5

/* Direct light at surface s from one light sample, MIS-weighted against
 * BSDF sampling. ng_out is the geometric normal on the side wo leaves from. */
inline float3 lv_direct_light(const lv_scene *sc, const lv_surface *s, const lv_bsdf *b, lv_frame f,
                              float3 wo, float3 ng_out, lv_rng *rng)
{
    lv_light_sample ls;
    float3 u = (float3)(lv_rng_next2(rng), lv_rng_next(rng));
    if (!lv_sample_light(sc, s->p, u, &ls)) return (float3)(0.0f);
    float3 wi = lv_to_local(f, ls.wi);
    float3 fcos = lv_bsdf_eval(b, wo, wi, LV_RADIANCE);
    if (lv_max3(fcos) <= 0.0f) return (float3)(0.0f);
    /* Leave from the side of the surface the light is on. */
    float3 n_side = dot(ls.wi, ng_out) >= 0.0f ? ng_out : -ng_out;
    if (!lv_bsdf_transmits(b->type) && dot(ls.wi, ng_out) <= 0.0f) return (float3)(0.0f);
    float3 origin = lv_offset_origin(s->p, n_side, sc->info.scene_scale);
    float3 d = ls.target - origin;
    if (lv_occluded(sc, origin, d, 0.9999f)) return (float3)(0.0f);
    float w = ls.delta ? 1.0f : lv_power_heuristic(ls.pdf, lv_bsdf_pdf(b, wo, wi));
    return fcos * ls.li * (w / ls.pdf);
}

/* Radiance arriving along ray r at its origin. */
inline float3 lv_path_radiance(const lv_scene *sc, lv_ray r, lv_rng *rng, uint max_depth)
{
    float3 radiance = (float3)(0.0f);
    float3 beta = (float3)(1.0f);
    float prev_pdf = 0.0f;
    int prev_delta = 1; /* the camera ray counts as a delta sample: no MIS */
    for (uint depth = 1; depth <= max_depth; depth++) {
        lv_hit h = lv_trace(sc, r, 0);
        if (h.tri == LV_NO_HIT) break;
        lv_surface s = lv_surface_at(sc, r, h);
        __global const lv_material *m = &sc->materials[s.material];

        float3 le = LV_F3(m->emission);
        if (s.front && lv_max3(le) > 0.0f) {
            float w = prev_delta ? 1.0f : lv_power_heuristic(prev_pdf, lv_light_pdf(sc, h.tri, r.dir, h.t, s.ng));
            radiance += beta * le * w;
        }
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

        if (depth + 1 <= max_depth && lv_bsdf_has_smooth_lobe(&b))
            radiance += beta * lv_direct_light(sc, &s, &b, f, wo, ng_out, rng);

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

        if (depth >= LV_RR_DEPTH) {
            float q = fmin(lv_max3(beta), 0.95f);
            if (lv_rng_next(rng) >= q) break;
            beta /= q;
        }
        r.origin = lv_offset_origin(s.p, reflected ? ng_out : -ng_out, sc->info.scene_scale);
        r.dir = wi;
        r.tmax = LV_FAR;
    }
    return lv_finite3(radiance) ? radiance : (float3)(0.0f);
}

#endif
