/* The path-tracing pass: one work-item per pixel of the range [first_pixel,
 * first_pixel + pixel_count) (a tile, or the whole image), one sample per
 * launch, added to a running sum per pixel (no atomics: each pixel has one
 * owner). */
#include "../lvcl.h"

__kernel void lv_pt_pass(LV_KERNEL_PARAMS(LV_PT_PASS_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= pixel_count) return;
    uint pixel = first_pixel + (uint)get_global_id(0);
    lv_rng rng = lv_rng_make_lattice(sc.info.seed, pixel, sample_index);
    lv_ray r = lv_camera_ray(camera, pixel % camera.width, pixel / camera.width, lv_rng_next2(&rng));
    float3 l = lv_path_trace(&sc, r, &rng, sc.info.max_depth);
    sum[pixel] += (float4)(l, 1.0f);
}
