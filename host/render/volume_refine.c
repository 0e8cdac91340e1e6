/* Refined cells (docs/light-volume.md, "Refined cells and directions"): after a first
 * part of the trace, the stored cells that the particles cross most
 * densely are split by axis-aligned planes through their middle, beside
 * the planes of their geometry, so an uncut cell becomes its eight octants
 * and each region of a cut cell the parts of it in each octant (less the
 * axes its planes already run across). The new regions are ordinary region slots. And
 * the slots of other cells whose light is concentrated in few directions
 * take fine bins, 2n x 2n per hemisphere (LV_FINE_DIRS).
 *
 * A refined slot's tallies restart from the particle the split happens at,
 * n0 (LV_RESTARTED in its tally_slot). The session then retraces the
 * particles [0, n0) into those slots alone (lvcl_volume_trace,
 * restarted_only), so that they hold all N particles as every other slot
 * does. Without the retrace a refined slot holds only [n0, N), and its lit
 * volume is scaled by (N - n0) / N (lvcl_volume_scale_split), which keeps
 * eq. 5 unbiased within each region too, at the cost of the particles
 * lost. The decision reads only the integer tallies, so every run and
 * device refines alike. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"

typedef struct {
    double score;   /* pieces per particle */
    double focused; /* the share of its light that came by specular scatters alone */
    uint32_t cell;  /* stored-cell index */
    uint8_t added;  /* planes it gains */
    uint8_t slots;  /* slots it holds now */
} candidate;

/* split_cell[] of a cell split where its light is focused (at least
 * LVCL_REFINE_FOCUS of it came by specular scatters alone, whatever
 * --refine-focus asks): its lookups jitter in half a cell's box
 * (LV_REGION_HALF_BOX), which sharpens focused light and only adds
 * noise to diffuse light. */
#define FOCUSED_SPLIT 2

static int by_score(const void *a, const void *b)
{
    const candidate *x = a, *y = b;
    if (x->score != y->score) return x->score > y->score ? -1 : 1;
    return x->cell < y->cell ? -1 : x->cell > y->cell;
}

/* Adds to c the middle planes of the axes no plane of it is within 25
 * degrees of (the regions' test for one wall), the least aligned first;
 * returns how many. */
static int add_middle_planes(lvcl_cell_planes *c)
{
    int order[3] = {0, 1, 2}, added = 0;
    double align[3];
    for (int a = 0; a < 3; a++) {
        align[a] = 0;
        for (int j = 0; j < c->count; j++) align[a] = fmax(align[a], fabs(c->planes[j][a]));
    }
    for (int i = 1; i < 3; i++)
        for (int j = i; j > 0 && align[order[j]] < align[order[j - 1]]; j--) {
            int t = order[j];
            order[j] = order[j - 1];
            order[j - 1] = t;
        }
    for (int i = 0; i < 3 && c->count < LV_REGION_PLANES; i++) {
        int a = order[i];
        if (align[a] > LVCL_SAME_NORMAL) continue;
        float *p = c->planes[c->count++];
        p[0] = p[1] = p[2] = 0.0f;
        p[a] = 1.0f;
        p[3] = 0.5f;
        added++;
    }
    return added;
}

/* Device bytes one more slot costs at most (tallies, subcell marks, lit
 * volume, tally set, region, a record entry per subcell), and the shares a
 * slot of a cut cell holds at most. */
static size_t slot_bytes(const lv_grid_info *g)
{
    uint32_t k = g->subcells;
    return LV_SET_LONGS(g->bins) * sizeof(int64_t) +
        (LV_MARK_WORDS + 2 + (LV_RAY_WORDS + 1) * k * k * k) * sizeof(uint32_t) + sizeof(lv_slot_region);
}

static size_t share_bytes(const lv_grid_info *g)
{
    uint32_t k = g->subcells;
    return (1u + (k ? k * k * k : 1u)) * sizeof(float);
}

/* The pieces per particle the bins of slots [base, end) hold (sets of
 * per_set longs, their bins' RGB tallies first). */
static double pieces(const int64_t *tallies, size_t per_set, uint32_t base, uint32_t end, double particles)
{
    double sum = 0;
    for (size_t s = base; s < end; s++)
        for (size_t t = s * per_set; t < s * per_set + per_set - LV_AXES - LV_LOBE_LONGS; t++)
            sum += (double)tallies[t];
    return sum / (3.0 * LV_TALLY_SCALE * LV_PIECE_TALLY) / particles;
}

/* Replaces the device's per-slot buffers by ones of the new layout, filled
 * with these tallies and records. */
static lvcl_error store_layout(lvcl_light_volume *vol, const int64_t *tallies, const uint32_t *records, lvcl_status *st)
{
    lv_grid_info info = vol->buf.info;
    lvcl_volume_buffers_release(&vol->buf);
    vol->buf.info = info;
    lvcl_error e = lvcl_volume_place(vol, st);
    if (!e) e = lvcl_volume_allocate(vol, st);
    return e ? e : lvcl_volume_write(vol, tallies, records, "storing the refined light volume", st);
}

/* One past the last slot of the cell whose cell_slot entry is `entry`. */
static uint32_t cell_end(const lv_slot_region *regions, uint32_t slot_count, uint32_t entry)
{
    uint32_t base = entry & ~LV_CUT_CELL, end = base + 1;
    if (entry & LV_CUT_CELL)
        while (end < slot_count && regions[end].base_slot == base) end++;
    return end;
}

/* The share of the luminance that slots [base, end) hold that came by
 * specular scatters alone: their lobes' over their bins'. */
static double focused_share(const int64_t *tallies, size_t per_set, uint32_t bins, uint32_t base, uint32_t end)
{
    double all = 0, focused = 0;
    for (size_t s = base; s < end; s++) {
        const int64_t *t = &tallies[s * per_set];
        for (uint32_t b = 0; b < bins; b++)
            all += LV_LUMINANCE((double)t[3 * b], (double)t[3 * b + 1], (double)t[3 * b + 2]);
        focused += (double)t[3 * bins + LV_AXES + LV_LOBE_LUMINANCE];
    }
    return all > 0 ? focused / all : 0.0;
}

/* Per stored cell (numbered in grid order): its planes and first slot, and
 * for each that can gain a middle plane and holds at least `focus` of
 * focused light a candidate scored by the pieces per particle its tallies
 * hold. Returns the candidates. */
static size_t collect(const lvcl_light_volume *vol, const int64_t *tallies, double focus, lvcl_cell_planes *planes,
                      uint32_t *first_slot, candidate *cand)
{
    const lv_grid_info *g = &vol->buf.info;
    size_t per_set = LV_SET_LONGS(g->bins), count = 0;
    for (size_t i = 0, s = 0; i < vol->cell_count; i++) {
        uint32_t entry = vol->cell_slot[i];
        if (entry == LV_EMPTY_CELL) continue;
        uint32_t base = entry & ~LV_CUT_CELL, end = cell_end(vol->regions.slots, g->slot_count, entry);
        uint32_t cut = vol->regions.slots[base].cut;
        memset(planes[s].planes, 0, sizeof planes[s].planes);
        planes[s].count = 0;
        if (cut != LV_NO_CUT) {
            memcpy(planes[s].planes, vol->regions.cuts[cut].planes, sizeof planes[s].planes);
            planes[s].count = (uint8_t)vol->regions.cuts[cut].plane_count;
        }
        planes[s].mixed = 0; /* the new slots take their old slot's flag (lvcl_volume_refine) */
        planes[s].solids = vol->solid_slabs.of_cell ? vol->solid_slabs.of_cell[s] : LVCL_NO_SOLIDS;
        first_slot[s] = base;
        lvcl_cell_planes trial = planes[s];
        int added = add_middle_planes(&trial);
        double focused = added ? focused_share(tallies, per_set, g->bins, base, end) : 0;
        if (added && (!(focus > 0) || focused >= focus))
            cand[count++] = (candidate){.score = pieces(tallies, per_set, base, end, g->particles),
                                        .focused = focused,
                                        .cell = (uint32_t)s,
                                        .added = (uint8_t)added,
                                        .slots = (uint8_t)(end - base)};
        s++;
    }
    return count;
}

/* For every slot of the new layout, the old slot it lies in (from[]) and
 * whether its cell was split (split_slot[]). A cell that kept its planes
 * keeps its slots in order; each region of a split cell lies in one old
 * region, the one of its pattern's old planes. */
static void remap(const lvcl_light_volume *vol, const uint32_t *new_cell_slot, const lv_slot_region *new_regions,
                  uint32_t new_slots, const uint32_t *first_slot, const uint8_t *split_cell, uint32_t *from,
                  uint8_t *split_slot)
{
    for (size_t i = 0, s = 0; i < vol->cell_count; i++) {
        uint32_t entry = new_cell_slot[i];
        if (entry == LV_EMPTY_CELL) continue;
        uint32_t base = entry & ~LV_CUT_CELL, end = cell_end(new_regions, new_slots, entry), old_base = first_slot[s];
        uint32_t old_cut = vol->regions.slots[old_base].cut;
        const lv_cell_cut *old = old_cut != LV_NO_CUT ? &vol->regions.cuts[old_cut] : NULL;
        uint32_t old_count = old ? old->plane_count : 0;
        for (uint32_t slot = base; slot < end; slot++) {
            from[slot] = old_base + (slot - base);
            split_slot[slot] = split_cell[s];
            if (split_cell[s]) {
                uint32_t pattern = new_regions[slot].region & ((1u << old_count) - 1u);
                from[slot] = old_base + (old_count ? LV_REGION_OFFSET(old, pattern) : 0u);
            }
        }
        s++;
    }
}

/* A slot that may take fine bins, by how concentrated its light is: its
 * brightest bin over the mean bin. */
typedef struct {
    double peak;
    uint32_t slot;
} fine_candidate;

static int by_peak(const void *a, const void *b)
{
    const fine_candidate *x = a, *y = b;
    if (x->peak != y->peak) return x->peak > y->peak ? -1 : 1;
    return x->slot < y->slot ? -1 : x->slot > y->slot;
}

/* Marks in fine[] (per old slot) the slots of cells not split whose
 * brightest bin is at least `peak` times their mean bin and that are dense
 * enough (pieces x N at least `threshold`: a restart costs a slot its first
 * particles), the most concentrated first
 * while the memory lasts; returns how many. */
static size_t choose_fine(const lvcl_light_volume *vol, const int64_t *tallies, const uint32_t *first_slot,
                          const uint8_t *split_cell, size_t stored, double peak, double threshold, double expected,
                          size_t *need, size_t budget, uint8_t *fine)
{
    const lv_grid_info *g = &vol->buf.info;
    size_t per_set = LV_SET_LONGS(g->bins), count = 0, taken = 0, more = 3 * per_set * sizeof(int64_t);
    fine_candidate *cand = malloc(((size_t)g->slot_count + 1) * sizeof *cand);
    if (!cand) return 0;
    for (size_t s = 0; s < stored; s++) {
        if (split_cell[s]) continue;
        uint32_t end = s + 1 < stored ? first_slot[s + 1] : g->slot_count;
        for (uint32_t slot = first_slot[s]; slot < end; slot++) {
            double total = 0, brightest = 0;
            for (uint32_t b = 0; b < g->bins; b++) {
                const int64_t *t = &tallies[(size_t)slot * per_set + 3 * b];
                double x = (double)t[0] + (double)t[1] + (double)t[2];
                total += x;
                if (x > brightest) brightest = x;
            }
            if (!(total > 0) || pieces(tallies, per_set, slot, slot + 1, g->particles) * expected < threshold) continue;
            double p = brightest * g->bins / total;
            if (p >= peak) cand[count++] = (fine_candidate){.peak = p, .slot = slot};
        }
    }
    qsort(cand, count, sizeof *cand, by_peak);
    for (; taken < count && *need + more <= budget; taken++) {
        fine[cand[taken].slot] = 1;
        *need += more;
    }
    free(cand);
    return taken;
}

/* The old layout's shares of a cell that was not split (lvcl_known_shares):
 * a pattern with a slot had its region's shares, one without had none. */
typedef struct {
    const lvcl_light_volume *vol;
    const uint32_t *first_slot; /* per stored cell, in the old layout */
    const uint8_t *split_cell;
    const lvcl_cell_planes *planes;
} old_layout;

static int old_shares(void *ctx, uint32_t s, float *out)
{
    const old_layout *o = ctx;
    if (o->split_cell[s]) return 0;
    const lv_grid_info *g = &o->vol->buf.info;
    uint32_t k = g->subcells, per = 1u + (k ? k * k * k : 1u), base = o->first_slot[s];
    uint32_t patterns = 1u << o->planes[s].count;
    for (uint32_t m = 0; m < patterns; m++) out[m * per] = 0.0f;
    for (uint32_t slot = base; slot < g->slot_count && o->vol->regions.slots[slot].base_slot == base; slot++) {
        const lv_slot_region *r = &o->vol->regions.slots[slot];
        if (r->shares == LV_NO_SHARES) return 0;
        const float *share = o->vol->regions.shares + r->shares;
        float *to = out + r->region * per;
        to[0] = share[0];
        if (!k) to[1] = share[0]; /* the cell's one "subcell" */
        for (uint32_t i = 0; k && i < k * k * k; i++) {
            uint32_t entry = lvcl_region_entry(r, i);
            to[1 + i] = entry == LV_NO_ENTRY ? 0.0f : share[1 + entry - r->entries];
        }
    }
    return 1;
}

/* Gives new slot `slot` (of the grid ng, regions new_regions, records
 * new_records) the subcell record of old slot `old`: the marks, and the
 * entries of the subcells both regions have volume in (a split region
 * holds a part of its old region's subcells). The blocks as
 * lvcl_volume_read lays them out. */
static void copy_record(const lvcl_light_volume *vol, const uint32_t *records, uint32_t old, const lv_grid_info *ng,
                        const lv_slot_region *new_regions, uint32_t *new_records, uint32_t slot)
{
    const lv_grid_info *g = &vol->buf.info;
    size_t old_rays = LV_MARK_WORDS * ((size_t)g->slot_count + 1),
           old_entries = vol->regions.slots[g->slot_count].entries;
    size_t new_rays = LV_MARK_WORDS * ((size_t)ng->slot_count + 1), new_entries = new_regions[ng->slot_count].entries;
    const uint32_t *old_lit = records + old_rays + LV_RAY_WORDS * old_entries;
    uint32_t *new_lit = new_records + new_rays + LV_RAY_WORDS * new_entries;
    memcpy(&new_records[(size_t)slot * LV_MARK_WORDS], &records[(size_t)old * LV_MARK_WORDS],
           LV_MARK_WORDS * sizeof(uint32_t));
    uint32_t k = g->subcells;
    for (uint32_t i = 0; i < k * k * k; i++) {
        uint32_t from = lvcl_region_entry(&vol->regions.slots[old], i), to = lvcl_region_entry(&new_regions[slot], i);
        if (from == LV_NO_ENTRY || to == LV_NO_ENTRY) continue;
        memcpy(&new_records[new_rays + (size_t)to * LV_RAY_WORDS], &records[old_rays + (size_t)from * LV_RAY_WORDS],
               LV_RAY_WORDS * sizeof(uint32_t));
        new_lit[to] = old_lit[from];
    }
}

lvcl_error lvcl_volume_refine(lvcl_light_volume *vol, double expected_particles, const lvcl_volume_settings *vs,
                              lvcl_status *st)
{
    lv_grid_info *g = &vol->buf.info;
    double density = vs->refine_density, peak = vs->refine_peak;
    if (vol->refined || (!(density > 0) && !(peak > 0)) || !(expected_particles > 0) || !(g->particles > 0))
        return LVCL_OK;
    if (vol->block_of_slot) return lvcl_fail(st, LVCL_ERR_USAGE, "--refine cannot be combined with --merge-tolerance");
    vol->refined = 1;
    int64_t *tallies = NULL, *new_tallies = NULL;
    uint32_t *records = NULL, *new_records = NULL, *new_tally_slot = NULL, *from = NULL;
    lvcl_regions new_layout = {0};
    lv_slot_region *new_regions = NULL; /* new_layout.slots */
    uint8_t *split_slot = NULL;
    size_t per_set = LV_SET_LONGS(g->bins), stored = 0;
    for (size_t i = 0; i < vol->cell_count; i++) stored += vol->cell_slot[i] != LV_EMPTY_CELL;
    lvcl_cell_planes *planes = malloc((stored ? stored : 1) * sizeof *planes);
    candidate *cand = malloc((stored ? stored : 1) * sizeof *cand);
    uint32_t *first_slot = malloc((stored ? stored : 1) * sizeof *first_slot);
    uint32_t *new_cell_slot = malloc(vol->cell_count * sizeof *new_cell_slot);
    uint8_t *split_cell = calloc(stored ? stored : 1, 1);
    uint8_t *fine = calloc((size_t)g->slot_count + 1, 1);
    lvcl_error e = lvcl_volume_read(vol, &tallies, &records, st);
    if (!e && (!planes || !cand || !first_slot || !new_cell_slot || !split_cell || !fine))
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory refining the light volume");
    size_t taken = 0, fine_taken = 0;
    if (!e) {
        size_t candidates = collect(vol, tallies, vs->refine_focus, planes, first_slot, cand);
        /* The densest first, while the pieces they will hold pass density
         * x sqrt(particles) and the memory lasts (a region that gains A
         * planes becomes at most 2^A slots, one of them its own already). */
        qsort(cand, candidates, sizeof *cand, by_score);
        size_t budget = vs->refine_memory ? (size_t)vs->refine_memory : 2 * vol->device_bytes, need = vol->device_bytes;
        double threshold = density * sqrt(expected_particles);
        for (; density > 0 && taken < candidates; taken++) {
            const candidate *c = &cand[taken];
            size_t most = (size_t)c->slots << c->added, cut = planes[c->cell].count > 0;
            size_t more = (most - c->slots) * slot_bytes(g) + (most - (cut ? c->slots : 0)) * share_bytes(g) +
                (cut ? 0 : sizeof(lv_cell_cut));
            if (c->score * expected_particles < threshold || need + more > budget) break;
            need += more;
            add_middle_planes(&planes[c->cell]);
            split_cell[c->cell] = c->focused >= LVCL_REFINE_FOCUS ? FOCUSED_SPLIT : 1;
        }
        if (peak > 0)
            fine_taken =
                choose_fine(vol, tallies, first_slot, split_cell, stored, peak,
                            LVCL_FINE_DENSITY * sqrt(expected_particles), expected_particles, &need, budget, fine);
    }
    lv_grid_info ng = *g;
    if (!e && (taken || fine_taken)) {
        for (size_t i = 0, s = 0; i < vol->cell_count; i++)
            new_cell_slot[i] = vol->cell_slot[i] == LV_EMPTY_CELL ? LV_EMPTY_CELL : (uint32_t)s++;
        ng.slot_count = (lv_u32)stored;
        old_layout old = {.vol = vol, .first_slot = first_slot, .split_cell = split_cell, .planes = planes};
        e = lvcl_volume_lay_out_regions(&ng, vol->cell_count, planes, vol->solid_slabs.list, old_shares, &old,
                                        new_cell_slot, &new_layout, st);
        new_regions = new_layout.slots;
        if (!e) {
            size_t n = (size_t)ng.slot_count + 1;
            from = malloc(n * sizeof *from);
            new_tally_slot = malloc(n * sizeof *new_tally_slot);
            split_slot = calloc(n, 1);
            new_records = calloc(LV_MARK_WORDS * n + (LV_RAY_WORDS + 1) * (size_t)new_regions[n - 1].entries + 1,
                                 sizeof(uint32_t));
            if (!from || !new_tally_slot || !split_slot || !new_records)
                e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory refining the light volume");
        }
    }
    size_t sets = 0;
    if (!e && (taken || fine_taken)) {
        remap(vol, new_cell_slot, new_regions, ng.slot_count, first_slot, split_cell, from, split_slot);
        for (uint32_t slot = 0; slot < ng.slot_count; slot++)
            new_regions[slot].flags |= (split_slot[slot] == FOCUSED_SPLIT ? LV_REGION_HALF_BOX : 0u) |
                (vol->regions.slots[from[slot]].flags & LV_REGION_MIXED);
        /* Tally sets in slot order; a set of fine bins takes four sets'
         * room in one buffer (lvcl_volume_layout_tallies puts per_part sets
         * in each). */
        size_t per_part = vol->dev->max_alloc / (per_set * sizeof(int64_t));
        if (per_part > UINT32_MAX) per_part = UINT32_MAX;
        for (uint32_t slot = 0; slot < ng.slot_count; slot++) {
            int f = !split_slot[slot] && fine[from[slot]];
            if (f && per_part && sets / per_part != (sets + 3) / per_part) sets = (sets / per_part + 1) * per_part;
            int restarted = split_slot[slot] || f;
            new_tally_slot[slot] = (uint32_t)sets | (f ? LV_FINE_DIRS : 0u) | (restarted ? LV_RESTARTED : 0u);
            sets += f ? 4 : 1;
            copy_record(vol, records, from[slot], &ng, new_regions, new_records, slot);
        }
        new_tally_slot[ng.slot_count] = 0;
        new_tallies = calloc(sets * per_set + 1, sizeof(int64_t));
        if (!new_tallies) e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory refining the light volume");
        for (uint32_t slot = 0; !e && slot < ng.slot_count; slot++)
            if (!(new_tally_slot[slot] & LV_RESTARTED))
                memcpy(&new_tallies[(size_t)new_tally_slot[slot] * per_set], &tallies[(size_t)from[slot] * per_set],
                       per_set * sizeof(int64_t));
    }
    if (!e && (taken || fine_taken)) {
#define SWAP(field, value)  \
    do {                    \
        free(vol->field);   \
        vol->field = value; \
        value = NULL;       \
    } while (0)
        /* The volume takes the new layout. */
        memcpy(vol->cell_slot, new_cell_slot, vol->cell_count * sizeof *new_cell_slot);
        SWAP(tally_slot, new_tally_slot);
#undef SWAP
        lvcl_regions_free(&vol->regions);
        vol->regions = new_layout;
        new_layout = (lvcl_regions){0};
        vol->split_cells = taken;
        vol->fine_slots = fine_taken;
        vol->split_from = g->particles;
        g->slot_count = ng.slot_count;
        g->tally_sets = (lv_u32)sets;
        e = store_layout(vol, new_tallies, new_records, st);
    }
    free(tallies);
    free(records);
    free(planes);
    free(cand);
    free(first_slot);
    free(new_cell_slot);
    free(split_cell);
    free(fine);
    free(from);
    free(new_tallies);
    free(new_records);
    free(new_tally_slot);
    lvcl_regions_free(&new_layout);
    free(split_slot);
    return e;
}

lvcl_error lvcl_volume_scale_split(lvcl_light_volume *vol, lvcl_status *st)
{
    const lv_grid_info *g = &vol->buf.info;
    if ((!vol->split_cells && !vol->fine_slots) || vol->split_from == 0) return LVCL_OK; /* none, or retraced */
    if (!(g->particles > vol->split_from))
        return lvcl_fail(st, LVCL_ERR_USAGE,
                         "refined slots need particles traced after the split (lvcl_volume_refine)");
    float *lit;
    lvcl_error e = lvcl_volume_read_lit(vol, &lit, st);
    if (e) return e;
    float scale = (float)((g->particles - vol->split_from) / g->particles);
    for (uint32_t s = 0; s < g->slot_count; s++)
        if (vol->tally_slot[s] & LV_RESTARTED) lit[s] *= scale;
    e = lvcl_volume_write_lit(vol, lit, "storing the refined slots' lit volumes", st);
    free(lit);
    return e;
}
