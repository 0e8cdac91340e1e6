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
    g.axis_sums = axis_sums;
    g.flags = flags;
    g.threshold = threshold;
    lv_camera_sample cs = lv_camera_sample_next(camera, sc.info.seed, pixel_list, first_pixel, first_sample, sum);
    float3 l = lv_gather_radiance(&sc, cs.ray, &cs.rng, sc.info.max_depth, &g);
    lv_camera_sample_add(sum, sum_sq, cs.pixel, l);
}

/* One work-item per slot and axis: the axis sums (integrator/gather.h),
 * once the trace is done. */
__kernel void lv_axis_sums(LV_KERNEL_PARAMS(LV_AXIS_SUMS_ARGS))
{
    uint id = get_global_id(0), slot = id / LV_AXES, axis = id % LV_AXES;
    if (slot >= grid_info.slot_count) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    lv_bin_tables tables = {bin_table, fine_bin_table};
    vstore3(lv_axis_sum(&grid, &tables, slot, axis), id, axis_sums);
}
