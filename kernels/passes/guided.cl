/* Guided path tracing (--mode guided; integrator/path_tracer.h with the
 * light volume as a guide, volume/guide.h): the guide table, once after
 * the trace, then camera rays, one sample per pixel of the launch's list,
 * as pt.cl. */
#include "../lvcl.h"

/* One room of the guide table (shared_types.h): the luminance of the
 * `bins` bins from t, then their sum and largest. */
inline void lv_guide_fill(__global const long *t, uint bins, __global float *out, __global float *stats)
{
    float sum = 0.0f, top = 0.0f;
    for (uint b = 0; b < bins; b++) {
        float l = lv_guide_luminance(t + 3 * (size_t)b);
        out[b] = l;
        sum += l;
        top = fmax(top, l);
    }
    stats[0] = sum;
    stats[1] = top;
}

/* A set's lobe in the guide table (shared_types.h) from its lobe sums:
 * the mean direction of travel, as long as the mean resultant length, and
 * the luminance. */
inline void lv_guide_fill_lobe(__global const long *sums, __global float *out)
{
    float l = (float)sums[3];
    float3 mean = l > 0.0f ? (float3)((float)sums[0], (float)sums[1], (float)sums[2]) / l : (float3)(0.0f);
    vstore3(mean, 0, out);
    out[3] = fmax(l, 0.0f);
}

/* Without fine_pass: one work-item per tally set, one more for the
 * padding. A set of fine bins takes four sets' room, its bins in one run
 * and its axis corrections after them, so the second to fourth rooms'
 * work-items read the wrong bins; with fine_pass, one work-item per slot
 * then fills each slot of fine bins' four rooms from its run, and its lobe (a volume
 * with fine bins merges no cells, so every such set has one slot). */
__kernel void lv_guide_table(LV_KERNEL_PARAMS(LV_GUIDE_TABLE_ARGS))
{
    uint id = get_global_id(0), bins = grid_info.bins;
    __global float *stats = guide_table + LV_GUIDE_STATS_AT(grid_info);
    __global float *lobes = guide_table + LV_GUIDE_LOBES_AT(grid_info);
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    if (fine_pass) {
        if (id >= grid_info.slot_count || !(grid.tally_slot[id] & LV_FINE_DIRS)) return;
        uint set = LV_TALLY_SET_OF(grid.tally_slot[id]);
        for (uint k = 0; k < 4u; k++)
            lv_guide_fill(lv_tally_bin(&grid, id, k * bins), bins, guide_table + (size_t)(set + k) * bins,
                          stats + 2 * (size_t)(set + k));
        lv_guide_fill_lobe(lv_lobe_sums(&grid, id), lobes + 4 * (size_t)set);
        return;
    }
    if (id > grid_info.tally_sets) return;
    if (id == grid_info.tally_sets) {
        for (uint l = 0; l < LV_BIN_GROUP; l++) guide_table[(size_t)id * bins + l] = 0.0f;
        return;
    }
    lv_guide_fill(lv_tally_set(&grid, id), bins, guide_table + (size_t)id * bins, stats + 2 * (size_t)id);
    lv_guide_fill_lobe(lv_tally_set(&grid, id) + 3 * (size_t)bins + LV_AXES, lobes + 4 * (size_t)id);
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
    g.lobes = guide_table + LV_GUIDE_LOBES_AT(grid_info);
    lv_light_candidates_pick(&sc, &g.lights);
    lv_camera_sample cs = lv_camera_sample_next(camera, sc.info.seed, pixel_list, first_pixel, first_sample, sum);
    float3 l = lv_path_trace(&sc, &g, cs.ray, &cs.rng, sc.info.max_depth, see_through);
    lv_camera_sample_add(sum, sum_sq, cs.pixel, l);
}
