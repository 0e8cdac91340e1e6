#include "materials.h"

#include <math.h>
#include <string.h>

void lvcl_material_from_desc(const lvcl_material_desc *d, size_t index, lv_material *m)
{
    memset(m, 0, sizeof *m);
    for (int k = 0; k < 3; k++) {
        m->base_color[k] = d->base_color[k];
        m->emission[k] = d->emissive[k];
    }
    m->base_color_texture = d->base_color_texture;
    m->texture_sampling = d->texture_sampling;
    static const float identity[6] = {1, 0, 0, 0, 1, 0};
    memcpy(m->uv_transform, d->has_uv_transform ? d->uv_transform : identity, sizeof m->uv_transform);
    m->alpha = d->roughness * d->roughness;
    m->ior = d->ior > 1.0f ? d->ior : 1.0f;
    m->specular = d->specular;
    m->double_sided = d->double_sided != 0;

    if (d->transmission > 0.0f) {
        if (d->transmission < 1.0f)
            lvcl_warn("material %zu: transmission %.2f rendered as fully transmissive", index, d->transmission);
        if (d->ior <= 1.0f) {
            lvcl_warn("material %zu: ior %.3f <= 1 rendered as 1.5", index, d->ior);
            m->ior = 1.5f;
        }
        m->bsdf = d->has_volume ? LV_BSDF_GLASS : LV_BSDF_THIN_GLASS;
        /* Beer-Lambert: light keeps attenuation_color after attenuation_distance. */
        if (d->has_volume && isfinite(d->attenuation_distance) && d->attenuation_distance > 0.0f)
            for (int k = 0; k < 3; k++)
                m->attenuation[k] = -logf(fmaxf(d->attenuation_color[k], 1e-6f)) / d->attenuation_distance;
        return;
    }
    if (d->metallic > 0.0f && d->metallic < 1.0f)
        lvcl_warn("material %zu: metallic %.2f rendered as %s", index, d->metallic,
                  d->metallic >= 0.5f ? "metal" : "dielectric");
    if (d->metallic >= 0.5f) m->bsdf = LV_BSDF_CONDUCTOR;
    else if (d->specular == 0.0f) m->bsdf = LV_BSDF_DIFFUSE;
    else m->bsdf = LV_BSDF_PLASTIC;
}

unsigned lvcl_scene_features(const lvcl_scene *scene)
{
    unsigned f = 0;
    if (scene->punctual_count) f |= LVCL_FEATURE_PUNCTUAL;
    for (size_t i = 0; i < scene->material_count; i++) {
        const lvcl_material_desc *d = &scene->materials[i];
        if (d->transmission > 0.0f) f |= LVCL_FEATURE_GLASS;
        if (d->base_color_texture >= 0) f |= LVCL_FEATURE_TEXTURES;
    }
    return f;
}
