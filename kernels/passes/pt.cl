/* The path-tracing pass: one work-item per pixel of the launch's list (a
 * band, the whole image, or the pixels adaptive sampling chose), one
 * sample each, added to a running sum per pixel (no atomics: each pixel has
 * one owner). */
#include "../lvcl.h"

__kernel void lv_pt_pass(LV_KERNEL_PARAMS(LV_PT_PASS_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= pixel_count) return;
    lv_camera_sample cs = lv_camera_sample_next(camera, sc.info.seed, pixel_list, first_pixel, first_sample, sum);
    float3 l = lv_path_trace(&sc, 0, cs.ray, &cs.rng, sc.info.max_depth, see_through);
    lv_camera_sample_add(sum, sum_sq, cs.pixel, l);
}
