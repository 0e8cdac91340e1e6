/* Lambertian reflection. Included by closure/bsdf.h, after lv_bsdf. */
#ifndef LV_CLOSURE_DIFFUSE_H
#define LV_CLOSURE_DIFFUSE_H

#include "../util/sampling.h"

inline float3 lv_diffuse_eval(const lv_bsdf *b, float3 wo, float3 wi, float *pdf)
{
    int above = wo.z > 0.0f && wi.z > 0.0f;
    if (pdf) *pdf = above ? wi.z * LV_INV_PI : 0.0f;
    return above ? b->base * (wi.z * LV_INV_PI) : (float3)(0.0f);
}

inline int lv_diffuse_sample(const lv_bsdf *b, float3 wo, float2 u, lv_bsdf_sample *s)
{
    if (wo.z <= 0.0f) return 0;
    s->wi = lv_sample_cosine_hemisphere(u);
    s->pdf = s->wi.z * LV_INV_PI;
    s->weight = b->base;
    s->delta = 0;
    return s->pdf > 0.0f;
}

#endif
