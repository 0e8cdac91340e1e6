/* The glTF material contract (docs/design.md, Scene conventions): maps a
 * material as the file describes it to one of the kernels' BSDF families,
 * and says which optional kernel code a scene needs. */
#ifndef LVCL_MATERIALS_H
#define LVCL_MATERIALS_H

#include "scene.h"

/* Fills *out from *desc. Warns (once per material) where glTF allows more
 * than lvcl renders, naming the approximation. */
void lvcl_material_from_desc(const lvcl_material_desc *desc, size_t index, lv_material *out);

/* Feature switches: kernel code a scene does not use is left out of the
 * build (host/device/program.c turns them into -D options). */
#define LVCL_FEATURE_GLASS 1u    /* solid and thin dielectrics */
#define LVCL_FEATURE_TEXTURES 2u /* base-colour textures */
#define LVCL_FEATURE_PUNCTUAL 4u /* point and spot lights */

/* LVCL_FEATURE_* bits the scene needs. */
unsigned lvcl_scene_features(const lvcl_scene *scene);

#endif
