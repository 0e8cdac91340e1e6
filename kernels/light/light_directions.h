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

/* Candidate triangles per surface point: the area lights at evenly spaced
 * quantiles of the lights' power distribution. */
#define LV_LIGHT_CANDIDATES 4

typedef struct {
    float3 v0[LV_LIGHT_CANDIDATES], e1[LV_LIGHT_CANDIDATES], e2[LV_LIGHT_CANDIDATES];
    float3 n[LV_LIGHT_CANDIDATES]; /* front normal times twice the area: cross(e1, e2), signed */
    float cdf[LV_LIGHT_CANDIDATES]; /* running sum of the candidates' probabilities, the last 1 */
    uint count;
} lv_light_candidates;

/* The candidates' triangles, at the power quantiles (k + 1/2) / K (the same
 * light may come twice). Punctual lights have no area to aim at and are
 * left out. Their probabilities are the caller's (lv_light_candidates_weigh). */
inline uint lv_light_candidates_pick(const lv_scene *sc, lv_light_candidates *c)
{
    c->count = 0;
    if (sc->info.light_count == 0) return 0;
    for (uint k = 0; k < LV_LIGHT_CANDIDATES; k++) {
        lv_light light = sc->lights[lv_pick_light(sc, ((float)k + 0.5f) / (float)LV_LIGHT_CANDIDATES)];
#ifdef LV_FEATURE_PUNCTUAL
        if (light.kind == LV_LIGHT_PUNCTUAL) continue;
#endif
        float3 v0, v1, v2;
        float front_sign = lv_triangle_world(sc, light.instance, light.index, &v0, &v1, &v2);
        uint i = c->count++;
        c->v0[i] = v0;
        c->e1[i] = v1 - v0;
        c->e2[i] = v2 - v0;
        c->n[i] = front_sign * cross(c->e1[i], c->e2[i]);
    }
    return c->count;
}

/* Sets the candidates' probabilities from weights w (count of them);
 * returns 0 where they are all zero. */
inline int lv_light_candidates_weigh(lv_light_candidates *c, const float *w)
{
    float total = 0.0f;
    for (uint k = 0; k < c->count; k++) total += w[k];
    if (!(total > 0.0f) || !isfinite(total)) return 0;
    float run = 0.0f;
    for (uint k = 0; k < c->count; k++) {
        run += w[k];
        c->cdf[k] = run / total;
    }
    c->cdf[c->count - 1] = 1.0f;
    return 1;
}

inline float lv_light_candidate_probability(const lv_light_candidates *c, uint k)
{
    return k == 0 ? c->cdf[0] : c->cdf[k] - c->cdf[k - 1];
}

/* Solid-angle density, per unit probability of candidate k, of the point
 * where the half-line from p along unit dir crosses its front face; 0 if it
 * does not. */
inline float lv_light_candidate_density(const lv_light_candidates *c, uint k, float3 p, float3 dir)
{
    float facing = -dot(dir, c->n[k]); /* twice the area times the light's cosine */
    if (!(facing > 0.0f)) return 0.0f;
    float3 pv = cross(dir, c->e2[k]);
    float det = dot(c->e1[k], pv), inv = 1.0f / det;
    float3 s = p - c->v0[k];
    float b1 = dot(s, pv) * inv;
    if (b1 < 0.0f || b1 > 1.0f) return 0.0f;
    float3 qv = cross(s, c->e1[k]);
    float b2 = dot(dir, qv) * inv;
    if (b2 < 0.0f || b1 + b2 > 1.0f) return 0.0f;
    float t = dot(c->e2[k], qv) * inv;
    return t > 0.0f ? 2.0f * t * t / facing : 0.0f;
}

/* The density of lv_light_candidates_sample at unit direction dir from p. */
inline float lv_light_candidates_pdf(const lv_light_candidates *c, float3 p, float3 dir)
{
    float pdf = 0.0f;
    for (uint k = 0; k < c->count; k++) {
        float pk = lv_light_candidate_probability(c, k);
        if (pk > 0.0f) pdf += pk * lv_light_candidate_density(c, k, p, dir);
    }
    return pdf;
}

/* A direction from p toward a point uniform on a candidate picked by its
 * probability (by u.x; the point by u.yz); *pdf is the density over all
 * candidates. Returns 0 where the point's face looks away from p. */
inline int lv_light_candidates_sample(const lv_light_candidates *c, float3 p, float3 u, float3 *dir, float *pdf)
{
    uint k = 0;
    while (k + 1 < c->count && u.x >= c->cdf[k]) k++;
    float2 b = lv_sample_triangle(u.yz);
    float3 d = c->v0[k] + b.x * c->e1[k] + b.y * c->e2[k] - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f)) return 0;
    *dir = d * rsqrt(dist2);
    float facing = -dot(*dir, c->n[k]);
    if (!(facing > 0.0f)) return 0;
    /* The sampled candidate's own density in closed form (the crossing test
     * could miss a point on its edge), the others' by crossing. */
    float own = lv_light_candidate_probability(c, k);
    *pdf = own * 2.0f * dist2 / facing;
    for (uint j = 0; j < c->count; j++) {
        float pj = lv_light_candidate_probability(c, j);
        if (j != k && pj > 0.0f) *pdf += pj * lv_light_candidate_density(c, j, p, *dir);
    }
    return *pdf > 0.0f && isfinite(*pdf);
}

#endif
