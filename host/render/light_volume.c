/* The light volume's lifetime: the grid (volume_grid.c) laid out over as
 * few buffers as the device allows, checked against its memory budget and
 * allocated; the accessors of the opaque handle. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

lvcl_error lvcl_volume_create(const lvcl_device *dev, const lvcl_packed_scene *p, const lvcl_volume_settings *s,
                              lvcl_light_volume **out, lvcl_status *st)
{
    *out = NULL;
    lvcl_light_volume *vol = calloc(1, sizeof *vol);
    if (!vol) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for a light volume");
    vol->dev = dev;
    lv_grid_info *g = &vol->buf.info;
    lvcl_error e = lvcl_volume_grid_choose(p, s, g, &vol->cell_count, st);
    if (e) {
        lvcl_volume_release(vol);
        return e;
    }
    vol->cell_slot = malloc(vol->cell_count * sizeof(uint32_t));
    if (!vol->cell_slot) {
        size_t cells = vol->cell_count;
        lvcl_volume_release(vol);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for a %zu-cell grid", cells);
    }
    if ((e = lvcl_volume_assign_slots(p, g, vol->cell_count, vol->cell_slot, st)) ||
        (e = lvcl_volume_build_regions(p, g, vol->cell_count, vol->cell_slot, &vol->regions, &vol->solid_slabs, st))) {
        lvcl_volume_release(vol);
        return e;
    }

    vol->tally_slot = malloc(((size_t)g->slot_count + 1) * sizeof(uint32_t));
    if (!vol->tally_slot) {
        lvcl_volume_release(vol);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for a light volume");
    }
    for (uint32_t i = 0; i <= g->slot_count; i++) vol->tally_slot[i] = i < g->slot_count ? i : 0;
    g->tally_sets = g->slot_count;
    if (s->merge_tolerance > 0 && (e = lvcl_volume_find_blocks(vol, p, st))) {
        lvcl_volume_release(vol);
        return e;
    }

    if ((e = lvcl_volume_place(vol, st)) || (e = lvcl_volume_allocate(vol, st))) {
        lvcl_volume_release(vol);
        return e;
    }
    *out = vol;
    return LVCL_OK;
}

/* Bytes of the regions' three buffers: per slot, per cut cell, shares. */
static void region_sizes(const lvcl_light_volume *vol, size_t sizes[3])
{
    const lvcl_regions *r = &vol->regions;
    sizes[0] = ((size_t)vol->buf.info.slot_count + 1) * sizeof(lv_slot_region);
    sizes[1] = (r->cut_count ? r->cut_count : 1) * sizeof(lv_cell_cut);
    sizes[2] = (r->share_count ? r->share_count : 1) * sizeof(float);
}

void lvcl_regions_free(lvcl_regions *r)
{
    free(r->slots);
    free(r->cuts);
    free(r->shares);
    *r = (lvcl_regions){0};
}

lvcl_error lvcl_volume_place(lvcl_light_volume *vol, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    const lv_grid_info *g = &vol->buf.info;
    int fits = lvcl_volume_layout_tallies(vol);
    /* Beside the tallies: the cell index, per slot its subcell marks, a lit
     * volume, its tally set and its region, per cut cell its planes, and
     * per subcell entry its rays and lit point (one buffer each). */
    size_t records = lvcl_volume_record_bytes(vol) + ((size_t)g->slot_count + 1) * 2 * sizeof(uint32_t);
    size_t sizes[3];
    region_sizes(vol, sizes);
    vol->device_bytes =
        vol->tally_bytes + vol->cell_count * sizeof(uint32_t) + records + sizes[0] + sizes[1] + sizes[2];
    if (!fits || records > dev->max_alloc || sizes[0] > dev->max_alloc || sizes[1] > dev->max_alloc ||
        sizes[2] > dev->max_alloc || vol->device_bytes > dev->global_mem)
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                         "the light volume needs %.1f MiB (%u cells x %u bins) but %s allows %.1f MiB in one "
                         "buffer (at most %d buffers) and %.1f MiB in all; use fewer --cells or --dirs",
                         vol->device_bytes / 1048576.0, g->slot_count, g->bins, dev->name, dev->max_alloc / 1048576.0,
                         LV_TALLY_PARTS, dev->global_mem / 1048576.0);
    return LVCL_OK;
}

lvcl_error lvcl_volume_allocate(lvcl_light_volume *vol, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    const lv_grid_info *g = &vol->buf.info;
    size_t sizes[3];
    region_sizes(vol, sizes);
    cl_int err;
    vol->buf.cell_slot = lvcl_buffer_create(dev, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                            vol->cell_count * sizeof(uint32_t), vol->cell_slot, &err);
    if (err == CL_SUCCESS)
        vol->buf.regions =
            lvcl_buffer_create(dev, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizes[0], vol->regions.slots, &err);
    if (err == CL_SUCCESS)
        vol->buf.cuts =
            lvcl_buffer_create(dev, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizes[1], vol->regions.cuts, &err);
    if (err == CL_SUCCESS)
        vol->buf.region_shares =
            lvcl_buffer_create(dev, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizes[2], vol->regions.shares, &err);
    if (err == CL_SUCCESS)
        vol->buf.tally_slot = lvcl_buffer_create(dev, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                                                 ((size_t)g->slot_count + 1) * sizeof(uint32_t), vol->tally_slot, &err);
    if (err == CL_SUCCESS) err = lvcl_volume_allocate_tallies(vol);
    size_t sections[3];
    lvcl_volume_record_sections(vol, sections);
    cl_mem *record_bufs[3] = {&vol->buf.subcell_marks, &vol->buf.subcell_rays, &vol->buf.lit_points};
    for (int i = 0; i < 3 && err == CL_SUCCESS; i++) /* OpenCL refuses empty buffers */
        *record_bufs[i] = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, sections[i] ? sections[i] : 8, NULL, &err);
    if (err == CL_SUCCESS)
        vol->buf.lit_volume =
            lvcl_buffer_create(dev, CL_MEM_READ_WRITE, ((size_t)g->slot_count + 1) * sizeof(float), NULL, &err);
    if (err == CL_SUCCESS && !vol->bin_table_buf)
        vol->bin_table_buf = lvcl_buffer_create(dev, CL_MEM_READ_WRITE,
                                                (size_t)LV_BIN_TABLE_FLOATS(g->bins) * sizeof(float), NULL, &err);
    char what[300];
    snprintf(what, sizeof what, "allocating the light volume (%.1f MiB) on %s", vol->device_bytes / 1048576.0,
             dev->name);
    return lvcl_cl_check(err, what, st);
}

int lvcl_volume_layout_tallies(lvcl_light_volume *vol)
{
    lv_grid_info *g = &vol->buf.info;
    /* The tallies go in as few buffers as the device's largest allocation
     * allows (GPUs often allow a quarter of their memory in one). */
    size_t set_bytes = LV_SET_LONGS(g->bins) * sizeof(int64_t);
    vol->tally_bytes = (size_t)g->tally_sets * set_bytes;
    size_t per_part = vol->dev->max_alloc / set_bytes;
    if (per_part > UINT32_MAX) per_part = UINT32_MAX;
    size_t parts = per_part ? ((size_t)g->tally_sets + per_part - 1) / per_part : SIZE_MAX;
    if (parts > LV_TALLY_PARTS) return 0;
    vol->tally_parts = parts ? (int)parts : 1;
    g->slots_per_part = (lv_u32)(parts > 1 ? per_part : (g->tally_sets ? g->tally_sets : 1));
    return 1;
}

cl_int lvcl_volume_allocate_tallies(lvcl_light_volume *vol)
{
    cl_int err = CL_SUCCESS;
    for (int i = 0; i < vol->tally_parts && err == CL_SUCCESS; i++)
        vol->buf.tallies[i] =
            lvcl_buffer_create(vol->dev, CL_MEM_READ_WRITE, lvcl_volume_part_bytes(vol, i), NULL, &err);
    return err;
}

size_t lvcl_volume_part_bytes(const lvcl_light_volume *vol, int part)
{
    size_t set_bytes = LV_SET_LONGS(vol->buf.info.bins) * sizeof(int64_t);
    size_t first = (size_t)part * vol->buf.info.slots_per_part;
    size_t sets = vol->buf.info.tally_sets > first ? vol->buf.info.tally_sets - first : 0;
    if (sets > vol->buf.info.slots_per_part) sets = vol->buf.info.slots_per_part;
    return sets ? sets * set_bytes : 8; /* OpenCL refuses empty buffers */
}

void lvcl_volume_record_sections(const lvcl_light_volume *vol, size_t bytes[3])
{
    size_t entries = vol->regions.slots[vol->buf.info.slot_count].entries;
    bytes[0] = ((size_t)vol->buf.info.slot_count + 1) * LV_MARK_WORDS * sizeof(uint32_t);
    bytes[1] = entries * LV_RAY_WORDS * sizeof(uint32_t);
    bytes[2] = entries * sizeof(uint32_t);
}

void lvcl_volume_record_buffers(const lvcl_light_volume *vol, cl_mem bufs[3])
{
    bufs[0] = vol->buf.subcell_marks;
    bufs[1] = vol->buf.subcell_rays;
    bufs[2] = vol->buf.lit_points;
}

size_t lvcl_volume_record_bytes(const lvcl_light_volume *vol)
{
    size_t b[3];
    lvcl_volume_record_sections(vol, b);
    return b[0] + b[1] + b[2];
}

const lv_grid_info *lvcl_volume_grid(const lvcl_light_volume *vol)
{
    return &vol->buf.info;
}

uint32_t lvcl_volume_grid_slot_at(const lv_grid_info *g, const uint32_t *cell_slot, const lvcl_regions *regions,
                                  const float p[3], long *cell)
{
    float u[3];
    uint32_t c[3];
    if (cell) *cell = -1;
    for (int k = 0; k < 3; k++) {
        float x = (p[k] - g->origin[k]) / g->cell_size;
        if (!(x >= 0.0f) || x >= (float)g->dims[k]) return LV_EMPTY_CELL;
        c[k] = (uint32_t)x;
        u[k] = x - (float)c[k];
    }
    size_t index = lvcl_volume_cell_index(g, (int)c[0], (int)c[1], (int)c[2]);
    if (cell) *cell = (long)index;
    uint32_t entry = cell_slot[index];
    if (entry == LV_EMPTY_CELL) return entry;
    uint32_t base = entry & ~LV_CUT_CELL, cut = regions->slots[base].cut;
    if (cut == LV_NO_CUT) return base;
    const lv_cell_cut *planes = &regions->cuts[cut];
    uint32_t pattern = 0;
    for (uint32_t i = 0; i < planes->plane_count; i++) {
        const float *n = planes->planes[i];
        if (n[0] * u[0] + n[1] * u[1] + n[2] * u[2] > n[3]) pattern |= 1u << i;
    }
    return base + LV_REGION_OFFSET(planes, pattern);
}

uint32_t lvcl_volume_slot_at(const lvcl_light_volume *vol, const float p[3])
{
    return lvcl_volume_grid_slot_at(&vol->buf.info, vol->cell_slot, &vol->regions, p, NULL);
}

uint32_t lvcl_volume_tally_set(const lvcl_light_volume *vol, uint32_t slot)
{
    return slot < vol->buf.info.slot_count ? vol->tally_slot[slot] : LV_EMPTY_CELL;
}

uint32_t lvcl_volume_slot(const lvcl_light_volume *vol, uint32_t x, uint32_t y, uint32_t z)
{
    const lv_grid_info *g = &vol->buf.info;
    if (x >= g->dims[0] || y >= g->dims[1] || z >= g->dims[2]) return LV_EMPTY_CELL;
    uint32_t entry = vol->cell_slot[lvcl_volume_cell_index(g, (int)x, (int)y, (int)z)];
    return entry == LV_EMPTY_CELL ? entry : entry & ~LV_CUT_CELL;
}

lvcl_volume_stats lvcl_volume_stats_of(const lvcl_light_volume *vol)
{
    size_t mixed = 0;
    for (uint32_t s = 0; s < vol->buf.info.slot_count; s++)
        mixed += (vol->regions.slots[s].flags & LV_REGION_MIXED) != 0;
    return (lvcl_volume_stats){.mixed_slots = mixed,
                               .tally_bytes = vol->tally_bytes,
                               .device_bytes = vol->device_bytes,
                               .axis_sums_bytes = (size_t)vol->axis_sums_slots * LV_AXIS_SUM_FLOATS * sizeof(float),
                               .tally_buffers = vol->tally_parts,
                               .particles = vol->particles,
                               .segments = vol->segments,
                               .visibility_rays = vol->visibility_rays,
                               .merged_cells = vol->merged_cells,
                               .split_cells = vol->split_cells,
                               .fine_slots = vol->fine_slots,
                               .see_through = vol->see_through,
                               .trace_seconds = vol->trace_seconds};
}

const lvcl_volume_buffers *lvcl_volume_kernel_buffers(const lvcl_light_volume *vol)
{
    return &vol->buf;
}

cl_mem lvcl_volume_bin_table(const lvcl_light_volume *vol)
{
    return vol->bin_table_buf;
}

cl_mem lvcl_volume_fine_bin_table(const lvcl_light_volume *vol)
{
    return vol->fine_bin_table_buf ? vol->fine_bin_table_buf : vol->bin_table_buf;
}

void lvcl_volume_release(lvcl_light_volume *vol)
{
    if (!vol) return;
    lvcl_volume_buffers_release(&vol->buf);
    if (vol->bin_table_buf) clReleaseMemObject(vol->bin_table_buf);
    free(vol->cell_slot);
    lvcl_regions_free(&vol->regions);
    free(vol->tally_slot);
    free(vol->block_of_slot);
    if (vol->fine_bin_table_buf) clReleaseMemObject(vol->fine_bin_table_buf);
    if (vol->guide_table_buf) clReleaseMemObject(vol->guide_table_buf);
    if (vol->axis_sums_buf) clReleaseMemObject(vol->axis_sums_buf);
    lvcl_volume_view_probe(vol, NULL, 0, 0, NULL);
    lvcl_solid_slabs_free(&vol->solid_slabs);
    free(vol);
}
