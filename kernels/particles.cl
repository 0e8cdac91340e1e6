/* The particle trace (paper section 4.1; integrator/particle_trace.h):
 * one work-item per particle of the range [first, first + count). Tallies
 * are integer atomics, so the result does not depend on the order of work. */
#include "lvcl.h"

/* Different from every pixel stream of the camera passes. */
#define LV_PARTICLE_STREAM 0x9e3779b9u

__kernel void lv_particle_trace(LV_SCENE_PARAMS, lv_grid_info grid_info, __global const uint *cell_slot,
                                __global long *tallies0, __global long *tallies1, __global long *tallies2,
                                __global long *tallies3, __global uint *subcells, uint first, uint count,
                                float inv_total_particles,
                                uint store_emitted, __global uint *ray_counts)
{
    LV_SCENE_OPEN(sc);
    uint id = get_global_id(0);
    if (id >= count) return;
    lv_grid grid;
    grid.g = grid_info;
    grid.cell_slot = cell_slot;
    grid.subcells = subcells;
    grid.lit_volume = 0; /* not known yet */
    grid.tallies[0] = tallies0;
    grid.tallies[1] = tallies1;
    grid.tallies[2] = tallies2;
    grid.tallies[3] = tallies3;
    lv_rng rng = lv_rng_make(sc.info.seed ^ LV_PARTICLE_STREAM, first + id, 0u);
    lv_particle_rays n = lv_trace_particle(&sc, &grid, &rng, inv_total_particles, store_emitted);
    atomic_add(&ray_counts[0], n.segments);
    atomic_add(&ray_counts[1], n.visibility_rays);
}

/* Every stored cell's lit volume, once the trace is done: lookups read one
 * number instead of walking the subcell record. */
__kernel void lv_lit_volumes(lv_grid_info grid_info, __global uint *subcells, __global float *lit_volume)
{
    uint slot = get_global_id(0);
    if (slot >= grid_info.slot_count) return;
    lv_grid grid;
    grid.g = grid_info;
    grid.subcells = subcells;
    lit_volume[slot] = lv_cell_lit_volume(&grid, slot);
}

/* The central direction of every bin, for gathers that visit them all. */
__kernel void lv_bin_directions(uint n, __global float4 *directions)
{
    uint bin = get_global_id(0);
    if (bin < 2u * n * n) directions[bin] = (float4)(lv_bin_direction(bin, n, (float2)(0.5f, 0.5f)), 0.0f);
}
