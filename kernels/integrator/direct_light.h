/* Next-event estimation with multiple importance sampling (power
 * heuristic) for area lights, plain NEE for punctual lights: the light
 * sampling half here, and the weight of the BSDF-sampling half that a path
 * applies where it hits an emitter. */
#ifndef LV_INTEGRATOR_DIRECT_LIGHT_H
#define LV_INTEGRATOR_DIRECT_LIGHT_H

#include "../light/lights.h"
#include "scatter.h"

/* A light sample's shadow ray (origin + t d, t in (0, 0.9999), leaving
 * triangle tri of instance inst) and the radiance it brings if nothing
 * blocks it. */
typedef struct {
    float3 origin, d;
    uint inst, tri;
    float3 li;
    float mis;  /* the MIS weight li carries */
    uint light; /* the light sampled, an index into sc->lights */
    /* A camera path's ray, where blocked, goes on through at most this
     * many delta scatters (see_through.h; 0: not), drawing from the
     * stream keyed chain_key. */
    uint see_through, chain_key;
} lv_shadow_ray;

/* Samples one light for surface s (hit h), MIS-weighted against BSDF
 * sampling, or against the mixture of BSDF and guide where gv is not null
 * (a guided path scatters by that mixture); returns 0 where the sample
 * cannot contribute. Draws three numbers. The occlusion test is the
 * caller's, so that a wavefront can trace shadow rays in a kernel of their
 * own. */
inline int lv_light_sample_ray(const lv_scene *sc, const lv_surface *s, lv_hit h, const lv_shading *sh,
                               const lv_guide_vertex *gv, lv_rng *rng, lv_shadow_ray *out)
{
    lv_light_sample ls;
    float3 u = lv_rng_next3(rng);
    if (!lv_sample_light(sc, s->p, u, &ls)) return 0;
    float3 wi = lv_to_local(sh->f, ls.wi);
    float pdf;
    float3 fcos = lv_bsdf_eval(&sh->b, sh->wo, wi, LV_RADIANCE, &pdf);
    if (lv_max3(fcos) <= 0.0f) return 0;
    /* Leave from the side of the surface the light is on. */
    float3 n_side = dot(ls.wi, sh->ng_out) >= 0.0f ? sh->ng_out : -sh->ng_out;
    if (!lv_bsdf_transmits(sh->b.type) && dot(ls.wi, sh->ng_out) <= 0.0f) return 0;
    out->origin = lv_leave_point(s->p, s->arrived, n_side, lv_to_world(sh->f, sh->wo), h.t, sc->info.scene_scale);
    out->d = ls.target - out->origin;
    out->inst = h.inst;
    out->tri = h.tri;
    float w = ls.delta ? 1.0f : lv_power_heuristic(ls.pdf, gv ? lv_guide_density(gv, pdf, ls.wi) : pdf);
    out->li = fcos * ls.li * (w / ls.pdf);
    out->mis = w;
    out->light = ls.light;
    out->see_through = 0u;
    return 1;
}

inline int lv_shadow_ray_blocked(const lv_scene *sc, const lv_shadow_ray *r)
{
    return lv_occluded(sc, r->origin, r->d, 0.9999f, r->inst, r->tri);
}

/* The MIS weight of emission that a ray along dir found at h (front normal
 * ng) after a BSDF sample of density prev_pdf; 1 after a delta lobe or
 * from the camera, which light sampling could not have found. */
inline float lv_emission_weight(const lv_scene *sc, lv_hit h, float3 dir, float3 ng, float prev_pdf, int prev_delta)
{
    return prev_delta ? 1.0f : lv_power_heuristic(prev_pdf, lv_light_pdf(sc, h, dir, ng));
}

#endif
