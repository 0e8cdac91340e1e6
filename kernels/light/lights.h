/* Light sampling for next-event estimation: one light chosen by the light
 * table's odds (pdf_select: part power, part an even share per emissive
 * material), then a point on it (area lights) or its position (punctual
 * lights). */
#ifndef LV_LIGHTS_H
#define LV_LIGHTS_H

#include "../util/sampling.h"
#include "../scene/surface.h"

typedef struct {
    float3 wi;     /* unit direction from the shading point to the light */
    float3 target; /* the point on the light, for the shadow ray */
    float3 li;     /* incident radiance (area) or irradiance-like I / d^2 (punctual) */
    float pdf;     /* solid-angle density, including the selection probability */
    int delta;     /* punctual: no MIS, pdf holds only the selection probability */
    uint light;    /* the light's index in sc->lights */
} lv_light_sample;

/* Index of the light whose cumulative-probability interval holds u. */
inline uint lv_pick_light(const lv_scene *sc, float u)
{
    uint lo = 0, hi = sc->info.light_count - 1;
    while (lo < hi) {
        uint mid = (lo + hi) / 2;
        if (sc->lights[mid].cdf > u) hi = mid;
        else lo = mid + 1;
    }
    return lo;
}

/* A point uniformly distributed on an area light (from u), its front
 * normal (unit) and the light's area, all in world space. */
inline float3 lv_sample_area_light(const lv_scene *sc, lv_light light, float2 u, float3 *n, float *area)
{
    float3 v0, v1, v2;
    float front_sign = lv_triangle_world(sc, light.instance, light.index, &v0, &v1, &v2);
    float2 b = lv_sample_triangle(u);
    float3 e1 = v1 - v0, e2 = v2 - v0;
    float3 c = cross(e1, e2);
    *area = 0.5f * length(c);
    *n = front_sign * normalize(c);
    return v0 + b.x * e1 + b.y * e2;
}

#ifdef LV_FEATURE_PUNCTUAL
/* glTF's spot cone: smooth between the outer and inner angles. */
inline float lv_spot_falloff(lv_punctual_light l, float3 from_light)
{
    if (l.type != LV_PUNCTUAL_SPOT) return 1.0f;
    float scale = 1.0f / fmax(0.001f, l.cos_inner - l.cos_outer);
    float a = clamp((dot(LV_F3(l.direction), from_light) - l.cos_outer) * scale, 0.0f, 1.0f);
    return a * a;
}
#endif

inline int lv_sample_light(const lv_scene *sc, float3 p, float3 u, lv_light_sample *ls)
{
    if (sc->info.light_count == 0) return 0;
    uint i = lv_pick_light(sc, u.z);
    lv_light light = sc->lights[i];
    ls->light = i;
#ifdef LV_FEATURE_PUNCTUAL
    if (light.kind == LV_LIGHT_PUNCTUAL) {
        lv_punctual_light l = sc->punctuals[light.index];
        if (l.type == LV_PUNCTUAL_DIRECTIONAL) {
            /* Toward the light, far enough to leave the scene's sphere. */
            ls->wi = -LV_F3(l.direction);
            ls->target = p + ls->wi * (4.0f * sc->info.bounds_radius + length(p - LV_F3(sc->info.bounds_centre)));
            ls->li = LV_F3(l.intensity);
            ls->pdf = light.pdf_select;
            ls->delta = 1;
            return 1;
        }
        float3 d = LV_F3(l.position) - p;
        float dist2 = dot(d, d);
        if (!(dist2 > 0.0f)) return 0;
        ls->wi = d * rsqrt(dist2);
        ls->target = LV_F3(l.position);
        ls->li = LV_F3(l.intensity) * (lv_spot_falloff(l, -ls->wi) / dist2);
        ls->pdf = light.pdf_select;
        ls->delta = 1;
        return 1;
    }
#endif
    float3 n;
    float area;
    float3 q = lv_sample_area_light(sc, light, u.xy, &n, &area);
    float3 d = q - p;
    float dist2 = dot(d, d);
    if (!(dist2 > 0.0f) || !(area > 0.0f)) return 0;
    ls->wi = d * rsqrt(dist2);
    float cos_l = -dot(ls->wi, n);
    if (cos_l <= 0.0f) return 0; /* emitters shine from their front face only */
    ls->target = lv_offset_origin(q, n, sc->info.scene_scale);
    ls->li = LV_F3(sc->materials[lv_triangle_record(sc, light.index).material].emission);
    ls->pdf = light.pdf_select * lv_area_to_solid_angle(1.0f / area, dist2, cos_l);
    ls->delta = 0;
    return 1;
}

/* The solid-angle density with which lv_sample_light would have picked the
 * point where a ray from p along unit dir hit h, an emissive triangle, at
 * distance h.t; ng is its front normal. */
inline float lv_light_pdf(const lv_scene *sc, lv_hit h, float3 dir, float3 ng)
{
    uint emitter = lv_triangle_record(sc, h.tri).light;
    if (emitter == LV_NO_LIGHT) return 0.0f;
    float3 v0, v1, v2;
    lv_triangle_world(sc, h.inst, h.tri, &v0, &v1, &v2);
    float area = 0.5f * length(cross(v1 - v0, v2 - v0));
    lv_light light = sc->lights[sc->instances[h.inst].light_base + emitter];
    return light.pdf_select * lv_area_to_solid_angle(1.0f / area, h.t * h.t, dot(dir, ng));
}

/* A particle leaving a light: where, which way, and its power relative to
 * the total emitted power (luminance watts) over the odds of its light, so
 * that particles carry equal shares where the odds are the power shares
 * and at most twice that elsewhere. */
typedef struct {
    float3 origin;
    float3 dir;
    float3 weight;
    uint triangle; /* the emitting triangle, or LV_NO_HIT for punctual lights */
    uint instance; /* and its instance */
    uint light;    /* the light's index in sc->lights */
} lv_emission_sample;

inline int lv_sample_emission(const lv_scene *sc, float2 u_light, float2 u_dir, float u_pick, lv_emission_sample *es)
{
    if (sc->info.light_count == 0 || !(sc->info.total_light_power > 0.0f)) return 0;
    uint i = lv_pick_light(sc, u_pick);
    lv_light light = sc->lights[i];
    es->light = i;
    float select_power = light.pdf_select * sc->info.total_light_power;
#ifdef LV_FEATURE_PUNCTUAL
    if (light.kind == LV_LIGHT_PUNCTUAL) {
        lv_punctual_light l = sc->punctuals[light.index];
        es->origin = LV_F3(l.position);
        es->triangle = es->instance = LV_NO_HIT;
        float3 intensity = LV_F3(l.intensity);
        if (l.type == LV_PUNCTUAL_DIRECTIONAL) {
            /* Parallel light from a disc as wide as the scene's sphere, in
             * front of it: weight = E pi R^2 / (probability x total power). */
            float r = sc->info.bounds_radius;
            es->dir = LV_F3(l.direction);
            float2 disc = r * lv_square_to_disk(u_light);
            lv_frame f = lv_frame_make(es->dir);
            es->origin = LV_F3(sc->info.bounds_centre) + lv_to_world(f, (float3)(disc, -r));
            es->weight = intensity * (LV_PI * r * r) / select_power;
        } else if (l.type == LV_PUNCTUAL_SPOT) {
            /* Uniform over the outer cone, pdf 1 / (2 pi (1 - cos_outer)). */
            float z = 1.0f - u_dir.x * (1.0f - l.cos_outer);
            float r = sqrt(fmax(0.0f, 1.0f - z * z)), phi = 2.0f * LV_PI * u_dir.y;
            lv_frame f = lv_frame_make(LV_F3(l.direction));
            es->dir = lv_to_world(f, (float3)(r * lv_cos_sin(phi), z));
            es->weight = intensity * lv_spot_falloff(l, es->dir) * (2.0f * LV_PI * (1.0f - l.cos_outer)) / select_power;
        } else {
            float z = 1.0f - 2.0f * u_dir.x;
            float r = sqrt(fmax(0.0f, 1.0f - z * z)), phi = 2.0f * LV_PI * u_dir.y;
            es->dir = (float3)(r * lv_cos_sin(phi), z);
            es->weight = intensity * (4.0f * LV_PI) / select_power;
        }
        return 1;
    }
#endif
    /* Uniform on the triangle, cosine-distributed about its front normal:
     * weight = Le pi A / (probability of this light x total power). */
    float3 n;
    float area;
    float3 q = lv_sample_area_light(sc, light, u_light, &n, &area);
    es->origin = lv_offset_origin(q, n, sc->info.scene_scale);
    es->triangle = light.index;
    es->instance = light.instance;
    es->dir = lv_to_world(lv_frame_make(n), lv_sample_cosine_hemisphere(u_dir));
    float3 le = LV_F3(sc->materials[lv_triangle_record(sc, light.index).material].emission);
    es->weight = le * (LV_PI * area / select_power);
    return 1;
}

#endif
