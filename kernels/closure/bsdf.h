/* BSDFs (docs/design.md, "Kernels"), one family per file, in a local frame
 * whose +z is the shading normal. Opaque BSDFs expect wo.z > 0 (the caller
 * turns the frame to the viewer's side); dielectrics keep +z on the outside
 * (front) face.
 *
 * Conventions: a family's eval returns f(wo, wi) |cos wi| for its
 * non-delta lobes and, where its pdf argument is not null, the solid-angle
 * density with which its sample picks wi through those lobes; callers that
 * need only the value pass null, and inlining drops the density's
 * arithmetic. Families whose sampling must check that density before it
 * pays for the value build eval from a _value and a _pdf half. sample
 * returns weight = f |cos| / pdf for the direction it picked (delta lobes
 * included, with pdf 0 and delta 1). `mode` says whether radiance (camera
 * paths) or importance (particles) flows, which matters only for the
 * 1/eta^2 scaling of refraction.
 *
 * A new family: its file (eval and sample), a case in each switch at the
 * bottom, and its row in lv_bsdf_traits. */
#ifndef LV_BSDF_H
#define LV_BSDF_H

#include "../util/geometry.h"
#include "../shared_types.h"

#define LV_RADIANCE 0
#define LV_IMPORTANCE 1

/* Below this GGX alpha a surface is treated as perfectly smooth. */
#define LV_SMOOTH_ALPHA 1e-3f

typedef struct {
    uint type;   /* LV_BSDF_* */
    float3 base; /* base colour, textured */
    float alpha; /* GGX roughness */
    float ior;
    float specular;
} lv_bsdf;

typedef struct {
    float3 wi;
    float3 weight;
    float pdf;
    int delta;
    float eta_scale; /* the factor 1/eta'^2 that weight holds where radiance refracts, else 1 (roulette undoes it) */
} lv_bsdf_sample;

inline int lv_bsdf_sample_delta(float3 wi, float3 weight, lv_bsdf_sample *s)
{
    s->wi = wi;
    s->weight = weight;
    s->pdf = 0.0f;
    s->delta = 1;
    s->eta_scale = 1.0f;
    return 1;
}

/* Fills s for a direction wi picked through non-delta lobes, given the
 * family's f |cos| and density (> 0) there. */
inline int lv_bsdf_sample_lobe(float3 wi, float3 fcos, float pdf, lv_bsdf_sample *s)
{
    s->wi = wi;
    s->delta = 0;
    s->pdf = pdf;
    s->weight = fcos / pdf;
    s->eta_scale = 1.0f;
    return 1;
}

#include "conductor.h"
#include "dielectric.h"
#include "diffuse.h"
#include "plastic.h"
#include "thin_dielectric.h"

/* ---- what each family is, as data ---- */

#define LV_TRAIT_LOBE 1u             /* a non-delta lobe at any roughness */
#define LV_TRAIT_LOBE_IF_ROUGH 2u    /* a non-delta lobe from LV_SMOOTH_ALPHA on, delta below */
#define LV_TRAIT_TRANSMITS 4u        /* lets light through (opaque ones reflect only) */
#define LV_TRAIT_GATHER 8u           /* the light volume may answer for the light it reflects */
#define LV_TRAIT_GATHER_IF_ROUGH 16u /* the same from LV_GATHER_MIN_ALPHA on */
#define LV_TRAIT_DELTA 32u           /* a delta lobe at any roughness */
#define LV_TRAIT_DELTA_IF_SMOOTH 64u /* a delta lobe below LV_SMOOTH_ALPHA */

/* Rough enough that the light volume answers for the light a coat or metal
 * reflects; smoother surfaces continue the path (paper section 5). Smooth
 * dielectric coats would also lose their delta lobe in the integrating
 * gather. */
#define LV_GATHER_MIN_ALPHA 0.1f

__constant uint lv_bsdf_traits[LV_BSDF_COUNT] = {
    [LV_BSDF_DIFFUSE] = LV_TRAIT_LOBE | LV_TRAIT_GATHER,
    [LV_BSDF_PLASTIC] = LV_TRAIT_LOBE | LV_TRAIT_GATHER_IF_ROUGH | LV_TRAIT_DELTA_IF_SMOOTH,
    [LV_BSDF_CONDUCTOR] = LV_TRAIT_LOBE_IF_ROUGH | LV_TRAIT_GATHER_IF_ROUGH | LV_TRAIT_DELTA_IF_SMOOTH,
    [LV_BSDF_GLASS] = LV_TRAIT_LOBE_IF_ROUGH | LV_TRAIT_TRANSMITS | LV_TRAIT_DELTA_IF_SMOOTH,
    [LV_BSDF_THIN_GLASS] = LV_TRAIT_TRANSMITS | LV_TRAIT_DELTA,
};

inline uint lv_bsdf_traits_of(uint type)
{
    return type < LV_BSDF_COUNT ? lv_bsdf_traits[type] : 0u;
}

/* True if the BSDF has a non-delta lobe, so light sampling can help. */
inline int lv_bsdf_has_lobe(const lv_bsdf *b)
{
    uint t = lv_bsdf_traits_of(b->type);
    return (t & LV_TRAIT_LOBE) || ((t & LV_TRAIT_LOBE_IF_ROUGH) && b->alpha >= LV_SMOOTH_ALPHA);
}

/* True if a BSDF of this family and roughness has a delta lobe, which a
 * sample may pick. */
inline int lv_bsdf_delta_at(uint type, float alpha)
{
    uint t = lv_bsdf_traits_of(type);
    return (t & LV_TRAIT_DELTA) || ((t & LV_TRAIT_DELTA_IF_SMOOTH) && alpha < LV_SMOOTH_ALPHA);
}

inline int lv_bsdf_has_delta(const lv_bsdf *b)
{
    return lv_bsdf_delta_at(b->type, b->alpha);
}

inline int lv_bsdf_transmits(uint type)
{
    return (lv_bsdf_traits_of(type) & LV_TRAIT_TRANSMITS) != 0u;
}

/* Whether the final gather may let the light volume answer at a surface of
 * this family and roughness (taken from the material, before its BSDF is
 * built). */
inline int lv_bsdf_gathers(uint type, float alpha)
{
    uint t = lv_bsdf_traits_of(type);
    return (t & LV_TRAIT_GATHER) || ((t & LV_TRAIT_GATHER_IF_ROUGH) && alpha >= LV_GATHER_MIN_ALPHA);
}

/* ---- the dispatchers ---- */

inline float3 lv_bsdf_eval(const lv_bsdf *b, float3 wo, float3 wi, int mode, float *pdf)
{
    switch (b->type) {
    case LV_BSDF_DIFFUSE:
        return lv_diffuse_eval(b, wo, wi, pdf);
    case LV_BSDF_PLASTIC:
        return lv_plastic_eval(b, wo, wi, pdf);
    case LV_BSDF_CONDUCTOR:
        return lv_conductor_eval(b, wo, wi, pdf);
#ifdef LV_FEATURE_GLASS
    case LV_BSDF_GLASS:
        return lv_dielectric_eval(b, wo, wi, mode, pdf);
#endif
    default: /* delta lobes only */
        if (pdf) *pdf = 0.0f;
        return (float3)(0.0f);
    }
}

/* u: three uniform numbers. Returns 0 if no direction was produced. */
inline int lv_bsdf_sample_dir(const lv_bsdf *b, float3 wo, float3 u, int mode, lv_bsdf_sample *s)
{
    s->eta_scale = 1.0f; /* only a dielectric's refraction changes it */
    switch (b->type) {
    case LV_BSDF_DIFFUSE:
        return lv_diffuse_sample(b, wo, u.xy, s);
    case LV_BSDF_PLASTIC:
        return lv_plastic_sample(b, wo, u, s);
    case LV_BSDF_CONDUCTOR:
        return lv_conductor_sample(b, wo, u.xy, s);
#ifdef LV_FEATURE_GLASS
    case LV_BSDF_GLASS:
        return lv_dielectric_sample(b, wo, u, mode, s);
    case LV_BSDF_THIN_GLASS:
        return lv_thin_dielectric_sample(b, wo, u.z, s);
#endif
    default:
        return 0;
    }
}

#endif
