/* glTF's dielectric over diffuse ("plastic"): a Lambertian base under a
 * GGX or, below LV_SMOOTH_ALPHA, smooth dielectric coat whose Fresnel term
 * is Schlick's, scaled by KHR_materials_specular. Included by
 * closure/bsdf.h, after lv_bsdf. */
#ifndef LV_CLOSURE_PLASTIC_H
#define LV_CLOSURE_PLASTIC_H

#include "../util/sampling.h"
#include "fresnel.h"
#include "microfacet.h"

inline float3 lv_plastic_fresnel(const lv_bsdf *b, float cos_theta)
{
    float f0 = (b->ior - 1.0f) / (b->ior + 1.0f);
    return b->specular * lv_schlick3((float3)(f0 * f0), cos_theta);
}

/* Probability of sampling the coat, from how much each layer would
 * reflect toward wo. */
inline float lv_plastic_coat_probability(const lv_bsdf *b, float3 wo)
{
    float fs = lv_luminance(lv_plastic_fresnel(b, wo.z));
    float fd = (1.0f - fs) * lv_luminance(b->base);
    return fs + fd > 0.0f ? clamp(fs / (fs + fd), 0.05f, 0.95f) : 0.5f;
}

inline float3 lv_plastic_value(const lv_bsdf *b, float3 wo, float3 wi)
{
    if (wo.z <= 0.0f || wi.z <= 0.0f) return (float3)(0.0f);
    /* Light reaching the diffuse base crosses the coat twice, so the base
     * is weighted by (1 - F) at both angles: reciprocal, and it never
     * reflects more than the coat lets through (the glTF formula, which
     * uses (1 - F) at the half vector, exceeds 1 at grazing angles). */
    float3 r =
        (1.0f - lv_plastic_fresnel(b, wo.z)) * (1.0f - lv_plastic_fresnel(b, wi.z)) * b->base * (wi.z * LV_INV_PI);
    if (b->alpha >= LV_SMOOTH_ALPHA) {
        float3 m = normalize(wo + wi);
        r += lv_plastic_fresnel(b, dot(wo, m)) * lv_ggx_reflection(wo, wi, b->alpha);
    }
    return r;
}

inline float lv_plastic_pdf(const lv_bsdf *b, float3 wo, float3 wi)
{
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float pc = lv_plastic_coat_probability(b, wo);
    float pdf = (1.0f - pc) * wi.z * LV_INV_PI;
    if (b->alpha >= LV_SMOOTH_ALPHA) pdf += pc * lv_ggx_reflection_pdf(wo, wi, b->alpha);
    return pdf;
}

inline float3 lv_plastic_eval(const lv_bsdf *b, float3 wo, float3 wi, float *pdf)
{
    if (pdf) *pdf = lv_plastic_pdf(b, wo, wi);
    return lv_plastic_value(b, wo, wi);
}

inline int lv_plastic_sample(const lv_bsdf *b, float3 wo, float3 u, lv_bsdf_sample *s)
{
    if (wo.z <= 0.0f) return 0;
    float pc = lv_plastic_coat_probability(b, wo);
    float3 wi;
    if (u.z < pc) {
        if (b->alpha < LV_SMOOTH_ALPHA) return lv_bsdf_sample_delta(lv_mirror(wo), lv_plastic_fresnel(b, wo.z) / pc, s);
        wi = lv_reflect(wo, lv_ggx_sample_visible(wo, b->alpha, u.xy));
        if (wi.z <= 0.0f) return 0;
    } else {
        wi = lv_sample_cosine_hemisphere(u.xy);
    }
    float pdf = lv_plastic_pdf(b, wo, wi);
    return pdf > 0.0f && lv_bsdf_sample_lobe(wi, lv_plastic_value(b, wo, wi), pdf, s);
}

#endif
