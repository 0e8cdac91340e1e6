/* The glTF material contract of DESIGN.md section 3: maps a material as the
 * file describes it to one of the kernels' BSDF families. */
#ifndef LVCL_MATERIALS_H
#define LVCL_MATERIALS_H

#include "scene.h"

/* Fills *out from *desc. Warns (once per material) where glTF allows more
 * than lvcl renders, naming the approximation. */
void lvcl_material_from_desc(const lvcl_material_desc *desc, size_t index, lv_material *out);

/* LVCL_FEATURE_* bits the scene needs (host/device/program.h). */
unsigned lvcl_scene_features(const lvcl_scene *scene);

#endif
