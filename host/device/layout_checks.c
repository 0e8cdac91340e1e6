/* The shared structs' sizes as the kernels see them (kernels/shared_types.h):
 * 32-bit fields only (all but lv_light and lv_cell_cut a multiple of 16 bytes), so that C11 and
 * OpenCL C lay them out alike. Checked at compile time; no code. */
#include "../../kernels/shared_types.h"

_Static_assert(sizeof(lv_wide_node) == 128, "lv_wide_node");
_Static_assert(sizeof(lv_triangle) == 32, "lv_triangle");
_Static_assert(sizeof(lv_instance) == 112, "lv_instance");
_Static_assert(sizeof(lv_material) == 96, "lv_material");
_Static_assert(sizeof(lv_texture) == 16, "lv_texture");
_Static_assert(sizeof(lv_light) == 24, "lv_light");
_Static_assert(sizeof(lv_punctual_light) == 48, "lv_punctual_light");
_Static_assert(sizeof(lv_camera) == 64, "lv_camera");
_Static_assert(sizeof(lv_scene_info) == 64, "lv_scene_info");
_Static_assert(sizeof(lv_grid_info) == 64, "lv_grid_info");
_Static_assert(sizeof(lv_slot_region) == 32, "lv_slot_region");
_Static_assert(sizeof(lv_cell_cut) == 164, "lv_cell_cut");
_Static_assert(sizeof(lv_float4) == 16 && sizeof(lv_ushort4) == 8, "vector storage");

/* An otherwise empty translation unit is not ISO C. */
typedef int lvcl_layout_checks_unit;
