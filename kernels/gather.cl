/* The final gather (paper section 5; integrator/gather.h): camera rays,
 * one sample per pixel of the range [first_pixel, first_pixel + pixel_count)
 * per launch, with the light volume answering at rough surfaces. */
#include "lvcl.h"

__kernel void lv_gather_pass(LV_SCENE_PARAMS, lv_grid_info grid_info, __global const uint *cell_slot,
                             __global long *tallies0, __global long *tallies1, __global long *tallies2,
                             __global long *tallies3, __global uint *subcells,
                             __global const float *lit_volume,
                             __global const float4 *bin_directions, uint flags,
                             float threshold, lv_camera camera, uint first_pixel, uint pixel_count,
                             uint sample_index, __global float4 *sum)
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= pixel_count) return;
    uint pixel = first_pixel + (uint)get_global_id(0);
    lv_gather g;
    g.grid.g = grid_info;
    g.grid.cell_slot = cell_slot;
    g.grid.subcells = subcells;
    g.grid.lit_volume = lit_volume;
    g.grid.tallies[0] = tallies0;
    g.grid.tallies[1] = tallies1;
    g.grid.tallies[2] = tallies2;
    g.grid.tallies[3] = tallies3;
    g.bin_directions = bin_directions;
    g.flags = flags;
    g.threshold = threshold;
    lv_rng rng = lv_rng_make(sc.info.seed, pixel, sample_index);
    lv_ray r = lv_camera_ray(camera, pixel % camera.width, pixel / camera.width, lv_rng_next2(&rng));
    float3 l = lv_gather_radiance(&sc, r, &rng, sc.info.max_depth, &g);
    sum[pixel] += (float4)(l, 1.0f);
}
