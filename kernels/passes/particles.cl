/* The particle trace (paper section 4.1; integrator/particle_trace.h):
 * one work-item per particle of the range [first, first + count). Tallies
 * are integer atomics, so the result does not depend on the order of work. */
#include "../lvcl.h"

/* Different from every pixel stream of the camera passes. */
#define LV_PARTICLE_STREAM 0x9e3779b9u

__kernel void lv_particle_trace(LV_KERNEL_PARAMS(LV_PARTICLE_TRACE_ARGS))
{
    LV_SCENE_OPEN(sc);
    uint id = get_global_id(0);
    if (id >= count) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid); /* its lit volumes are not known yet: the trace does not read them */
    grid.subcells_seen = subcells_seen;
    grid.restarted_only = restarted_only;
    lv_rng rng = lv_rng_make(sc.info.seed ^ LV_PARTICLE_STREAM, first + id, 0u);
    lv_bin_tables tables = {bin_table, fine_bin_table};
    lv_view_probe view = {view_slots, view_light, view_groups};
    lv_particle_rays n = lv_trace_particle(&sc, &grid, &tables, &rng, store_emitted, see_through, &view);
    atomic_add(&ray_counts[0], n.segments);
    atomic_add(&ray_counts[1], n.visibility_rays);
}

/* Every stored cell's lit volume, once the trace is done: lookups read one
 * number instead of walking the subcell record. */
__kernel void lv_lit_volumes(LV_KERNEL_PARAMS(LV_LIT_VOLUMES_ARGS))
{
    uint slot = get_global_id(0);
    if (slot >= grid_info.slot_count) return;
    lv_grid grid;
    LV_VOLUME_OPEN(grid);
    lit_volume[slot] = lv_cell_lit_volume(&grid, slot);
}

/* The bin table (shared_types.h), for gathers that visit every bin. */
__kernel void lv_bin_table(LV_KERNEL_PARAMS(LV_BIN_TABLE_ARGS))
{
    uint bin = get_global_id(0);
    if (bin < LV_BIN_GROUPS(2u * n * n) * LV_BIN_GROUP) lv_fill_bin_table(bin, n, table);
}
