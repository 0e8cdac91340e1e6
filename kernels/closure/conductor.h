/* Metal: GGX or, below LV_SMOOTH_ALPHA, mirror reflection with Schlick's
 * Fresnel term, F0 = the base colour. Included by closure/bsdf.h, after
 * lv_bsdf. */
#ifndef LV_CLOSURE_CONDUCTOR_H
#define LV_CLOSURE_CONDUCTOR_H

#include "fresnel.h"
#include "microfacet.h"

inline float3 lv_conductor_value(const lv_bsdf *b, float3 wo, float3 wi)
{
    if (b->alpha < LV_SMOOTH_ALPHA || wo.z <= 0.0f || wi.z <= 0.0f) return (float3)(0.0f);
    float3 m = normalize(wo + wi);
    return lv_schlick3(b->base, dot(wo, m)) * lv_ggx_reflection(wo, wi, b->alpha);
}

inline float3 lv_conductor_eval(const lv_bsdf *b, float3 wo, float3 wi, float *pdf)
{
    if (pdf) *pdf = b->alpha < LV_SMOOTH_ALPHA ? 0.0f : lv_ggx_reflection_pdf(wo, wi, b->alpha);
    return lv_conductor_value(b, wo, wi);
}

inline int lv_conductor_sample(const lv_bsdf *b, float3 wo, float2 u, lv_bsdf_sample *s)
{
    if (wo.z <= 0.0f) return 0;
    if (b->alpha < LV_SMOOTH_ALPHA) return lv_bsdf_sample_delta(lv_mirror(wo), lv_schlick3(b->base, wo.z), s);
    float3 m = lv_ggx_sample_visible(wo, b->alpha, u);
    float3 wi = lv_reflect(wo, m);
    if (wi.z <= 0.0f) return 0;
    s->wi = wi;
    s->delta = 0;
    s->pdf = lv_ggx_reflection_pdf(wo, wi, b->alpha);
    /* f |cos| / pdf of visible-normal sampling leaves F G2 / G1. */
    s->weight = lv_schlick3(b->base, dot(wo, m)) * (lv_ggx_g2(wo, wi, b->alpha) / lv_ggx_g1(wo, b->alpha));
    return s->pdf > 0.0f;
}

#endif
