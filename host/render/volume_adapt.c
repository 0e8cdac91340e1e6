/* Adaptive cells (docs/light-volume.md, "Adaptive cells"): where the
 * particles cannot tell the cells of a 2 x 2 x 2 block apart (their
 * differences, at the particle count expected, stay within a tolerance of
 * their noise), its stored cells share one tally set, a cell twice the
 * size. A block may merge only if no geometry lies inside it (on its outer
 * faces is fine): its cells then all see each other, so one set holds
 * light of one side of every surface. Merging adds integer tallies, so a
 * set equals the sum of its cells' tallies whenever it was merged, and the
 * same tallies make the same decision on every device. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

/* Per cell: geometry inside it, or a wall lying on its low face along x,
 * y or z. */
#define GEOMETRY_INSIDE 1u
#define WALL_ON_LOW_FACE(axis) (2u << (axis))
/* A box within this (cells) of a cell boundary lies on it. */
#define ON_BOUNDARY 1e-3f

/* Flags the cells whose inside a box of geometry reaches, or, for a box
 * flat on a cell boundary (an axis-aligned wall there), the faces it lies
 * on. Conservative for slanted triangles, whose box covers more cells. */
static void mark_inside(const lv_grid_info *g, const float lo_w[3], const float hi_w[3], void *ctx)
{
    uint8_t *flags = ctx;
    int lo[3], hi[3], flat_axis = -1, flat = 0;
    for (int k = 0; k < 3; k++) {
        float a = (lo_w[k] - g->origin[k]) / g->cell_size, b = (hi_w[k] - g->origin[k]) / g->cell_size;
        lo[k] = (int)floorf(a + ON_BOUNDARY);
        hi[k] = (int)ceilf(b - ON_BOUNDARY) - 1;
        if (hi[k] < lo[k]) { /* within ON_BOUNDARY of boundary lo[k] */
            flat++;
            flat_axis = k;
            hi[k] = lo[k];
        }
        if (lo[k] < 0) lo[k] = 0;
        if (hi[k] > (int)g->dims[k] - 1) hi[k] = (int)g->dims[k] - 1;
        if (lo[k] > hi[k]) return;
    }
    if (flat > 1) return; /* a line or a point has no area */
    uint8_t bit = flat ? WALL_ON_LOW_FACE(flat_axis) : GEOMETRY_INSIDE;
    for (int z = lo[2]; z <= hi[2]; z++)
        for (int y = lo[1]; y <= hi[1]; y++)
            for (int x = lo[0]; x <= hi[0]; x++) flags[lvcl_volume_cell_index(g, x, y, z)] |= bit;
}

/* The block grid of phase `phase` (bit k: blocks start at odd cells along
 * axis k): cell c lies in block (c + phase_k) / 2. */
typedef struct {
    int phase[3];
    uint32_t dims[3];
} block_grid;

static block_grid blocks_of_phase(const lv_grid_info *g, int phase)
{
    block_grid b;
    for (int k = 0; k < 3; k++) {
        b.phase[k] = phase >> k & 1;
        b.dims[k] = (g->dims[k] + (uint32_t)b.phase[k] + 1) / 2;
    }
    return b;
}

static size_t block_index(const block_grid *b, int x, int y, int z)
{
    return (size_t)((x + b->phase[0]) / 2) +
        b->dims[0] * ((size_t)((y + b->phase[1]) / 2) + b->dims[1] * (size_t)((z + b->phase[2]) / 2));
}

/* Per block of b, the cells that may share its tallies: 0 unless the block
 * is clear of geometry (nothing inside any of its cells, no wall on a face
 * between two of them: on the low face of a cell in the block's upper half
 * along that axis; its outer faces may hold walls), else its stored cells
 * that planes do not cut (a cut cell's regions keep their own). */
static void count_members(const lv_grid_info *g, const uint32_t *cell_slot, const uint8_t *flags, const block_grid *b,
                          uint8_t *members)
{
    size_t blocks = (size_t)b->dims[0] * b->dims[1] * b->dims[2];
    enum { BLOCKED = 255 };
    memset(members, 0, blocks);
    for (int z = 0; z < (int)g->dims[2]; z++)
        for (int y = 0; y < (int)g->dims[1]; y++)
            for (int x = 0; x < (int)g->dims[0]; x++) {
                int c[3] = {x, y, z};
                uint8_t f = flags[lvcl_volume_cell_index(g, x, y, z)];
                int blocked = (f & GEOMETRY_INSIDE) != 0;
                for (int k = 0; k < 3; k++)
                    if ((c[k] + b->phase[k]) % 2 == 1 && c[k] > 0 && (f & WALL_ON_LOW_FACE(k))) blocked = 1;
                if (blocked) members[block_index(b, x, y, z)] = BLOCKED;
            }
    for (int z = 0; z < (int)g->dims[2]; z++)
        for (int y = 0; y < (int)g->dims[1]; y++)
            for (int x = 0; x < (int)g->dims[0]; x++) {
                uint32_t entry = cell_slot[lvcl_volume_cell_index(g, x, y, z)];
                uint8_t *m = &members[block_index(b, x, y, z)];
                if (*m != BLOCKED && entry != LV_EMPTY_CELL && !(entry & LV_CUT_CELL)) (*m)++;
            }
    for (size_t i = 0; i < blocks; i++)
        if (members[i] == BLOCKED) members[i] = 0;
}

/* Cells in blocks where at least two may merge. */
static size_t mergeable_cells(const uint8_t *members, size_t blocks)
{
    size_t n = 0;
    for (size_t i = 0; i < blocks; i++)
        if (members[i] >= 2) n += members[i];
    return n;
}

lvcl_error lvcl_volume_find_blocks(lvcl_light_volume *vol, const lvcl_packed_scene *p, lvcl_status *st)
{
    const lv_grid_info *g = &vol->buf.info;
    uint8_t *flags = calloc(vol->cell_count, 1);
    size_t most_blocks = ((size_t)g->dims[0] / 2 + 1) * ((size_t)g->dims[1] / 2 + 1) * ((size_t)g->dims[2] / 2 + 1);
    uint8_t *members = malloc(most_blocks);
    vol->block_of_slot = malloc(((size_t)g->slot_count + 1) * sizeof(uint32_t));
    if (!flags || !members || !vol->block_of_slot) {
        free(flags);
        free(members);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the light volume's blocks");
    }
    lvcl_volume_walk_geometry(p, g, mark_inside, flags);
    /* Of the eight ways to pair cells into blocks, the one that lets most
     * cells merge: walls on every other cell boundary then lie on the
     * blocks' faces (first phase on a tie: deterministic). */
    int best = 0;
    size_t best_cells = 0;
    for (int phase = 0; phase < 8; phase++) {
        block_grid b = blocks_of_phase(g, phase);
        count_members(g, vol->cell_slot, flags, &b, members);
        size_t n = mergeable_cells(members, (size_t)b.dims[0] * b.dims[1] * b.dims[2]);
        if (n > best_cells) {
            best_cells = n;
            best = phase;
        }
    }
    block_grid b = blocks_of_phase(g, best);
    count_members(g, vol->cell_slot, flags, &b, members);
    for (uint32_t s = 0; s <= g->slot_count; s++) vol->block_of_slot[s] = LV_EMPTY_CELL;
    for (int z = 0; z < (int)g->dims[2]; z++)
        for (int y = 0; y < (int)g->dims[1]; y++)
            for (int x = 0; x < (int)g->dims[0]; x++) {
                uint32_t entry = vol->cell_slot[lvcl_volume_cell_index(g, x, y, z)];
                size_t bi = block_index(&b, x, y, z);
                if (members[bi] >= 2 && entry != LV_EMPTY_CELL && !(entry & LV_CUT_CELL))
                    vol->block_of_slot[entry] = (uint32_t)bi;
            }
    vol->block_count = (size_t)b.dims[0] * b.dims[1] * b.dims[2];
    free(flags);
    free(members);
    return LVCL_OK;
}

/* Writes the merged tally sets and the slots' map to the device, in place
 * of the old sets (released first: the host holds the sums). */
static lvcl_error store_sets(lvcl_light_volume *vol, const int64_t *sets, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    for (int i = 0; i < LV_TALLY_PARTS; i++)
        if (vol->buf.tallies[i]) {
            clReleaseMemObject(vol->buf.tallies[i]);
            vol->buf.tallies[i] = NULL;
        }
    size_t old_bytes = vol->tally_bytes;
    lvcl_volume_layout_tallies(vol); /* fewer sets than before: it fits */
    vol->device_bytes = vol->device_bytes - old_bytes + vol->tally_bytes;
    const char *what = "storing the light volume's merged cells";
    lvcl_error e = lvcl_cl_check(lvcl_volume_allocate_tallies(vol), what, st);
    if (!e) e = lvcl_volume_write(vol, sets, NULL, what, st);
    if (!e)
        e = lvcl_cl_check(clEnqueueWriteBuffer(dev->queue, vol->buf.tally_slot, CL_TRUE, 0,
                                               ((size_t)vol->buf.info.slot_count + 1) * sizeof(uint32_t),
                                               vol->tally_slot, 0, NULL, NULL),
                          what, st);
    return e;
}

#define PI 3.14159265358979323846

/* The lit volume of an uncut slot as lv_cell_lit_volume computes it, in
 * double from the integer subcell record, so that the decision below
 * depends on integers alone. */
static double record_lit_volume(const lvcl_light_volume *vol, const uint32_t *records, uint32_t slot)
{
    uint32_t k = vol->buf.info.subcells;
    if (k == 0) return 1.0;
    const uint32_t *marks = records + (size_t)slot * LV_MARK_WORDS;
    const uint32_t *rays = records + LV_MARK_WORDS * ((size_t)vol->buf.info.slot_count + 1);
    double lit = 0, n = (double)(k * k * k);
    for (uint32_t i = 0; i < k * k * k; i++) {
        uint32_t entry = lvcl_region_entry(&vol->regions.slots[slot], i);
        if (!(marks[i >> 5] & (1u << (i & 31u))) || entry == LV_NO_ENTRY) continue;
        const uint32_t *r = rays + (size_t)entry * LV_RAY_WORDS;
        lit += r[0] ? (double)r[1] / r[0] : 1.0;
    }
    return lit / n > 1.0 / n ? lit / n : 1.0 / n;
}

/* The central direction of bin `bin` of n x n per hemisphere, as
 * lv_bin_direction computes it (kernels/volume/direction_map.h), in double
 * on the host. */
static void bin_centre(uint32_t bin, uint32_t n, double w[3])
{
    uint32_t lower = bin >= n * n, cell = bin - (lower ? n * n : 0);
    double a = 2.0 * ((cell % n) + 0.5) / n - 1.0, b = 2.0 * ((cell / n) + 0.5) / n - 1.0;
    double r, phi;
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (PI / 4.0) * (b / a);
    } else {
        r = b;
        phi = PI / 2.0 - (PI / 4.0) * (a / b);
    }
    double dx = r * cos(phi), dy = r * sin(phi), r2 = dx * dx + dy * dy, z = 1.0 - r2;
    double s = r2 > 0 ? sqrt(fmax(0.0, 1.0 - z * z) / r2) : 0.0;
    w[0] = dx * s;
    w[1] = dy * s;
    w[2] = lower ? -z : z;
}

/* The six moments a block's cells are compared by: per axis and sign, the
 * cosine-weighted sum of the bins travelling that way, the irradiance an
 * axis-aligned surface would gather. The gather integrates the BSDF over
 * the bins, so these, not single bins, are what an image shows (less the
 * axis corrections of concentrated light, which merging adds up). */
#define MOMENTS 6

/* Whether the `count` slots in `members` (one block's) should share one
 * tally set: each cell's moments are compared with what it would hold if
 * the block's light were uniform over the cells' lit volumes. chi2, the
 * squared differences over their noise, exceeds its degrees of freedom df
 * by the signal, which grows with the particle count; at `scale` times the
 * particles traced the cells' differences (the bias of merging them) must
 * stay below `tolerance` times the noise they keep apart. */
static int block_should_merge(const int64_t *tallies, const lvcl_light_volume *vol, const uint32_t *records,
                              const double *weights, const uint32_t *members, uint32_t count, uint32_t bins,
                              double scale, double tolerance)
{
    double lit[8], volume = 0;
    for (uint32_t i = 0; i < count; i++) {
        lit[i] = record_lit_volume(vol, records, members[i]);
        volume += lit[i];
    }
    /* Per cell and moment: the sum, and the sum with squared weights (its
     * variance over LV_PIECE_TALLY). */
    double m[8][MOMENTS] = {{0}}, m2[8][MOMENTS] = {{0}}, total[MOMENTS] = {0}, total2[MOMENTS] = {0};
    for (uint32_t i = 0; i < count; i++)
        for (uint32_t b = 0; b < bins; b++) {
            const int64_t *t = &tallies[(size_t)members[i] * LV_SET_LONGS(bins) + 3 * b];
            double x = (double)(t[0] + t[1] + t[2]) / (3.0 * LV_TALLY_SCALE);
            for (int j = 0; j < MOMENTS; j++) {
                double w = weights[(size_t)b * MOMENTS + j];
                m[i][j] += w * x;
                m2[i][j] += w * w * x;
            }
        }
    for (uint32_t i = 0; i < count; i++)
        for (int j = 0; j < MOMENTS; j++) {
            total[j] += m[i][j];
            total2[j] += m2[i][j];
        }
    double chi2 = 0, df = 0;
    for (int j = 0; j < MOMENTS; j++) {
        if (!(total[j] > 0)) continue;
        for (uint32_t i = 0; i < count; i++) {
            double share = lit[i] / volume, expected = total[j] * share, variance = LV_PIECE_TALLY * total2[j] * share;
            if (variance > 0) chi2 += (m[i][j] - expected) * (m[i][j] - expected) / variance;
        }
        df += count - 1;
    }
    return (chi2 - df) * scale < tolerance * df;
}

lvcl_error lvcl_volume_adapt(lvcl_light_volume *vol, double expected_particles, double tolerance, lvcl_status *st)
{
    lv_grid_info *g = &vol->buf.info;
    if (vol->adapted || !(tolerance > 0) || !(expected_particles > 0) || !vol->block_of_slot || !(g->particles > 0))
        return LVCL_OK;
    int64_t *tallies = NULL;
    uint32_t *records = NULL;
    lvcl_error e = lvcl_volume_read(vol, &tallies, &records, st);
    size_t per_set = LV_SET_LONGS(g->bins);
    /* Each block's slots, in slot order: a counting sort by block. */
    uint32_t *start = calloc(vol->block_count + 1, sizeof(uint32_t));
    uint32_t *members = malloc(((size_t)g->slot_count + 1) * sizeof(uint32_t));
    uint32_t *set_of_block = malloc((vol->block_count + 1) * sizeof(uint32_t));
    double *weights = malloc((size_t)g->bins * MOMENTS * sizeof(double));
    if (!e && (!start || !members || !set_of_block || !weights))
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory adapting the light volume");
    if (!e) {
        for (uint32_t b = 0; b < g->bins; b++) {
            double w[3];
            bin_centre(b, g->dirs, w);
            for (int j = 0; j < MOMENTS; j++) {
                double c = (j & 1 ? -1.0 : 1.0) * w[j / 2];
                weights[(size_t)b * MOMENTS + j] = c > 0 ? c : 0.0;
            }
        }
        for (uint32_t s = 0; s < g->slot_count; s++)
            if (vol->block_of_slot[s] != LV_EMPTY_CELL) start[vol->block_of_slot[s] + 1]++;
        for (size_t bi = 0; bi < vol->block_count; bi++) start[bi + 1] += start[bi];
        uint32_t *fill = set_of_block; /* borrowed as the fill cursor */
        memcpy(fill, start, vol->block_count * sizeof(uint32_t));
        for (uint32_t s = 0; s < g->slot_count; s++)
            if (vol->block_of_slot[s] != LV_EMPTY_CELL) members[fill[vol->block_of_slot[s]]++] = s;
        double scale = expected_particles / (double)g->particles;
        for (size_t bi = 0; bi < vol->block_count; bi++) {
            uint32_t count = start[bi + 1] - start[bi];
            int merge = count >= 2 &&
                block_should_merge(tallies, vol, records, weights, members + start[bi], count, g->bins, scale,
                                   tolerance);
            set_of_block[bi] = merge ? LV_EMPTY_CELL - 1 : LV_EMPTY_CELL; /* to be numbered / not merged */
        }
        /* Sets numbered in slot order: a merged block's at its first slot. */
        uint32_t sets = 0;
        vol->merged_cells = 0;
        for (uint32_t s = 0; s < g->slot_count; s++) {
            uint32_t bi = vol->block_of_slot[s];
            if (bi == LV_EMPTY_CELL || set_of_block[bi] == LV_EMPTY_CELL) {
                vol->tally_slot[s] = sets++;
                continue;
            }
            if (set_of_block[bi] == LV_EMPTY_CELL - 1) set_of_block[bi] = sets++;
            vol->tally_slot[s] = set_of_block[bi];
            vol->merged_cells++;
        }
        /* In place: a slot's set is never after it, so every row is read
         * before a set's sums can overwrite it. */
        uint32_t filled = 0;
        for (uint32_t s = 0; s < g->slot_count; s++) {
            int64_t *to = &tallies[(size_t)vol->tally_slot[s] * per_set], *from = &tallies[(size_t)s * per_set];
            if (vol->tally_slot[s] == filled) { /* the set's first slot */
                if (to != from) memmove(to, from, per_set * sizeof(int64_t));
                filled++;
            } else {
                for (size_t i = 0; i < per_set; i++) to[i] += from[i];
            }
        }
        g->tally_sets = sets;
        vol->adapted = 1;
        e = store_sets(vol, tallies, st);
    }
    free(tallies);
    free(records);
    free(weights);
    free(start);
    free(members);
    free(set_of_block);
    return e;
}

lvcl_error lvcl_volume_share_lit(lvcl_light_volume *vol, lvcl_status *st)
{
    if (!vol->merged_cells) return LVCL_OK;
    const lv_grid_info *g = &vol->buf.info;
    float *lit;
    lvcl_error e = lvcl_volume_read_lit(vol, &lit, st);
    if (e) return e;
    double *set_lit = calloc(g->tally_sets ? g->tally_sets : 1, sizeof(double));
    if (!set_lit) {
        free(lit);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the lit volumes");
    }
    for (uint32_t s = 0; s < g->slot_count; s++) set_lit[vol->tally_slot[s]] += lit[s];
    for (uint32_t s = 0; s < g->slot_count; s++) lit[s] = (float)set_lit[vol->tally_slot[s]];
    e = lvcl_volume_write_lit(vol, lit, "storing the merged cells' lit volumes", st);
    free(set_lit);
    free(lit);
    return e;
}
