/* Guided path tracing (--mode guided; integrator/path_tracer.h with the
 * light volume as a guide, volume/guide.h): the guide table, once after
 * the trace, then camera rays, one sample per pixel of the launch's list,
 * as pt.cl. */
#include "../lvcl.h"

/* One work-item per tally set: its bins' luminance, then its sum and
 * largest; one more writes the padding. */
__kernel void lv_guide_table(LV_KERNEL_PARAMS(LV_GUIDE_TABLE_ARGS))
{
    uint set = get_global_id(0), bins = grid_info.bins;
    if (set > grid_info.tally_sets) return;
    if (set == grid_info.tally_sets) {
        for (uint l = 0; l < LV_BIN_GROUP; l++) guide_table[(size_t)set * bins + l] = 0.0f;
        return;
    }
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    __global const long *t = lv_tally_set(&grid, set);
    __global float *out = guide_table + (size_t)set * bins;
    float sum = 0.0f, top = 0.0f;
    for (uint b = 0; b < bins; b++) {
        float l = lv_guide_luminance(t + 3 * (size_t)b);
        out[b] = l;
        sum += l;
        top = fmax(top, l);
    }
    __global float *stats = guide_table + LV_GUIDE_STATS_AT(grid_info) + 2 * (size_t)set;
    stats[0] = sum;
    stats[1] = top;
}

__kernel void lv_guided_pass(LV_KERNEL_PARAMS(LV_GUIDED_PASS_ARGS))
{
    LV_SCENE_OPEN(sc);
    if (get_global_id(0) >= pixel_count) return;
    lv_guide g;
    LV_VOLUME_OPEN(g.grid);
    g.tables.coarse = bin_table;
    g.tables.fine = fine_bin_table;
    g.luminance = guide_table;
    g.stats = guide_table + LV_GUIDE_STATS_AT(grid_info);
    lv_camera_sample cs = lv_camera_sample_next(camera, sc.info.seed, pixel_list, first_pixel, first_sample, sum);
    float3 l = lv_path_trace(&sc, &g, cs.ray, &cs.rng, sc.info.max_depth);
    lv_camera_sample_add(sum, sum_sq, cs.pixel, l);
}
