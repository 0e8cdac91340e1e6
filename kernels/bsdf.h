/* BSDFs of DESIGN.md section 3, in a local frame whose +z is the shading
 * normal. Opaque BSDFs expect wo.z > 0 (the caller turns the frame to the
 * viewer's side); dielectrics keep +z on the outside (front) face.
 *
 * Conventions: lv_bsdf_eval returns f(wo, wi) |cos wi| for the non-delta
 * lobes; lv_bsdf_pdf the solid-angle density with which lv_bsdf_sample picks
 * wi through those lobes; lv_bsdf_sample returns weight = f |cos| / pdf for
 * the direction it picked (delta lobes included, with pdf 0 and delta 1).
 * `mode` says whether radiance (camera paths) or importance (particles)
 * flows, which matters only for the 1/eta^2 scaling of refraction. */
#ifndef LV_BSDF_H
#define LV_BSDF_H

#include "util/geometry.h"
#include "util/sampling.h"
#include "shared_types.h"

#define LV_RADIANCE 0
#define LV_IMPORTANCE 1

/* Below this GGX alpha a surface is treated as perfectly smooth. */
#define LV_SMOOTH_ALPHA 1e-3f

typedef struct {
    uint type;     /* LV_BSDF_* */
    float3 base;   /* base colour, textured */
    float alpha;   /* GGX roughness */
    float ior;
    float specular;
} lv_bsdf;

typedef struct {
    float3 wi;
    float3 weight;
    float pdf;
    int delta;
} lv_bsdf_sample;

/* ---- Fresnel ---- */

inline float3 lv_schlick3(float3 f0, float cos_theta)
{
    float m = clamp(1.0f - cos_theta, 0.0f, 1.0f);
    float m2 = m * m;
    return f0 + (1.0f - f0) * (m2 * m2 * m);
}

/* Unpolarised Fresnel reflectance of a dielectric interface; eta is the
 * inside index over the outside one and cos_i is taken from the outside
 * normal (negative: the light arrives from inside). */
inline float lv_fresnel_dielectric(float cos_i, float eta)
{
    cos_i = clamp(cos_i, -1.0f, 1.0f);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
    }
    float sin2_t = (1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 1.0f;
    float cos_t = sqrt(fmax(0.0f, 1.0f - sin2_t));
    float rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    float rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    return 0.5f * (rs * rs + rp * rp);
}

/* Refracts w (pointing away from the surface) about n; eta as above. On
 * success writes the refracted direction and eta' = n_t / n_i. */
inline int lv_refract(float3 w, float3 n, float eta, float3 *wt, float *etap)
{
    float cos_i = dot(n, w);
    if (cos_i < 0.0f) {
        eta = 1.0f / eta;
        cos_i = -cos_i;
        n = -n;
    }
    float sin2_t = fmax(0.0f, 1.0f - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0f) return 0;
    float cos_t = sqrt(1.0f - sin2_t);
    *wt = -w / eta + (cos_i / eta - cos_t) * n;
    *etap = eta;
    return 1;
}

inline float3 lv_reflect(float3 w, float3 n)
{
    return 2.0f * dot(w, n) * n - w;
}

/* ---- GGX (Trowbridge-Reitz) microfacets, isotropic ---- */

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
    float p1 = r * cos(phi), p2 = r * sin(phi);
    float s = 0.5f * (1.0f + vh.z);
    p2 = (1.0f - s) * sqrt(fmax(0.0f, 1.0f - p1 * p1)) + s * p2;
    float3 nh = p1 * t1 + p2 * t2 + sqrt(fmax(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
    return normalize((float3)(alpha * nh.x, alpha * nh.y, fmax(1e-6f, nh.z)));
}

/* f |cos wi| of a GGX reflection lobe without its Fresnel factor. */
inline float lv_ggx_reflection(float3 wo, float3 wi, float alpha)
{
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float3 m = normalize(wo + wi);
    return lv_ggx_d(m, alpha) * lv_ggx_g2(wo, wi, alpha) / (4.0f * wo.z);
}

inline float lv_ggx_reflection_pdf(float3 wo, float3 wi, float alpha)
{
    if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
    float3 m = normalize(wo + wi);
    return lv_ggx_visible_pdf(wo, m, alpha) / (4.0f * fabs(dot(wo, m)));
}

/* ---- glTF dielectric over diffuse ("plastic") ---- */

inline float3 lv_plastic_fresnel(const lv_bsdf *b, float cos_theta)
{
    float f0 = (b->ior - 1.0f) / (b->ior + 1.0f);
    return b->specular * lv_schlick3((float3)(f0 * f0), cos_theta);
}

/* Probability of sampling the specular layer, from how much each layer
 * would reflect toward wo. */
inline float lv_plastic_specular_probability(const lv_bsdf *b, float3 wo)
{
    float fs = lv_luminance(lv_plastic_fresnel(b, wo.z));
    float fd = (1.0f - fs) * lv_luminance(b->base);
    return fs + fd > 0.0f ? clamp(fs / (fs + fd), 0.05f, 0.95f) : 0.5f;
}

/* ---- the dispatchers ---- */

inline float3 lv_bsdf_eval(const lv_bsdf *b, float3 wo, float3 wi, int mode)
{
    switch (b->type) {
    case LV_BSDF_DIFFUSE:
        return wo.z > 0.0f && wi.z > 0.0f ? b->base * (wi.z * LV_INV_PI) : (float3)(0.0f);
    case LV_BSDF_PLASTIC: {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return (float3)(0.0f);
        /* Light reaching the diffuse base crosses the layer twice, so the base
         * is weighted by (1 - F) at both angles: reciprocal, and it never
         * reflects more than the layer lets through (the glTF formula, which
         * uses (1 - F) at the half vector, exceeds 1 at grazing angles). */
        float3 r = (1.0f - lv_plastic_fresnel(b, wo.z)) * (1.0f - lv_plastic_fresnel(b, wi.z)) * b->base *
                   (wi.z * LV_INV_PI);
        if (b->alpha >= LV_SMOOTH_ALPHA) {
            float3 m = normalize(wo + wi);
            r += lv_plastic_fresnel(b, dot(wo, m)) * lv_ggx_reflection(wo, wi, b->alpha);
        }
        return r;
    }
    case LV_BSDF_CONDUCTOR: {
        if (b->alpha < LV_SMOOTH_ALPHA || wo.z <= 0.0f || wi.z <= 0.0f) return (float3)(0.0f);
        float3 m = normalize(wo + wi);
        return lv_schlick3(b->base, dot(wo, m)) * lv_ggx_reflection(wo, wi, b->alpha);
    }
#ifdef LV_FEATURE_GLASS
    case LV_BSDF_GLASS: {
        if (b->alpha < LV_SMOOTH_ALPHA || wo.z == 0.0f || wi.z == 0.0f) return (float3)(0.0f);
        int reflect = wo.z * wi.z > 0.0f;
        float etap = reflect ? 1.0f : (wo.z > 0.0f ? b->ior : 1.0f / b->ior);
        float3 m = wi * etap + wo;
        if (dot(m, m) == 0.0f) return (float3)(0.0f);
        m = normalize(m);
        if (m.z < 0.0f) m = -m;
        if (dot(m, wi) * wi.z < 0.0f || dot(m, wo) * wo.z < 0.0f) return (float3)(0.0f);
        float fr = lv_fresnel_dielectric(dot(wo, m), b->ior);
        float d = lv_ggx_d(m, b->alpha), g = lv_ggx_g2(wo, wi, b->alpha);
        if (reflect) return (float3)(fr * d * g / (4.0f * fabs(wo.z)));
        float denom = dot(wi, m) + dot(wo, m) / etap;
        float f = (1.0f - fr) * d * g * fabs(dot(wi, m) * dot(wo, m) / (wo.z * denom * denom));
        if (mode == LV_RADIANCE) f /= etap * etap;
        return (float3)(f);
    }
#endif
    default:
        return (float3)(0.0f);
    }
}

inline float lv_bsdf_pdf(const lv_bsdf *b, float3 wo, float3 wi)
{
    switch (b->type) {
    case LV_BSDF_DIFFUSE:
        return wo.z > 0.0f && wi.z > 0.0f ? wi.z * LV_INV_PI : 0.0f;
    case LV_BSDF_PLASTIC: {
        if (wo.z <= 0.0f || wi.z <= 0.0f) return 0.0f;
        float ps = lv_plastic_specular_probability(b, wo);
        float pdf = (1.0f - ps) * wi.z * LV_INV_PI;
        if (b->alpha >= LV_SMOOTH_ALPHA) pdf += ps * lv_ggx_reflection_pdf(wo, wi, b->alpha);
        return pdf;
    }
    case LV_BSDF_CONDUCTOR:
        return b->alpha < LV_SMOOTH_ALPHA ? 0.0f : lv_ggx_reflection_pdf(wo, wi, b->alpha);
#ifdef LV_FEATURE_GLASS
    case LV_BSDF_GLASS: {
        if (b->alpha < LV_SMOOTH_ALPHA || wo.z == 0.0f || wi.z == 0.0f) return 0.0f;
        int reflect = wo.z * wi.z > 0.0f;
        float etap = reflect ? 1.0f : (wo.z > 0.0f ? b->ior : 1.0f / b->ior);
        float3 m = wi * etap + wo;
        if (dot(m, m) == 0.0f) return 0.0f;
        m = normalize(m);
        if (m.z < 0.0f) m = -m;
        if (dot(m, wi) * wi.z < 0.0f || dot(m, wo) * wo.z < 0.0f) return 0.0f;
        float fr = lv_fresnel_dielectric(dot(wo, m), b->ior);
        float pm = lv_ggx_visible_pdf(wo, m, b->alpha);
        if (reflect) return pm / (4.0f * fabs(dot(wo, m))) * fr;
        float denom = dot(wi, m) + dot(wo, m) / etap;
        return pm * fabs(dot(wi, m)) / (denom * denom) * (1.0f - fr);
    }
#endif
    default:
        return 0.0f;
    }
}

/* Fills s from eval and pdf for a direction picked through non-delta lobes. */
inline int lv_bsdf_finish_sample(const lv_bsdf *b, float3 wo, float3 wi, int mode, lv_bsdf_sample *s)
{
    s->wi = wi;
    s->delta = 0;
    s->pdf = lv_bsdf_pdf(b, wo, wi);
    if (!(s->pdf > 0.0f)) return 0;
    s->weight = lv_bsdf_eval(b, wo, wi, mode) / s->pdf;
    return 1;
}

inline int lv_bsdf_sample_delta(float3 wi, float3 weight, lv_bsdf_sample *s)
{
    s->wi = wi;
    s->weight = weight;
    s->pdf = 0.0f;
    s->delta = 1;
    return 1;
}

/* u: three uniform numbers. Returns 0 if no direction was produced. */
inline int lv_bsdf_sample_dir(const lv_bsdf *b, float3 wo, float3 u, int mode, lv_bsdf_sample *s)
{
    const float3 mirror = (float3)(-wo.x, -wo.y, wo.z);
    switch (b->type) {
    case LV_BSDF_DIFFUSE:
        if (wo.z <= 0.0f) return 0;
        s->wi = lv_sample_cosine_hemisphere(u.xy);
        s->pdf = s->wi.z * LV_INV_PI;
        s->weight = b->base;
        s->delta = 0;
        return s->pdf > 0.0f;
    case LV_BSDF_PLASTIC: {
        if (wo.z <= 0.0f) return 0;
        float ps = lv_plastic_specular_probability(b, wo);
        if (u.z < ps) {
            if (b->alpha < LV_SMOOTH_ALPHA)
                return lv_bsdf_sample_delta(mirror, lv_plastic_fresnel(b, wo.z) / ps, s);
            float3 wi = lv_reflect(wo, lv_ggx_sample_visible(wo, b->alpha, u.xy));
            return wi.z > 0.0f && lv_bsdf_finish_sample(b, wo, wi, mode, s);
        }
        return lv_bsdf_finish_sample(b, wo, lv_sample_cosine_hemisphere(u.xy), mode, s);
    }
    case LV_BSDF_CONDUCTOR: {
        if (wo.z <= 0.0f) return 0;
        if (b->alpha < LV_SMOOTH_ALPHA) return lv_bsdf_sample_delta(mirror, lv_schlick3(b->base, wo.z), s);
        float3 m = lv_ggx_sample_visible(wo, b->alpha, u.xy);
        float3 wi = lv_reflect(wo, m);
        if (wi.z <= 0.0f) return 0;
        s->wi = wi;
        s->delta = 0;
        s->pdf = lv_ggx_reflection_pdf(wo, wi, b->alpha);
        s->weight = lv_schlick3(b->base, dot(wo, m)) * (lv_ggx_g2(wo, wi, b->alpha) / lv_ggx_g1(wo, b->alpha));
        return s->pdf > 0.0f;
    }
#ifdef LV_FEATURE_GLASS
    case LV_BSDF_GLASS: {
        if (wo.z == 0.0f) return 0;
        if (b->alpha < LV_SMOOTH_ALPHA) {
            float fr = lv_fresnel_dielectric(wo.z, b->ior);
            if (u.z < fr) return lv_bsdf_sample_delta(mirror, (float3)(1.0f), s);
            float3 wi;
            float etap;
            if (!lv_refract(wo, (float3)(0.0f, 0.0f, 1.0f), b->ior, &wi, &etap)) return 0;
            float scale = mode == LV_RADIANCE ? 1.0f / (etap * etap) : 1.0f;
            return lv_bsdf_sample_delta(wi, (float3)(scale), s);
        }
        float3 m = lv_ggx_sample_visible(wo, b->alpha, u.xy);
        float fr = lv_fresnel_dielectric(dot(wo, m), b->ior);
        float3 wi;
        if (u.z < fr) {
            wi = lv_reflect(wo, m);
            if (wi.z * wo.z <= 0.0f) return 0;
        } else {
            float etap;
            if (!lv_refract(wo, m, b->ior, &wi, &etap) || wi.z * wo.z >= 0.0f) return 0;
        }
        return lv_bsdf_finish_sample(b, wo, wi, mode, s);
    }
    case LV_BSDF_THIN_GLASS: {
        float r = lv_fresnel_dielectric(fabs(wo.z), b->ior);
        /* Light bounces inside the thin sheet; summing the geometric series
         * gives the total reflectance 2R / (1 + R). */
        if (r < 1.0f) r = 2.0f * r / (1.0f + r);
        if (u.z < r) return lv_bsdf_sample_delta(mirror, (float3)(1.0f), s);
        return lv_bsdf_sample_delta(-wo, (float3)(1.0f), s);
    }
#endif
    default:
        return 0;
    }
}

/* True if the BSDF has a non-delta lobe, so light sampling can help. */
inline int lv_bsdf_has_smooth_lobe(const lv_bsdf *b)
{
    switch (b->type) {
    case LV_BSDF_DIFFUSE:
    case LV_BSDF_PLASTIC:
        return 1;
    case LV_BSDF_CONDUCTOR:
    case LV_BSDF_GLASS:
        return b->alpha >= LV_SMOOTH_ALPHA;
    default:
        return 0;
    }
}

/* Opaque BSDFs reflect only; dielectrics also transmit. */
inline int lv_bsdf_transmits(uint type)
{
    return type == LV_BSDF_GLASS || type == LV_BSDF_THIN_GLASS;
}

#endif
