/* The light volume's grid: which stored slot holds a point, and where a
 * slot's tallies live. See lv_grid_info in shared_types.h for the layout:
 * cell_slot maps a cell (x + dims.x (y + dims.y z)) to its first slot (with
 * LV_CUT_CELL set if it has planes) or
 * LV_EMPTY_CELL; slot s, bin b, channel c is, with t = tally_slot[s] and
 * q = slots_per_part, tallies[t / q][(t % q) * LV_SET_LONGS(bins) + 3 b + c]
 * (the cells of a merged block share t). docs/light-volume.md
 * describes the estimator the tallies feed. */
#ifndef LV_VOLUME_GRID_H
#define LV_VOLUME_GRID_H

#include "../util/geometry.h"
#include "../shared_types.h"

typedef struct {
    lv_grid_info g;
    __global const uint *cell_slot;         /* cell -> its first slot, | LV_CUT_CELL if it has planes */
    __global const lv_slot_region *regions; /* per slot: its region of its cell (shared_types.h) */
    __global const lv_cell_cut *cuts;       /* per cut cell: its planes */
    __global const float *region_shares;    /* per slot of a cut cell: its exact shares (shared_types.h) */
    __global const uint *tally_slot;        /* per slot: its tally set (shared by a merged block) */
    __global uint *subcell_marks;           /* LV_MARK_WORDS per slot (shared_types.h) */
    __global uint *subcell_rays;            /* LV_RAY_WORDS per subcell entry */
    __global uint *lit_points;              /* one per subcell entry */
    __global const uint *subcells_seen;     /* the trace's copy of each slot's two mask words from before its batch */
    __global const float *lit_volume;       /* per slot, lv_cell_lit_volume after the trace (lookups only) */
    uint restarted_only;                    /* the trace: tally into LV_RESTARTED slots only, mark nothing */
    __global long *tallies[LV_TALLY_PARTS];
} lv_grid;

/* The RGB tallies of tally set `set`'s first bin (its bins follow). */
inline __global long *lv_tally_set(const lv_grid *grid, uint set)
{
    /* Most grids fit one buffer: skip the division there. */
    uint part = set < grid->g.slots_per_part ? 0u : set / grid->g.slots_per_part;
    uint in_part = set - part * grid->g.slots_per_part;
    return grid->tallies[part] + (size_t)in_part * LV_SET_LONGS(grid->g.bins);
}

/* The three (RGB) tallies of one bin of a stored cell. */
inline __global long *lv_tally_bin(const lv_grid *grid, uint slot, uint bin)
{
    return lv_tally_set(grid, LV_TALLY_SET_OF(grid->tally_slot[slot])) + (size_t)bin * 3;
}

/* n of the n x n bins per hemisphere that slot's tally set holds. */
inline uint lv_slot_dirs(const lv_grid *grid, uint slot)
{
    return grid->tally_slot[slot] & LV_FINE_DIRS ? 2u * grid->g.dirs : grid->g.dirs;
}

/* The LV_AXES axis corrections of slot's tally set (shared_types.h). */
inline __global long *lv_axis_corrections(const lv_grid *grid, uint slot)
{
    uint n = lv_slot_dirs(grid, slot);
    return lv_tally_bin(grid, slot, 2u * n * n);
}

/* The LV_LOBE_LONGS sums of slot's lobe of concentrated light (shared_types.h). */
inline __global long *lv_lobe_sums(const lv_grid *grid, uint slot)
{
    return lv_axis_corrections(grid, slot) + LV_AXES;
}

/* The bin tables (shared_types.h has their layout) of the passes that
 * visit every bin of a cell and of the trace's axis corrections: one for
 * n x n bins per hemisphere, one for the 2n x 2n of slots with fine bins
 * (LV_FINE_DIRS). */
typedef struct {
    __global const float *coarse, *fine;
} lv_bin_tables;

/* The table of a slot whose set holds n x n bins per hemisphere. */
inline __global const float *lv_bin_table_for(const lv_bin_tables *t, const lv_grid *grid, uint n)
{
    return n == grid->g.dirs ? t->coarse : t->fine;
}

inline float3 lv_grid_origin(const lv_grid *grid)
{
    return LV_F3(grid->g.origin);
}

/* Which region of its cell the point u (cell units from the cell's corner)
 * lies in: bit i set where it is on the positive side of plane i. */
inline uint lv_region_of(__global const lv_cell_cut *c, float3 u)
{
    uint pattern = 0u;
    for (uint i = 0; i < c->plane_count; i++)
        if (dot((float3)(c->planes[i][0], c->planes[i][1], c->planes[i][2]), u) > c->planes[i][3]) pattern |= 1u << i;
    return pattern;
}

/* The cut of the cell whose first slot is base (one with LV_CUT_CELL set). */
inline __global const lv_cell_cut *lv_cell_cut_of(const lv_grid *grid, uint base)
{
    return grid->cuts + grid->regions[base].cut;
}

/* The slot of the region holding u in the cell whose cell_slot entry is
 * entry. */
inline uint lv_region_slot(const lv_grid *grid, uint entry, float3 u)
{
    if (entry == LV_EMPTY_CELL || !(entry & LV_CUT_CELL)) return entry;
    uint base = entry & ~LV_CUT_CELL;
    __global const lv_cell_cut *c = lv_cell_cut_of(grid, base);
    return base + LV_REGION_OFFSET(c, lv_region_of(c, u));
}

/* The slot of the region of its cell holding point p, or LV_EMPTY_CELL. */
inline uint lv_grid_slot_at(const lv_grid *grid, float3 p)
{
    float3 c = (p - lv_grid_origin(grid)) / grid->g.cell_size;
    if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) return LV_EMPTY_CELL;
    uint x = (uint)c.x, y = (uint)c.y, z = (uint)c.z;
    if (x >= grid->g.dims[0] || y >= grid->g.dims[1] || z >= grid->g.dims[2]) return LV_EMPTY_CELL;
    uint base = grid->cell_slot[x + grid->g.dims[0] * (y + grid->g.dims[1] * z)];
    return lv_region_slot(grid, base, c - (float3)((float)x, (float)y, (float)z));
}

#endif
