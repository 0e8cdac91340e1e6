/* Directions toward a few emitter triangles, as a way to continue a path
 * (not as light samples). Where a shadow ray to a lamp is blocked by a
 * glass table top or a window pane, a path that leaves a rough surface
 * toward the lamp passes the glass, shifted sideways by a fraction of its
 * thickness, and most often still reaches the lamp. Its density at a
 * direction counts each candidate triangle that the half-line from the
 * point crosses, whatever lies between, so a one-sample mixture that holds
 * it stays unbiased (docs/guided.md, "Toward the lights"). */
#ifndef LV_LIGHT_DIRECTIONS_H
#define LV_LIGHT_DIRECTIONS_H

#include "lights.h"

/* The most candidate triangles: the area lights at evenly spaced quantiles
 * of the light table's odds, each once. */
#define LV_LIGHT_CANDIDATES 4

/* The candidates' triangles in world space; the same for every point, so
 * picked once per work-item. */
typedef struct {
    float3 v0[LV_LIGHT_CANDIDATES], e1[LV_LIGHT_CANDIDATES], e2[LV_LIGHT_CANDIDATES];
    float3 n[LV_LIGHT_CANDIDATES]; /* front normal times twice the area: cross(e1, e2), signed */
    uint count;
} lv_light_candidates;

/* How likely each candidate is at one point: the running sum of their
 * probabilities, the last 1. */
typedef struct {
    float cdf[LV_LIGHT_CANDIDATES];
} lv_light_odds;

/* Picks the area lights at the table's quantiles (k + 1/2) / K, each once.
 * Punctual lights have no area to aim at and are left out. */
inline uint lv_light_candidates_pick(const lv_scene *sc, lv_light_candidates *c)
{
    c->count = 0;
    uint picked[LV_LIGHT_CANDIDATES];
    for (uint k = 0; k < LV_LIGHT_CANDIDATES && sc->info.light_count > 0; k++) {
        uint index = lv_pick_light(sc, ((float)k + 0.5f) / (float)LV_LIGHT_CANDIDATES);
        lv_light light = sc->lights[index];
        int seen = 0;
        for (uint j = 0; j < c->count; j++) seen |= picked[j] == index;
#ifdef LV_FEATURE_PUNCTUAL
        seen |= light.kind == LV_LIGHT_PUNCTUAL;
#endif
        if (seen) continue;
        float3 v0, v1, v2;
        float front_sign = lv_triangle_world(sc, light.instance, light.index, &v0, &v1, &v2);
        uint i = c->count++;
        picked[i] = index;
        c->v0[i] = v0;
        c->e1[i] = v1 - v0;
        c->e2[i] = v2 - v0;
        c->n[i] = front_sign * cross(c->e1[i], c->e2[i]);
    }
    return c->count;
}

/* The odds of c's candidates from weights w, one each; returns 0 where
 * they are all zero. */
inline int lv_light_odds_set(const lv_light_candidates *c, const float *w, lv_light_odds *odds)
{
    float total = 0.0f;
    for (uint k = 0; k < c->count; k++) total += w[k];
    if (!(total > 0.0f) || !isfinite(total)) return 0;
    float run = 0.0f;
    for (uint k = 0; k < c->count; k++) {
        run += w[k];
        odds->cdf[k] = run / total;
    }
    odds->cdf[c->count - 1] = 1.0f;
    return 1;
}

inline float lv_light_odds_of(const lv_light_odds *odds, uint k)
{
    return k == 0 ? odds->cdf[0] : odds->cdf[k] - odds->cdf[k - 1];
}

/* Solid-angle density, per unit probability of candidate k, of the point
 * where the half-line from p along unit dir crosses its front face; 0 if it
 * does not. */
inline float lv_light_candidate_density(const lv_light_candidates *c, uint k, float3 p, float3 dir)
{
    float facing = -dot(dir, c->n[k]); /* twice the area times the light's cosine */
    if (!(facing > 0.0f)) return 0.0f;
    float t = lv_half_line_crossing(p, dir, c->v0[k], c->e1[k], c->e2[k]);
    return 2.0f * t * t / facing;
}

/* The density of lv_light_directions_sample at unit direction dir from p,
 * leaving out candidate `skip` (none: c->count). */
inline float lv_light_directions_pdf_but(const lv_light_candidates *c, const lv_light_odds *odds, float3 p, float3 dir,
                                         uint skip)
{
    float pdf = 0.0f;
    for (uint k = 0; k < c->count; k++) {
        float pk = lv_light_odds_of(odds, k);
        if (k != skip && pk > 0.0f) pdf += pk * lv_light_candidate_density(c, k, p, dir);
    }
    return pdf;
}

inline float lv_light_directions_pdf(const lv_light_candidates *c, const lv_light_odds *odds, float3 p, float3 dir)
{
    return lv_light_directions_pdf_but(c, odds, p, dir, c->count);
}

/* A direction from p toward a point uniform on a candidate picked by its
 * odds (by u.x; the point by u.yz); *pdf is the density over all
 * candidates. Returns 0 where the point's face looks away from p. */
inline int lv_light_directions_sample(const lv_light_candidates *c, const lv_light_odds *odds, float3 p, float3 u,
                                      float3 *dir, float *pdf)
{
    uint k = 0;
    while (k + 1 < c->count && u.x >= odds->cdf[k]) k++;
    float2 b = lv_sample_triangle(u.yz);
    float3 d = c->v0[k] + b.x * c->e1[k] + b.y * c->e2[k] - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return 0;
    *dir = d * rsqrt(dist2);
    float facing = -dot(*dir, c->n[k]);
    if (!(facing > 0.0f)) return 0;
    /* The sampled candidate's own density in closed form (the crossing test
     * could miss a point on its edge), the others' by crossing. */
    *pdf = lv_light_odds_of(odds, k) * 2.0f * dist2 / facing + lv_light_directions_pdf_but(c, odds, p, *dir, k);
    return *pdf > 0.0f && isfinite(*pdf);
}

#endif
