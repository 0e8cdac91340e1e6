/* GGX (Trowbridge-Reitz) microfacets, isotropic, in the local frame whose
 * +z is the shading normal: the distribution, masking-shadowing, sampling
 * of visible normals and the Fresnel-free reflection lobe built on them. */
#ifndef LV_CLOSURE_MICROFACET_H
#define LV_CLOSURE_MICROFACET_H

#include "../util/geometry.h"
#include "../util/sampling.h"

inline float lv_ggx_d(float3 m, float alpha)
{
    float a2 = alpha * alpha;
    float c2 = m.z * m.z;
    float k = c2 * (a2 - 1.0f) + 1.0f;
    return a2 / (LV_PI * k * k);
}

inline float lv_ggx_lambda(float3 w, float alpha)
{
    float c2 = w.z * w.z;
    if (c2 <= 0.0f) return 0.0f;
    float t2 = fmax(0.0f, 1.0f - c2) / c2;
    return 0.5f * (sqrt(1.0f + alpha * alpha * t2) - 1.0f);
}

inline float lv_ggx_g1(float3 w, float alpha)
{
    return 1.0f / (1.0f + lv_ggx_lambda(w, alpha));
}

/* Height-correlated masking-shadowing, as the glTF specification uses. */
inline float lv_ggx_g2(float3 wo, float3 wi, float alpha)
{
    return 1.0f / (1.0f + lv_ggx_lambda(wo, alpha) + lv_ggx_lambda(wi, alpha));
}

/* Density of the visible normal m seen from wo (both in the upper hemisphere). */
inline float lv_ggx_visible_pdf(float3 wo, float3 m, float alpha)
{
    float cos_o = fabs(wo.z);
    if (cos_o == 0.0f) return 0.0f;
    return lv_ggx_g1(wo, alpha) * fabs(dot(wo, m)) * lv_ggx_d(m, alpha) / cos_o;
}

/* Samples a visible normal (Heitz 2018); wo is flipped to the upper
 * hemisphere first, and the normal returned has m.z >= 0. */
inline float3 lv_ggx_sample_visible(float3 wo, float alpha, float2 u)
{
    if (wo.z < 0.0f) wo = -wo;
    float3 vh = normalize((float3)(alpha * wo.x, alpha * wo.y, wo.z));
    float len2 = vh.x * vh.x + vh.y * vh.y;
    float3 t1 = len2 > 0.0f ? (float3)(-vh.y, vh.x, 0.0f) * rsqrt(len2) : (float3)(1.0f, 0.0f, 0.0f);
    float3 t2 = cross(vh, t1);
    float r = sqrt(u.x), phi = 2.0f * LV_PI * u.y;
    float2 cs = r * lv_cos_sin(phi);
    float p1 = cs.x, p2 = cs.y;
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * p2;
    float3 nh = p1 * t1 + p2 * t2 + sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return normalize((float3)(alpha * nh.x, alpha * nh.y, fmax(1e-6f, nh.z)));
}

/* The density with which reflecting wo about a visible normal picks wi. */
inline float lv_ggx_reflection_pdf(float3 wo, float3 wi, float alpha)
{
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float3 m = normalize(wo + wi);
    return lv_ggx_visible_pdf(wo, m, alpha) / (4.0f * fabs(dot(wo, m)));
}

/* f |cos wi| of a GGX reflection lobe without its Fresnel factor. */
inline float lv_ggx_reflection(float3 wo, float3 wi, float alpha)
{
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float3 m = normalize(wo + wi);
    return lv_ggx_d(m, alpha) * lv_ggx_g2(wo, wi, alpha) / (4.0f * wo.z);
}

#endif
