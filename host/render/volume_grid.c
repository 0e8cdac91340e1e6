/* The light volume's grid: its placement over the scene's bounds, and the
 * cells it stores, those the geometry touches and their neighbours. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

/* Cell coordinates covering the world box lo..hi (clamped to the grid). A
 * surface lying on a cell boundary belongs to the cells on both sides. */
static void cell_range(const lv_grid_info *g, float inv, const float lo_w[3], const float hi_w[3], int lo[3], int hi[3])
{
    for (int k = 0; k < 3; k++) {
        lo[k] = (int)floorf((lo_w[k] - g->origin[k]) * inv - 1e-4f);
        hi[k] = (int)floorf((hi_w[k] - g->origin[k]) * inv + 1e-4f);
        if (lo[k] < 0) lo[k] = 0;
        if (hi[k] > (int)g->dims[k] - 1) hi[k] = (int)g->dims[k] - 1;
    }
}

int lvcl_volume_box_cells(const lv_grid_info *g, const float lo_w[3], const float hi_w[3], int lo[3], int hi[3])
{
    cell_range(g, 1.0f / g->cell_size, lo_w, hi_w, lo, hi);
    return hi[0] - lo[0] <= 1 && hi[1] - lo[1] <= 1 && hi[2] - lo[2] <= 1;
}

static void mark_range(const lv_grid_info *g, const int lo[3], const int hi[3], uint8_t *mark)
{
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) mark[lvcl_volume_cell_index(g, x, y, z)] = 1;
}

typedef struct {
    const lv_grid_info *g;
    lvcl_box_visitor visit;
    void *ctx;
} geometry_walk;

/* A placed node that spans few cells is one box; others are entered. */
static int node_or_box(void *ctx, const float lo_w[3], const float hi_w[3])
{
    const geometry_walk *w = ctx;
    int lo[3], hi[3];
    if (!lvcl_volume_box_cells(w->g, lo_w, hi_w, lo, hi)) return 1;
    w->visit(w->g, lo_w, hi_w, w->ctx);
    return 0;
}

static int triangle_box(void *ctx, const float v[9])
{
    const geometry_walk *w = ctx;
    float lo_w[3], hi_w[3];
    for (int k = 0; k < 3; k++) {
        lo_w[k] = fminf(v[k], fminf(v[3 + k], v[6 + k]));
        hi_w[k] = fmaxf(v[k], fmaxf(v[3 + k], v[6 + k]));
    }
    w->visit(w->g, lo_w, hi_w, w->ctx);
    return 0;
}

void lvcl_volume_walk_geometry(const lvcl_packed_scene *p, const lv_grid_info *g, lvcl_box_visitor visit, void *ctx)
{
    geometry_walk w = {g, visit, ctx};
    lvcl_packed_walk(p, node_or_box, triangle_box, &w);
}

/* Marks the cells a box of geometry touches (conservative for slanted
 * triangles; see docs/light-volume.md). */
static void mark_box(const lv_grid_info *g, const float lo_w[3], const float hi_w[3], void *mark)
{
    int lo[3], hi[3];
    cell_range(g, 1.0f / g->cell_size, lo_w, hi_w, lo, hi);
    mark_range(g, lo, hi, mark);
}

/* A lookup jitters up to half a cell from a surface, so the cells next to
 * geometry cells are stored too. */
static size_t assign_slots(const lv_grid_info *g, const uint8_t *mark, uint32_t *slot)
{
    size_t count = 0;
    for (int z = 0; z < (int)g->dims[2]; z++)
        for (int y = 0; y < (int)g->dims[1]; y++)
            for (int x = 0; x < (int)g->dims[0]; x++) {
                int near = 0;
                for (int dz = -1; dz <= 1 && !near; dz++)
                    for (int dy = -1; dy <= 1 && !near; dy++)
                        for (int dx = -1; dx <= 1 && !near; dx++) {
                            int a = x + dx, b = y + dy, c = z + dz;
                            if (a < 0 || b < 0 || c < 0 || a >= (int)g->dims[0] || b >= (int)g->dims[1] ||
                                c >= (int)g->dims[2])
                                continue;
                            near = mark[lvcl_volume_cell_index(g, a, b, c)];
                        }
                slot[lvcl_volume_cell_index(g, x, y, z)] = near ? (uint32_t)count++ : LV_EMPTY_CELL;
            }
    return count;
}

lvcl_error lvcl_volume_grid_choose(const lvcl_packed_scene *p, const lvcl_volume_settings *s, lv_grid_info *g,
                                   size_t *cell_count, lvcl_status *st)
{
    memset(g, 0, sizeof *g);
    if (s->dirs < 1 || s->dirs > 64) return lvcl_fail(st, LVCL_ERR_USAGE, "--dirs must be from 1 to 64");
    if (s->subcells < 0 || s->subcells > 4) return lvcl_fail(st, LVCL_ERR_USAGE, "--subcells must be from 0 to 4");
    if (s->offset < 0 || s->offset >= 1) return lvcl_fail(st, LVCL_ERR_USAGE, "--grid-offset must be in [0, 1)");
    float extent[3], longest = 0.0f;
    for (int k = 0; k < 3; k++) {
        extent[k] = p->bounds_max[k] - p->bounds_min[k];
        longest = fmaxf(longest, extent[k]);
    }
    g->cell_size = s->cell_size > 0 ? (float)s->cell_size : longest / (float)(s->cells > 0 ? s->cells : 1);
    if (!(g->cell_size > 0.0f))
        return lvcl_fail(st, LVCL_ERR_UNSUPPORTED, "the scene has no extent for a light volume");
    /* One spare cell on every side holds lookups jittered off the bounds;
     * an offset shifts the grid by a fraction of a cell (one more cell). */
    double cells = 1.0;
    for (int k = 0; k < 3; k++) {
        double d = ceil(extent[k] / g->cell_size) + (s->offset > 0 ? 3.0 : 2.0);
        if (d < 1.0) d = 1.0;
        g->dims[k] = (lv_u32)d;
        g->origin[k] = p->bounds_min[k] - g->cell_size * (1.0f + (float)s->offset);
        cells *= d;
    }
    if (cells > 1 << 28) {
        char size[32];
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                         "a %ux%ux%u light-volume grid (cell size %g m) has %.3g cells, more than the 2^28 lvcl "
                         "indexes; its cell index alone would need %s; use fewer --cells or a larger --cell-size",
                         g->dims[0], g->dims[1], g->dims[2], g->cell_size, cells,
                         lvcl_bytes_text(cells * sizeof(uint32_t), size));
    }
    g->dirs = (lv_u32)s->dirs;
    g->bins = 2 * g->dirs * g->dirs;
    g->total_power = p->info.total_light_power;
    g->subcells = (lv_u32)s->subcells;
    g->visibility_rate = (float)(s->visibility_rate > 0 ? s->visibility_rate : LVCL_VISIBILITY_RATE);

    *cell_count = (size_t)cells;
    return LVCL_OK;
}

lvcl_error lvcl_volume_assign_slots(const lvcl_packed_scene *p, lv_grid_info *g, size_t cells, uint32_t *slot,
                                    lvcl_status *st)
{
    uint8_t *mark = calloc(cells, 1);
    if (!mark) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for a %zu-cell grid", cells);
    lvcl_volume_walk_geometry(p, g, mark_box, mark);
    g->slot_count = (lv_u32)assign_slots(g, mark, slot);
    free(mark);
    return LVCL_OK;
}
