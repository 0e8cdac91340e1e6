/* Solid glass: a dielectric interface, GGX-rough (Walter et al. 2007) or,
 * below LV_SMOOTH_ALPHA, smooth; +z is the outside (front) face and b->ior
 * the inside index over the outside one. Refraction scales radiance by
 * 1/eta'^2, importance not (`mode`), and the base colour tints it at each
 * crossing (glTF's KHR_materials_transmission; reflection keeps its
 * colour). Beer-Lambert absorption inside is the integrators' business.
 * Included by closure/bsdf.h, after lv_bsdf. */
#ifndef LV_CLOSURE_DIELECTRIC_H
#define LV_CLOSURE_DIELECTRIC_H

#include "fresnel.h"
#include "microfacet.h"

/* The microfacet normal m (m.z >= 0) that turns wo into wi, by reflection
 * (*reflect) or refraction with eta' = *etap; 0 if none does, or if m
 * would face away from either direction's side. */
inline int lv_dielectric_half_vector(const lv_bsdf *b, float3 wo, float3 wi, float3 *m, float *etap, int *reflect)
{
    *reflect = wo.z * wi.z > 0.0f;
    *etap = *reflect ? 1.0f : (wo.z > 0.0f ? b->ior : 1.0f / b->ior);
    float3 h = wi * *etap + wo;
    if (dot(h, h) == 0.0f) return 0;
    h = normalize(h);
    if (h.z < 0.0f) h = -h;
    if (dot(h, wi) * wi.z < 0.0f || dot(h, wo) * wo.z < 0.0f) return 0;
    *m = h;
    return 1;
}

inline float3 lv_dielectric_value(const lv_bsdf *b, float3 wo, float3 wi, int mode)
{
    float3 m;
    float etap;
    int reflect;
    if (b->alpha < LV_SMOOTH_ALPHA || wo.z == 0.0f || wi.z == 0.0f ||
        !lv_dielectric_half_vector(b, wo, wi, &m, &etap, &reflect))
        return (float3)(0.0f);
    float fr = lv_fresnel_dielectric(dot(wo, m), b->ior);
    float d = lv_ggx_d(m, b->alpha), g = lv_ggx_g2(wo, wi, b->alpha);
    if (reflect) return (float3)(fr * d * g / (4.0f * fabs(wo.z)));
    float denom = dot(wi, m) + dot(wo, m) / etap;
    float f = (1.0f - fr) * d * g * fabs(dot(wi, m) * dot(wo, m) / (wo.z * denom * denom));
    if (mode == LV_RADIANCE) f /= etap * etap;
    return f * b->base;
}

inline float lv_dielectric_pdf(const lv_bsdf *b, float3 wo, float3 wi)
{
    float3 m;
    float etap;
    int reflect;
    if (b->alpha < LV_SMOOTH_ALPHA || wo.z == 0.0f || wi.z == 0.0f ||
        !lv_dielectric_half_vector(b, wo, wi, &m, &etap, &reflect))
        return 0.0f;
    float fr = lv_fresnel_dielectric(dot(wo, m), b->ior);
    float pm = lv_ggx_visible_pdf(wo, m, b->alpha);
    if (reflect) return pm / (4.0f * fabs(dot(wo, m))) * fr;
    float denom = dot(wi, m) + dot(wo, m) / etap;
    return pm * fabs(dot(wi, m)) / (denom * denom) * (1.0f - fr);
}

inline float3 lv_dielectric_eval(const lv_bsdf *b, float3 wo, float3 wi, int mode, float *pdf)
{
    if (pdf) *pdf = lv_dielectric_pdf(b, wo, wi);
    return lv_dielectric_value(b, wo, wi, mode);
}

inline int lv_dielectric_sample(const lv_bsdf *b, float3 wo, float3 u, int mode, lv_bsdf_sample *s)
{
    if (wo.z == 0.0f) return 0;
    float3 wi;
    float etap;
    if (b->alpha < LV_SMOOTH_ALPHA) {
        float fr = lv_fresnel_dielectric(wo.z, b->ior);
        if (u.z < fr) return lv_bsdf_sample_delta(lv_mirror(wo), (float3)(1.0f), s);
        if (!lv_refract(wo, (float3)(0.0f, 0.0f, 1.0f), b->ior, &wi, &etap)) return 0;
        float scale = mode == LV_RADIANCE ? 1.0f / (etap * etap) : 1.0f;
        lv_bsdf_sample_delta(wi, scale * b->base, s);
        s->eta_scale = scale;
        return 1;
    }
    float3 m = lv_ggx_sample_visible(wo, b->alpha, u.xy);
    float fr = lv_fresnel_dielectric(dot(wo, m), b->ior);
    etap = 1.0f;
    if (u.z < fr) {
        wi = lv_reflect(wo, m);
        if (wi.z * wo.z <= 0.0f) return 0;
    } else {
        if (!lv_refract(wo, m, b->ior, &wi, &etap) || wi.z * wo.z >= 0.0f) return 0;
    }
    float pdf = lv_dielectric_pdf(b, wo, wi);
    if (!(pdf > 0.0f) || !lv_bsdf_sample_lobe(wi, lv_dielectric_value(b, wo, wi, mode), pdf, s)) return 0;
    s->eta_scale = mode == LV_RADIANCE ? 1.0f / (etap * etap) : 1.0f;
    return 1;
}

#endif
