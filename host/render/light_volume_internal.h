/* The light volume's private parts, shared by the files of host/render/
 * that implement it: grid choice and cell marking (volume_grid.c), the
 * allocation within the device's budget (light_volume.c), the trace
 * (volume_trace.c), the read-back and merge (volume_readback.c), the
 * guide table (volume_guide.c) and the gather's axis sums
 * (volume_axis_sums.c). */
#ifndef LVCL_LIGHT_VOLUME_INTERNAL_H
#define LVCL_LIGHT_VOLUME_INTERNAL_H

#include "../util/vec3.h"
#include "light_volume.h"

/* The slab of an opaque solid whose faces a cell's planes do not keep out
 * of its regions (volume_planes.c): one thinner than a quarter cell whose
 * two faces one plane stands for (a wall: the plane gives half of its
 * inside to each side's region), or a thicker one whose one face took a
 * plane while the other was spare (a slab of a room's shell: all of its
 * inside lies in the region on that face's side). In cell units, the slab
 * lo[0] <= axis[0] . u <= hi[0] between its faces (axis[0] its normal),
 * bounded by a face's extent along the two axes in its plane (open on a
 * side where both faces reach the cell's side: keep_solid). Light
 * never enters the solid, so a region's volume leaves its part there out
 * (lvcl_region_open_volume): without subcells that volume is the region's
 * lit volume, with them it bounds the lit volume (lv_cell_lit_volume). */
typedef struct {
    float axis[3][3];
    float lo[3], hi[3];
} lvcl_solid_slab;

/* A stored cell's solids' slabs: at most two per plane (volume_planes.c,
 * keep_solid). */
#define LVCL_CELL_SOLIDS (2 * LV_GEOMETRY_PLANES)
typedef struct {
    uint8_t count;
    lvcl_solid_slab solid[LVCL_CELL_SOLIDS];
} lvcl_cell_solids;

/* The solids' slabs of the cells that have any: per stored cell its entry
 * in `list`, or LVCL_NO_SOLIDS. */
#define LVCL_NO_SOLIDS 0xffffffffu
typedef struct lvcl_solid_slabs {
    uint32_t *of_cell;
    lvcl_cell_solids *list;
} lvcl_solid_slabs;

/* The regions of the stored cells (shared_types.h, "Regions of a cut
 * cell"): per slot its region, per cut cell its planes, and the regions'
 * exact shares. Each array malloc'ed, with at least one entry. */
typedef struct {
    lv_slot_region *slots; /* slot_count + 1 (the last: the records' entry count) */
    lv_cell_cut *cuts;
    size_t cut_count;
    float *shares; /* what lv_slot_region.shares points into */
    size_t share_count;
} lvcl_regions;

/* Frees the arrays of *r and empties it. */
void lvcl_regions_free(lvcl_regions *r);

struct lvcl_light_volume {
    const lvcl_device *dev;    /* borrowed */
    lvcl_volume_buffers buf;   /* the grid and the buffers the kernels take (tallies: info.slots_per_part
                                 slots each, unused parts NULL) */
    uint32_t *cell_slot;       /* host copy of the index grid (cell -> first slot) */
    lvcl_regions regions;      /* host copy of the slots' regions and the cells' planes */
    uint32_t *tally_slot;      /* host copy of each slot's tally set (slot_count + 1) */
    uint32_t *block_of_slot;   /* per slot: the block of cells it may merge in, or LV_EMPTY_CELL (volume_adapt.c) */
    size_t block_count;        /* blocks block_of_slot numbers */
    int adapted;               /* lvcl_volume_adapt has merged blocks: the tally sets are fixed */
    size_t merged_cells;       /* slots that share their block's tally set */
    int refined;               /* lvcl_volume_refine has run: the layout is fixed */
    size_t split_cells;        /* cells it split (volume_refine.c) */
    int see_through;           /* its trace left out lamps seen through glass (lvcl_volume_settings) */
    size_t fine_slots;         /* slots it gave fine bins (LV_FINE_DIRS) */
    double split_from;         /* the particle count when it refined them, while the LV_RESTARTED slots
                                  (tally_slot) hold only the particles from there on; 0 once retraced */
    cl_mem fine_bin_table_buf; /* the bin table of 2n x 2n, once there are fine slots */
    cl_mem guide_table_buf;    /* guided mode: lvcl_volume_fill_guide's table, or NULL */
    cl_mem axis_sums_buf;      /* lvcl_volume_axis_sums's, for axis_sums_slots slots, or NULL */
    cl_mem view_slots_buf;     /* lvcl_volume_view_probe's slots, or NULL: the trace does not probe */
    cl_mem view_light_buf;     /* and its sums, view_seen x view_groups x 2 */
    size_t view_seen, view_groups;
    uint32_t axis_sums_slots;
    int axis_sums_current;        /* they sum the volume lvcl_volume_finish last finished */
    lvcl_solid_slabs solid_slabs; /* the cells' solids' slabs (none: NULLs) */
    size_t cell_count; /* dims[0] * dims[1] * dims[2] */
    int tally_parts;
    cl_mem bin_table_buf; /* LV_BIN_TABLE_FLOATS(bins) floats, filled by lvcl_volume_trace */
    size_t tally_bytes;   /* all parts */
    size_t device_bytes;  /* everything the volume holds on the device */
    double trace_seconds;
    uint64_t particles;
    uint64_t segments;
    uint64_t visibility_rays;
};

/* Planes whose normals are within 25 degrees (cos 25 degrees) are one
 * wall's to the regions of cut cells (volume_planes.c, volume_refine.c). */
#define LVCL_SAME_NORMAL 0.9063077870366499

/* The index of cell (x, y, z) in the grid's cell arrays (cell_slot). */
static inline size_t lvcl_volume_cell_index(const lv_grid_info *g, int x, int y, int z)
{
    return (size_t)x + g->dims[0] * ((size_t)y + g->dims[1] * (size_t)z);
}

/* Fills g's placement (origin, cell size, dims), bins and light totals from
 * the settings over the packed scene's bounds; *cells is the cell count. */
lvcl_error lvcl_volume_grid_choose(const lvcl_packed_scene *p, const lvcl_volume_settings *s, lv_grid_info *g,
                                   size_t *cells, lvcl_status *st);

/* The cells lo..hi (clamped to the grid) that the world box lo_w..hi_w
 * covers, and whether they span at most two along every axis: such a part
 * of a mesh's tree is marked whole and, for the planes, sampled
 * (volume_grid.c, volume_planes.c). */
int lvcl_volume_box_cells(const lv_grid_info *g, const float lo_w[3], const float hi_w[3], int lo[3], int hi[3]);

/* Calls visit with the world box of every placed triangle, except that a
 * part of a mesh's tree whose placed box spans at most two cells along
 * every axis is one box: a tile instanced hundreds of times then costs a
 * few boxes, not its 500,000 triangles (volume_grid.c). */
typedef void (*lvcl_box_visitor)(const lv_grid_info *g, const float lo_w[3], const float hi_w[3], void *ctx);
void lvcl_volume_walk_geometry(const lvcl_packed_scene *p, const lv_grid_info *g, lvcl_box_visitor visit, void *ctx);

/* Numbers the stored cells (slot per cell, LV_EMPTY_CELL elsewhere) and
 * sets g->slot_count; LVCL_ERR_OUT_OF_MEMORY if the marks do not fit. */
lvcl_error lvcl_volume_assign_slots(const lvcl_packed_scene *p, lv_grid_info *g, size_t cells, uint32_t *slot,
                                    lvcl_status *st);

/* Chooses every stored cell's planes (volume_planes.c) and gives a cell
 * cut by P of them 2^P consecutive slots: on entry slot[] numbers the
 * stored cells (g->slot_count of them), on return it holds each cell's
 * first slot, g->slot_count the slots and *regions the slots' regions,
 * the cut cells' planes and the regions' shares, and *solids (its arrays
 * malloc'ed, or NULL where no cell has any) the cells' solids' slabs,
 * which their regions' volumes leave out. */
lvcl_error lvcl_volume_build_regions(const lvcl_packed_scene *p, lv_grid_info *g, size_t cells, uint32_t *slot,
                                     lvcl_regions *regions, lvcl_solid_slabs *solids, lvcl_status *st);

/* Frees what lvcl_volume_build_regions put in *solids and empties it. */
void lvcl_solid_slabs_free(lvcl_solid_slabs *solids);

/* The slot of the region holding world point p in a grid whose cells'
 * entries are cell_slot and whose regions are `regions` (what
 * lvcl_volume_build_regions made), or LV_EMPTY_CELL; *cell (unless NULL)
 * gets p's cell index, or -1 outside the grid. */
uint32_t lvcl_volume_grid_slot_at(const lv_grid_info *g, const uint32_t *cell_slot, const lvcl_regions *regions,
                                  const float p[3], long *cell);

/* One stored cell's planes (cell units, lv_cell_cut's convention). */
typedef struct {
    float planes[LV_REGION_PLANES][4];
    uint8_t count;
    uint64_t mixed; /* bit m: region pattern m is LV_REGION_MIXED */
    uint32_t solids; /* its entry in the solids' slabs' list, or LVCL_NO_SOLIDS */
} lvcl_cell_planes;

/* Fills out[] with stored cell s's region shares as lvcl_region_shares
 * would (per pattern, the region's volume then its subcells'), where they
 * are known already; returns 0 where they must be computed. */
typedef int (*lvcl_known_shares)(void *ctx, uint32_t s, float *out);

/* Gives a stored cell cut by P planes 2^P consecutive slots (fewer where a
 * region is empty): on entry slot[] numbers the stored cells
 * (g->slot_count of them) and planes[] holds each one's; on return slot[]
 * holds each cell's first slot (| LV_CUT_CELL where it has planes),
 * g->slot_count the slots, and *regions is as lvcl_volume_build_regions
 * gives it. `known` (may be NULL) saves
 * computing the shares of cells whose planes did not change. A region's
 * volume leaves out its cell's solids' slabs (solids: the list that
 * planes[].solids index, or NULL). */
lvcl_error lvcl_volume_lay_out_regions(lv_grid_info *g, size_t cells, const lvcl_cell_planes *planes,
                                       const lvcl_cell_solids *solids, lvcl_known_shares known, void *ctx,
                                       uint32_t *slot, lvcl_regions *regions, lvcl_status *st);

/* The exact shares of the 2^count regions of a cell with these planes (cell
 * units, lv_cell_cut's convention) and k^3 subcells (k = 0: none): per
 * region m, at out[m (1 + max(k^3, 1))], the region's volume over the
 * cell's, then the fraction of each subcell (of the cell if k = 0) in it
 * (volume_shares.c). */
void lvcl_region_shares(const float planes[][4], int count, uint32_t k, float *out);

/* lvcl_region_shares of each of the `count` cells of planes that has
 * planes, at out + at[i], on several threads (a 64-cell grid of the
 * kitchen's took a second on one). */
void lvcl_region_shares_batch(const lvcl_cell_planes *planes, size_t count, uint32_t k, const size_t *at, float *out);

/* The volume (over the cell's) of region `pattern` of a cell with these
 * planes, less its part inside the union of the cell's solids' slabs (two
 * that cross in one cell, at a wall's corner, share a part), exactly, but
 * never under a twentieth of the region's volume (volume_shares.c). */
double lvcl_region_open_volume(const float planes[][4], int count, uint32_t pattern, const lvcl_cell_solids *solids);

/* Finds the blocks of 2 x 2 x 2 cells with no geometry inside whose
 * stored cells may share one tally set, and sets vol->block_of_slot
 * (volume_adapt.c). */
lvcl_error lvcl_volume_find_blocks(lvcl_light_volume *vol, const lvcl_packed_scene *p, lvcl_status *st);

/* After lv_lit_volumes: gives every cell of a merged block the block's
 * lit volume, the sum of its cells' (volume_adapt.c). */
lvcl_error lvcl_volume_share_lit(lvcl_light_volume *vol, lvcl_status *st);

/* Stores tallies (laid out as lvcl_volume_read reads them) and, if not
 * NULL, subcell records into the volume's buffers; `what` names the step
 * in an error (volume_readback.c). */
lvcl_error lvcl_volume_write(lvcl_light_volume *vol, const int64_t *tallies, const uint32_t *records, const char *what,
                             lvcl_status *st);

/* Stores every slot's lit volume, as lvcl_volume_read_lit reads them. */
lvcl_error lvcl_volume_write_lit(lvcl_light_volume *vol, const float *lit, const char *what, lvcl_status *st);

/* After lv_lit_volumes: scales the lit volume of every refined slot by the
 * share of the particles it was traced (volume_refine.c). */
lvcl_error lvcl_volume_scale_split(lvcl_light_volume *vol, lvcl_status *st);

/* Lays the tallies out (lvcl_volume_layout_tallies), totals the device
 * memory the volume takes and checks it against the device. */
lvcl_error lvcl_volume_place(lvcl_light_volume *vol, lvcl_status *st);

/* Creates the volume's device buffers (the tallies and subcell records
 * uninitialised) from the host copies of its layout. */
lvcl_error lvcl_volume_allocate(lvcl_light_volume *vol, lvcl_status *st);

/* Lays info.tally_sets out over the fewest buffers the device allows
 * (info.slots_per_part, vol->tally_parts, vol->tally_bytes); 0 if more than
 * LV_TALLY_PARTS would be needed. */
int lvcl_volume_layout_tallies(lvcl_light_volume *vol);

/* Allocates the tally buffers of that layout (uninitialised). */
cl_int lvcl_volume_allocate_tallies(lvcl_light_volume *vol);

/* Bytes of tally buffer `part` (a buffer holds info.slots_per_part tally sets). */
size_t lvcl_volume_part_bytes(const lvcl_light_volume *vol, int part);

/* The entry of subcell i in the records of the slot whose region is *r
 * (shared_types.h), or LV_NO_ENTRY where the region has no volume in it. */
static inline uint32_t lvcl_region_entry(const lv_slot_region *r, uint32_t i)
{
    if (!(r->present[i >> 5] >> (i & 31u) & 1u)) return LV_NO_ENTRY;
    return r->entries + LV_ENTRIES_BELOW(r->present[0], r->present[1], i);
}

/* The sizes of the subcell records' three buffers (shared_types.h), in the
 * order of lvcl_volume_read's block: marks, rays, lit points. */
void lvcl_volume_record_sections(const lvcl_light_volume *vol, size_t bytes[3]);
/* Those three buffers, in the same order. */
void lvcl_volume_record_buffers(const lvcl_light_volume *vol, cl_mem bufs[3]);

#endif
