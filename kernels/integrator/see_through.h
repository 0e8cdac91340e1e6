/* Lamps seen through glass (docs/light-volume.md, "Lamps seen through
 * glass"). Light that left a lamp, crossed only specular surfaces and
 * still travels the way it left (a glass table top or a window pane: flat
 * parallel faces shift it sideways but do not turn it) reaches a rough
 * surface as the lamp's own light would, sharp shadows and all. In lv mode
 * the final gather finds it at the point, as its shadow rays find direct
 * light, and the particle trace leaves it out of the volume, which would
 * blur it over a cell. Both sides sort light by the same test, so each
 * piece is counted once, by one of them. */
#ifndef LV_INTEGRATOR_SEE_THROUGH_H
#define LV_INTEGRATOR_SEE_THROUGH_H

#include "direct_light.h"

/* The most specular scatters a lamp is seen through (two for a slab). */
#define LV_SEE_THROUGH_MAX 4
/* The least cosine between the directions light left the lamp with and
 * arrives with (a slab's float refraction is good to about 1e-7). */
#define LV_SEE_THROUGH_COS 0.99999f

/* Whether a ray that set out along dir0 (either way along the light's
 * path) and leaves surface s (material m) along dir has turned in the open:
 * it travels outside solid glass and no longer along dir0. A slab turns
 * light only inside itself, so such light is never seen through; both
 * sides stop following it there (a curved glass or a mirror). */
inline int lv_turned_outside_glass(__global const lv_material *m, const lv_surface *s, float3 dir, float3 dir0)
{
    int inside = m->bsdf == LV_BSDF_GLASS && dot(dir, s->ng) < 0.0f;
    return !inside && dot(dir, dir0) < LV_SEE_THROUGH_COS;
}

/* Whether a particle's light that left area light `emitter` (an index into
 * sc->lights) along dir0, crossed `scatters` specular surfaces at which no
 * gather reads the volume, and now travels along dir from p is seen
 * through: its direction kept, and the half-line from p back along -dir
 * meeting the emitter's front face, as a gather's light sample toward that
 * face would. */
inline int lv_seen_through(const lv_scene *sc, uint emitter, float3 dir0, float3 p, float3 dir, uint scatters)
{
    if (scatters < 1u || scatters > LV_SEE_THROUGH_MAX || dot(dir, dir0) < LV_SEE_THROUGH_COS) return 0;
    lv_light light = sc->lights[emitter];
#ifdef LV_FEATURE_PUNCTUAL
    if (light.kind == LV_LIGHT_PUNCTUAL) return 0; /* a point cannot be met again */
#endif
    float3 v0, v1, v2;
    float front_sign = lv_triangle_world(sc, light.instance, light.index, &v0, &v1, &v2);
    float3 e1 = v1 - v0, e2 = v2 - v0;
    if (!(front_sign * dot(dir, cross(e1, e2)) > 0.0f)) return 0;
    return lv_half_line_crossing(p, -dir, v0, e1, e2) > 0.0f;
}

/* What the light sample of shadow ray r, found blocked, brings through
 * glass: the ray goes on through specular surfaces (sampled as a path
 * would; numbers are drawn only where a surface has a delta lobe) and
 * counts if it meets the sampled triangle's front face after at most
 * LV_SEE_THROUGH_MAX of them, going the way it set out. Without MIS
 * weight: a gather point's BSDF rays stop at glass and read the volume, so
 * they never find this light. */
inline float3 lv_light_seen_through(const lv_scene *sc, const lv_shadow_ray *r, lv_rng *rng)
{
    lv_light light = sc->lights[r->light];
#ifdef LV_FEATURE_PUNCTUAL
    if (light.kind == LV_LIGHT_PUNCTUAL) return (float3)(0.0f);
#endif
    if (!(r->mis > 0.0f)) return (float3)(0.0f);
    float3 dir = normalize(r->d), beta = r->li / r->mis;
    lv_ray ray = lv_ray_make(r->origin, dir, LV_FAR, r->inst, r->tri);
    const lv_walk walk = {LV_RADIANCE, LV_ROULETTE_NONE, (float3)(1.0f)};
    for (uint scatters = 0u;; scatters++) {
        lv_hit h = lv_trace(sc, ray, 0);
        if (h.tri == LV_NO_HIT) return (float3)(0.0f);
        lv_surface s = lv_surface_at(sc, ray, h);
        if (h.inst == light.instance && h.tri == light.index)
            return s.front && scatters >= 1u && dot(ray.dir, dir) >= LV_SEE_THROUGH_COS ? beta : (float3)(0.0f);
        __global const lv_material *m = &sc->materials[s.material];
        if (scatters == LV_SEE_THROUGH_MAX || lv_bsdf_gathers(m->bsdf, m->alpha)) return (float3)(0.0f);
        if (lv_inside_glass(m, &s)) beta *= exp(-LV_F3(m->attenuation) * h.t);
        lv_shading sh;
        lv_bsdf_sample bs;
        if (!lv_shading_at(sc, &s, ray.dir, &sh) || !lv_bsdf_has_delta(&sh.b) ||
            !lv_scatter(sc, &s, h, &sh, walk, 1u, rng, &beta, &ray, &bs) || !bs.delta ||
            lv_turned_outside_glass(m, &s, ray.dir, dir))
            return (float3)(0.0f);
    }
}

/* Direct light at a gather point (surface s, hit h) from one light sample,
 * MIS-weighted against BSDF sampling, and where its shadow ray is blocked
 * and see_through is set, the sampled lamp seen through glass. Draws three
 * numbers, and more only on glass. */
inline float3 lv_gather_direct_light(const lv_scene *sc, const lv_surface *s, lv_hit h, const lv_shading *sh,
                                     int see_through, lv_rng *rng)
{
    lv_shadow_ray r;
    if (!lv_light_sample_ray(sc, s, h, sh, 0, rng, &r)) return (float3)(0.0f);
    if (!lv_shadow_ray_blocked(sc, &r)) return r.li;
    return see_through ? lv_light_seen_through(sc, &r, rng) : (float3)(0.0f);
}

#endif
