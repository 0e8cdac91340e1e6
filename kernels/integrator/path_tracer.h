/* The reference path tracer: unidirectional, next-event estimation with
 * MIS (direct_light.h), Russian roulette, Beer-Lambert absorption inside
 * glass. Depth counts path segments as Mitsuba's max_depth does: 1 shows
 * only emitters seen directly, 2 adds direct lighting. */
#ifndef LV_INTEGRATOR_PATH_TRACER_H
#define LV_INTEGRATOR_PATH_TRACER_H

#include "direct_light.h"

/* Radiance arriving along r at its origin. */
inline float3 lv_path_trace(const lv_scene *sc, lv_ray r, lv_rng *rng, uint max_depth)
{
    const lv_walk walk = {LV_RADIANCE, LV_ROULETTE_BETA, (float3)(1.0f)};
    float3 radiance = (float3)(0.0f);
    float3 beta = (float3)(1.0f);
    lv_bsdf_sample bs;
    bs.pdf = 0.0f;
    bs.delta = 1; /* the camera ray counts as a delta sample: no MIS */
    for (uint depth = 1; depth <= max_depth; depth++) {
        lv_hit h = lv_trace(sc, r, 0);
        if (h.tri == LV_NO_HIT) break;
        lv_surface s = lv_surface_at(sc, r, h);
        __global const lv_material *m = &sc->materials[s.material];
        float3 le = LV_F3(m->emission);
        if (s.front && lv_max3(le) > 0.0f)
            radiance += beta * le * lv_emission_weight(sc, h, r.dir, s.ng, bs.pdf, bs.delta);
        if (lv_inside_glass(m, &s)) beta *= exp(-LV_F3(m->attenuation) * h.t);
        if (depth == max_depth) break;

        lv_shading sh;
        if (!lv_shading_at(sc, &s, r.dir, &sh)) break;
        if (depth + 1 <= max_depth && lv_bsdf_has_lobe(&sh.b)) radiance += beta * lv_direct_light(sc, &s, h, &sh, rng);
        if (!lv_scatter(sc, &s, h, &sh, walk, depth, rng, &beta, &r, &bs)) break;
    }
    return lv_finite3(radiance) ? radiance : (float3)(0.0f);
}

#endif
