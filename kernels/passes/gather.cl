/* The final gather (paper section 5; integrator/gather.h): camera rays,
 * one sample per pixel of the launch's list (as pt.cl), with the light
 * volume answering at rough surfaces. */
#include "../lvcl.h"

__kernel void lv_gather_pass(LV_KERNEL_PARAMS(LV_GATHER_PASS_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= pixel_count) return;
    lv_gather g;
    LV_VOLUME_OPEN(g.grid);
    g.tables.coarse = bin_table;
    g.tables.fine = fine_bin_table;
    g.flags = flags;
    g.threshold = threshold;
    lv_camera_sample cs = lv_camera_sample_next(camera, sc.info.seed, pixel_list, first_pixel, first_sample, sum);
    float3 l = lv_gather_radiance(&sc, cs.ray, &cs.rng, sc.info.max_depth, &g);
    lv_camera_sample_add(sum, sum_sq, cs.pixel, l);
}
