/* Thin-walled glass (a window pane): mirror reflection and straight
 * transmission, both delta lobes, so there is nothing to evaluate. The
 * base colour tints what passes through, not what is reflected (glTF's
 * KHR_materials_transmission).
 * Included by closure/bsdf.h, after lv_bsdf. */
#ifndef LV_CLOSURE_THIN_DIELECTRIC_H
#define LV_CLOSURE_THIN_DIELECTRIC_H

#include "fresnel.h"

inline int lv_thin_dielectric_sample(const lv_bsdf *b, float3 wo, float u, lv_bsdf_sample *s)
{
    float r = lv_fresnel_dielectric(fabs(wo.z), b->ior);
    /* Light bounces inside the thin sheet; summing the geometric series
     * gives the total reflectance 2R / (1 + R). */
    if (r < 1.0f) r = 2.0f * r / (1.0f + r);
    if (u < r) return lv_bsdf_sample_delta(lv_mirror(wo), (float3)(1.0f), s);
    return lv_bsdf_sample_delta(-wo, b->base, s);
}

#endif
