/* The final gather (paper section 5; integrator/gather.h): camera rays,
 * one sample per pixel of the range [first_pixel, first_pixel + pixel_count)
 * per launch, with the light volume answering at rough surfaces. */
#include "../lvcl.h"

__kernel void lv_gather_pass(LV_KERNEL_PARAMS(LV_GATHER_PASS_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= pixel_count) return;
    uint pixel = first_pixel + (uint)get_global_id(0);
    lv_gather g;
    LV_VOLUME_OPEN(g.grid);
    g.bin_table = bin_table;
    g.flags = flags;
    g.threshold = threshold;
    lv_rng rng = lv_rng_make_lattice(sc.info.seed, pixel, sample_index);
    lv_ray r = lv_camera_ray(camera, pixel % camera.width, pixel / camera.width, lv_rng_next2(&rng));
    float3 l = lv_gather_radiance(&sc, r, &rng, sc.info.max_depth, &g);
    sum[pixel] += (float4)(l, 1.0f);
}
