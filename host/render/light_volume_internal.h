/* The light volume's private parts, shared by the files of host/render/
 * that implement it: grid choice and cell marking (volume_grid.c), the
 * allocation within the device's budget (light_volume.c), the trace
 * (volume_trace.c) and the read-back and merge (volume_readback.c). */
#ifndef LVCL_LIGHT_VOLUME_INTERNAL_H
#define LVCL_LIGHT_VOLUME_INTERNAL_H

#include "light_volume.h"

struct lvcl_light_volume {
    const lvcl_device *dev;  /* borrowed */
    lvcl_volume_buffers buf; /* the grid and the buffers the kernels take (tallies: info.slots_per_part
                                 slots each, unused parts NULL) */
    uint32_t *cell_slot;     /* host copy of the index grid (cell -> first slot) */
    lv_slot_region *regions; /* host copy of the per-slot planes (slot_count + 1) */
    size_t cell_count;       /* dims[0] * dims[1] * dims[2] */
    int tally_parts;
    cl_mem bin_directions_buf; /* float4 per bin, filled by lvcl_volume_trace */
    size_t tally_bytes;        /* all parts */
    size_t device_bytes;       /* everything the volume holds on the device */
    double trace_seconds;
    uint64_t particles;
    uint64_t segments;
    uint64_t visibility_rays;
};

/* Fills g's placement (origin, cell size, dims), bins and light totals from
 * the settings over the packed scene's bounds; *cells is the cell count. */
lvcl_error lvcl_volume_grid_choose(const lvcl_packed_scene *p, const lvcl_volume_settings *s, lv_grid_info *g,
                                   size_t *cells, lvcl_status *st);

/* Numbers the stored cells (slot per cell, LV_EMPTY_CELL elsewhere) and
 * sets g->slot_count; LVCL_ERR_OUT_OF_MEMORY if the marks do not fit. */
lvcl_error lvcl_volume_assign_slots(const lvcl_packed_scene *p, lv_grid_info *g, size_t cells, uint32_t *slot,
                                    lvcl_status *st);

/* Chooses every stored cell's planes (volume_planes.c) and gives a cell
 * cut by P of them 2^P consecutive slots: on entry slot[] numbers the
 * stored cells (g->slot_count of them), on return it holds each cell's
 * first slot, g->slot_count the slots and *regions (malloc'ed,
 * slot_count + 1 entries) every slot's planes. */
lvcl_error lvcl_volume_build_regions(const lvcl_packed_scene *p, lv_grid_info *g, size_t cells, uint32_t *slot,
                                     lv_slot_region **regions, lvcl_status *st);

/* Bytes of tally buffer `part` (a buffer holds info.slots_per_part slots). */
size_t lvcl_volume_part_bytes(const lvcl_light_volume *vol, int part);

/* Bytes of the subcell records (one spare slot's worth). */
size_t lvcl_volume_record_bytes(const lvcl_light_volume *vol);

#endif
