/* Lamps seen through glass (docs/light-volume.md, "Lamps seen through
 * glass"). Light that left a lamp, crossed only specular surfaces and
 * still travels the way it left (a glass table top or a window pane: flat
 * parallel faces shift it sideways but do not turn it) reaches a rough
 * surface as the lamp's own light would, sharp shadows and all. In lv mode
 * the final gather finds it at the point, as its shadow rays find direct
 * light, and the particle trace leaves it out of the volume, which would
 * blur it over a cell. Both sides sort light by the same test, so each
 * piece is counted once, by one of them. Camera paths (pt, guided) find it
 * both by light samples and by the paths themselves, weighted by MIS (the
 * second half of this file). */
#ifndef LV_INTEGRATOR_SEE_THROUGH_H
#define LV_INTEGRATOR_SEE_THROUGH_H

#include "direct_light.h"

/* The most specular scatters a lamp is seen through (two for a slab). */
#define LV_SEE_THROUGH_MAX 4
/* The least cosine between the directions light left the lamp with and
 * arrives with (a slab's float refraction is good to about 1e-7). */
#define LV_SEE_THROUGH_COS 0.99999f

/* Whether directions a and b agree within LV_SEE_THROUGH_COS, whatever
 * their lengths: fast math may leave a direction 1e-4 off unit length
 * (Intel's runtime did, in the wavefront benchmark's kernels), which alone
 * would fail the test. */
inline int lv_same_direction(float3 a, float3 b)
{
    return dot(a, b) >= LV_SEE_THROUGH_COS * sqrt(dot(a, a) * dot(b, b));
}

/* Whether a ray that set out along dir0 (either way along the light's
 * path) and leaves surface s (material m) along dir has turned in the open:
 * it travels outside solid glass and no longer along dir0. A slab turns
 * light only inside itself, so such light is never seen through; both
 * sides stop following it there (a curved glass or a mirror). */
inline int lv_turned_outside_glass(__global const lv_material *m, const lv_surface *s, float3 dir, float3 dir0)
{
    int inside = m->bsdf == LV_BSDF_GLASS && dot(dir, s->ng) < 0.0f;
    return !inside && !lv_same_direction(dir, dir0);
}

/* Whether light that set out along dir0 is still seen through after a
 * scatter at surface s (material m) that sampled a delta lobe or not
 * (delta) and left along dir: the lobe was a delta one, at a surface
 * where no gather reads the volume, and the light did not turn outside
 * glass. The particle trace, the gather's chains and camera paths all
 * test this, so they agree on what is seen through. */
inline int lv_still_seen_through(__global const lv_material *m, const lv_surface *s, int delta, float3 dir,
                                 float3 dir0)
{
    return delta && !lv_bsdf_gathers(m->bsdf, m->alpha) && !lv_turned_outside_glass(m, s, dir, dir0);
}

/* Whether a light is a sun (a directional light): the one punctual light
 * that glass may be seen through, since its light arrives from a direction,
 * not from a point a shifted path would miss. */
inline int lv_light_is_sun(const lv_scene *sc, lv_light light)
{
#ifdef LV_FEATURE_PUNCTUAL
    return light.kind == LV_LIGHT_PUNCTUAL && sc->punctuals[light.index].type == LV_PUNCTUAL_DIRECTIONAL;
#else
    return 0;
#endif
}

/* Whether a particle's light that left light `emitter` (an index into
 * sc->lights) along dir0, crossed `scatters` specular surfaces at which no
 * gather reads the volume, and now travels along dir from p is seen
 * through: its direction kept, and for an area light the half-line from p
 * back along -dir meeting the emitter's front face, as a gather's light
 * sample toward that face would (a sun's is met by any such half-line). */
inline int lv_seen_through(const lv_scene *sc, uint emitter, float3 dir0, float3 p, float3 dir, uint scatters)
{
    if (scatters < 1u || scatters > LV_SEE_THROUGH_MAX || !lv_same_direction(dir, dir0)) return 0;
    lv_light light = sc->lights[emitter];
    if (lv_light_is_sun(sc, light)) return 1;
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
 * glass, starting from weight beta: the ray goes on through specular
 * surfaces (sampled as a path would; numbers are drawn only where a
 * surface has a delta lobe) and counts if it meets the sampled triangle's
 * front face after 1 to max_scatters of them, going the way it set out; or,
 * toward a sun, if it leaves the scene so. No path can meet a sun, so that
 * light is this sample's alone (r->mis is 1). */
inline float3 lv_light_seen_through(const lv_scene *sc, const lv_shadow_ray *r, float3 beta, uint max_scatters,
                                    lv_rng *rng)
{
    lv_light light = sc->lights[r->light];
    int sun = lv_light_is_sun(sc, light);
#ifdef LV_FEATURE_PUNCTUAL
    if (light.kind == LV_LIGHT_PUNCTUAL && !sun) return (float3)(0.0f);
#endif
    if (!(r->mis > 0.0f)) return (float3)(0.0f);
    float3 dir = normalize(r->d);
    lv_ray ray = lv_ray_make(r->origin, dir, LV_FAR, r->inst, r->tri);
    const lv_walk walk = {LV_RADIANCE, LV_ROULETTE_NONE, (float3)(1.0f)};
    for (uint scatters = 0u;; scatters++) {
        lv_hit h = lv_trace(sc, ray, 0);
        if (h.tri == LV_NO_HIT) return sun && scatters >= 1u && lv_same_direction(ray.dir, dir) ? beta : (float3)(0.0f);
        lv_surface s = lv_surface_at(sc, ray, h);
        if (!sun && h.inst == light.instance && h.tri == light.index)
            return s.front && scatters >= 1u && lv_same_direction(ray.dir, dir) ? beta : (float3)(0.0f);
        __global const lv_material *m = &sc->materials[s.material];
        if (scatters >= max_scatters || lv_bsdf_gathers(m->bsdf, m->alpha)) return (float3)(0.0f);
        if (lv_inside_glass(m, &s)) beta *= exp(-LV_F3(m->attenuation) * h.t);
        lv_shading sh;
        lv_bsdf_sample bs;
        if (!lv_shading_at(sc, &s, ray.dir, &sh) || !lv_bsdf_has_delta(&sh.b) ||
            !lv_scatter(sc, &s, h, &sh, walk, 1u, rng, &beta, &ray, &bs) ||
            !lv_still_seen_through(m, &s, bs.delta, ray.dir, dir))
            return (float3)(0.0f);
    }
}

/* ---- Camera paths (pt and guided): the same light found two ways ----
 *
 * At a vertex x that samples lights, a light sample toward triangle T whose
 * shadow ray glass blocks goes on through it (lv_light_seen_through), and a
 * path that leaves x along w, crosses the same glass and hits T finds the
 * same light. Both weigh it by the power heuristic between x's density of
 * w and the light sample's density of the straight half-line from x along
 * w, which must meet T's front face; both follow the delta lobes alike, so
 * those choices' odds cancel, and the two weights sum to 1 wherever both
 * can find the light. Where only the path can (the straight half-line
 * misses T, the chain turns, or is too long) its weight stays 1. */

/* A camera path's chain of delta scatters since its last vertex x that
 * sampled lights. */
#define LV_CHAIN_NONE 0xffffffffu
typedef struct {
    float3 from;   /* x */
    float3 dir;    /* the way the path left x */
    float pdf;     /* that direction's density at x, as x's light sample weighs it */
    uint scatters; /* delta scatters since x that light is still seen through, or LV_CHAIN_NONE */
} lv_glass_chain;

/* The chain of a path that left x along dir with density pdf, where
 * lights are sampled and seen through glass (on) or not. */
inline lv_glass_chain lv_glass_chain_start(float3 x, float3 dir, float pdf, int on)
{
    lv_glass_chain c;
    c.from = x;
    c.dir = dir;
    c.pdf = pdf;
    c.scatters = on ? 0u : LV_CHAIN_NONE;
    return c;
}

/* The chain after a delta scatter at surface s (material m) that left
 * along dir. */
inline void lv_glass_chain_step(lv_glass_chain *c, __global const lv_material *m, const lv_surface *s, float3 dir)
{
    c->scatters = c->scatters < LV_SEE_THROUGH_MAX && lv_still_seen_through(m, s, 1, dir, c->dir) ? c->scatters + 1u
                                                                                                 : LV_CHAIN_NONE;
}

/* The MIS weight of emission that a path arriving along dir right after a
 * delta scatter found at h (front normal ng): the power heuristic against
 * the light sample at the chain's start where that sample could have seen
 * the same point through the glass, else 1. */
inline float lv_glass_chain_weight(const lv_scene *sc, const lv_glass_chain *c, lv_hit h, float3 dir, float3 ng)
{
    if (c->scatters < 1u || c->scatters > LV_SEE_THROUGH_MAX || !lv_same_direction(dir, c->dir) ||
        !(dot(c->dir, ng) < 0.0f))
        return 1.0f;
    float3 v0, v1, v2;
    lv_triangle_world(sc, h.inst, h.tri, &v0, &v1, &v2);
    lv_hit straight = h;
    straight.t = lv_half_line_crossing(c->from, c->dir, v0, v1 - v0, v2 - v0);
    if (!(straight.t > 0.0f)) return 1.0f;
    return lv_power_heuristic(c->pdf, lv_light_pdf(sc, straight, c->dir, ng));
}

/* The light a camera path's shadow ray r brings: its own where nothing
 * blocks it, else what it finds through glass within r->see_through
 * scatters, on a random stream of its own (r->chain_key), so that a
 * wavefront's shadow kernel draws the same numbers as the megakernel. */
inline float3 lv_shadow_ray_light(const lv_scene *sc, const lv_shadow_ray *r)
{
    if (!lv_shadow_ray_blocked(sc, r)) return r->li;
    if (!r->see_through) return (float3)(0.0f);
    lv_rng chain = lv_rng_keyed(r->chain_key);
    return lv_light_seen_through(sc, r, r->li, r->see_through, &chain);
}

/* Direct light at a vertex of a gather's camera path (surface s, hit h)
 * from one light sample, MIS-weighted against BSDF sampling, and where its
 * shadow ray is blocked, the sampled lamp seen through up to see_through
 * glass scatters: without MIS weight at a gather point, whose BSDF rays
 * stop at glass and read the volume, so they never find this light; with
 * it where the path goes on (path_goes_on), whose glass chain then weighs
 * what it finds alike. Draws three numbers, and more only on glass. */
inline float3 lv_gather_direct_light(const lv_scene *sc, const lv_surface *s, lv_hit h, const lv_shading *sh,
                                     uint see_through, int path_goes_on, lv_rng *rng)
{
    lv_shadow_ray r;
    if (!lv_light_sample_ray(sc, s, h, sh, 0, rng, &r)) return (float3)(0.0f);
    if (!lv_shadow_ray_blocked(sc, &r)) return r.li;
    return see_through ? lv_light_seen_through(sc, &r, path_goes_on ? r.li : r.li / r.mis, see_through, rng)
                       : (float3)(0.0f);
}

#endif
