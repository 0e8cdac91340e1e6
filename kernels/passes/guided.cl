/* Guided path tracing (--mode guided; integrator/path_tracer.h with the
 * light volume as a guide, volume/guide.h): the guide table, once after
 * the trace, then camera rays, one sample per pixel of the launch's list,
 * as pt.cl. */
#include "../lvcl.h"

__kernel void lv_guide_table(LV_KERNEL_PARAMS(LV_GUIDE_TABLE_ARGS))
{
    uint i = get_global_id(0), bins = grid_info.bins;
    if (i >= grid_info.tally_sets * bins + LV_BIN_GROUP) return;
    if (i >= grid_info.tally_sets * bins) {
        guide_table[i] = 0.0f; /* the padding lv_guide_group reads past the last set */
        return;
    }
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    guide_table[i] = lv_guide_luminance(lv_tally_set(&grid, i / bins) + (size_t)(i % bins) * 3);
}

__kernel void lv_guided_pass(LV_KERNEL_PARAMS(LV_GUIDED_PASS_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= pixel_count) return;
    lv_guide g;
    LV_VOLUME_OPEN(g.grid);
    g.bin_table = bin_table;
    g.fine_bin_table = fine_bin_table;
    g.luminance = guide_table;
    lv_camera_sample cs = lv_camera_sample_next(camera, sc.info.seed, pixel_list, first_pixel, first_sample, sum);
    float3 l = lv_path_trace(&sc, &g, cs.ray, &cs.rng, sc.info.max_depth);
    lv_camera_sample_add(sum, sum_sq, cs.pixel, l);
}
