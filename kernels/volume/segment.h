/* Tallying one straight particle segment into every stored cell it
 * crosses, and marking the subcells it passes. */
#ifndef LV_VOLUME_SEGMENT_H
#define LV_VOLUME_SEGMENT_H

#include "../bvh/traverse.h"
#include "tally.h"

/* The subcells that a piece of segment passes in one cell and that were
 * not yet on, as the two words of its mask: from `entry` (in cell units,
 * relative to the cell's corner) along dir for `length` cell units. Points
 * every 1/(2k) of the piece stand in for an exact walk: a piece that only
 * clips a subcell's corner may miss it. Always inlined: it runs for every
 * piece in a cell that geometry cuts, and PoCL called it apart. */
__attribute__((always_inline)) inline uint2 lv_new_subcells(const lv_grid *grid, uint slot, float3 entry, float3 dir,
                                                            float length)
{
    uint k = grid->g.subcells;
    /* Most cells fill up after a few particles, so the walk and the atomics
     * are skipped for bits already set. They are read from the copy made
     * before the batch: OpenCL 1.2 has no atomic load, a plain load of a word
     * that other work-items update atomically is a data race, and reading the
     * live masks with atomic_or(.., 0) made the trace 38% slower. */
    __global const uint *seen = grid->subcells_seen + (size_t)slot * LV_MARK_WORDS;
    uint full = k == 4u ? 0xffffffffu : (1u << (k * k * k)) - 1u;
    uint was[2] = {seen[0], k == 4u ? seen[1] : full};
    if (was[0] == full && was[1] == full) return (uint2)(0u);
    uint bits[2] = {0u, 0u};
    if (k == 4u) {
        /* The default's eight points at once, in vector lanes (the loop
         * below ran as scalar code): the same arithmetic per point. */
        float8 t = length * ((float8)(0.5f, 1.5f, 2.5f, 3.5f, 4.5f, 5.5f, 6.5f, 7.5f)) / 8.0f;
        uint8 cx = min(convert_uint8(clamp(entry.x + dir.x * t, 0.0f, 1.0f) * 4.0f), (uint8)(3u));
        uint8 cy = min(convert_uint8(clamp(entry.y + dir.y * t, 0.0f, 1.0f) * 4.0f), (uint8)(3u));
        uint8 cz = min(convert_uint8(clamp(entry.z + dir.z * t, 0.0f, 1.0f) * 4.0f), (uint8)(3u));
        uint8 bit = cx + 4u * (cy + 4u * cz);
        uint8 one = (uint8)(1u) << (bit & 31u);
        uint8 low = select((uint8)(0u), one, bit < 32u), high = select(one, (uint8)(0u), bit < 32u);
        uint4 low4 = low.lo | low.hi, high4 = high.lo | high.hi;
        uint2 low2 = low4.lo | low4.hi, high2 = high4.lo | high4.hi;
        bits[0] = low2.x | low2.y;
        bits[1] = high2.x | high2.y;
    }
    for (uint j = 0, m = 2u * k; k != 4u && j < m; j++) {
        float3 p = entry + dir * (length * ((float)j + 0.5f) / (float)m);
        uint3 c = min(convert_uint3(clamp(p, 0.0f, 1.0f) * (float)k), (uint3)(k - 1u));
        uint bit = c.x + k * (c.y + k * c.z);
        bits[bit >> 5] |= 1u << (bit & 31u);
    }
    return (uint2)((was[0] & bits[0]) != bits[0] ? bits[0] : 0u, (was[1] & bits[1]) != bits[1] ? bits[1] : 0u);
}

/* Pieces shorter than this (in cell units) switch no subcell on. */
#define LV_MARK_MIN_PIECE 1e-3f

/* How close to a segment's end (in cell units) a cell boundary or a cell's
 * plane counts as where it ends. A segment that ends on a wall ends on the
 * wall's plane only up to rounding: the boundary or plane may fall a
 * rounding error before the end, and the sliver beyond it belongs to the
 * space behind the wall. Weighed by a bright room's particles, such
 * slivers put 0.5% of a dim room's light in its region where a wall ends
 * against another (tests/volume/test_junctions.c). */
#define LV_SEGMENT_END_SLIVER 1e-3f

/* Tallies the piece [a, b] (cell units along dir from `corner`, the
 * segment's origin relative to the cell's corner) into region slot `slot`
 * and marks the subcells it passes there; concentrated light (tables in
 * `concentrated`) also corrects the axis sums, and adds to the lobe where `lobe`. Always inlined: called apart,
 * -cl-fast-relaxed-math rounded the amounts in glass differently on PoCL,
 * and the volumes changed against the recorded goldens. */
__attribute__((always_inline)) inline void lv_tally_piece(const lv_grid *grid, lv_tally_batch *batch, uint slot,
                                                          float3 corner, float3 dir, float a, float b, float h,
                                                          float t0, uint2 bins, float3 weight, float3 sigma,
                                                          const lv_bin_tables *concentrated, int lobe)
{
    /* A retrace fills the restarted slots alone; the others and every
     * slot's subcell record have these particles already. */
    if (grid->restarted_only && !(grid->tally_slot[slot] & LV_RESTARTED)) return;
    /* A segment ending on a wall that lies on a cell boundary pokes a
     * rounding error's length into the cell behind it; marking that would
     * call the space behind the wall lit. */
    uint2 marks = grid->g.subcells && !grid->restarted_only && b - a > LV_MARK_MIN_PIECE
        ? lv_new_subcells(grid, slot, corner + dir * a, dir, b - a)
        : (uint2)(0u);
    /* Track length in cell units, with the absorption integrated over it. */
    float3 amount;
    if (sigma.x > 0.0f || sigma.y > 0.0f || sigma.z > 0.0f) {
        float3 ea = exp(-sigma * (a * h - t0)), eb = exp(-sigma * (b * h - t0));
        amount = select((ea - eb) / (sigma * h), (float3)(b - a), sigma <= 0.0f);
    } else {
        amount = (float3)(b - a);
    }
    int fine = (grid->tally_slot[slot] & LV_FINE_DIRS) != 0u;
    uint bin = fine ? bins.y : bins.x;
    lv_tally_queue(batch, lv_tally_bin(grid, slot, bin), weight * amount,
                   grid->subcell_marks + (size_t)slot * LV_MARK_WORDS, marks);
    if (concentrated) {
        uint n = lv_slot_dirs(grid, slot);
        lv_tally_correct(lv_axis_corrections(grid, slot), weight * amount, dir,
                         fine ? concentrated->fine : concentrated->coarse, 2u * n * n, bin);
        if (lobe) lv_tally_lobe(lv_lobe_sums(grid, slot), weight * amount, dir);
    }
}

/* Adds the segment origin + t dir, t in [t0, t1] (dir unit, t in metres),
 * carrying `weight` (power over total power, over particle count) at t0, to
 * every stored cell it crosses, in bin bins.x of n x n (bins.y of 2n x 2n
 * in a set of fine bins). Where concentrated is not null the segment's
 * light is concentrated (tally.h) and corrects the axis sums, reading its
 * bins' mean cosines from those tables, and where `lobe` also adds to its
 * set's lobe (shared_types.h). sigma > 0 absorbs along the
 * segment (inside glass). A 3-D DDA (Amanatides and Woo) walks the cells;
 * in a cell its planes cut into regions, the piece is split where it
 * crosses them. A segment cannot cross a surface, so a sub-piece across an
 * extended plane (past a wall's end, through a doorway) simply belongs to
 * the region on that side. */
inline void lv_tally_segment(const lv_grid *grid, float3 origin, float3 dir, float t0, float t1, uint2 bins,
                             float3 weight, float3 sigma, const lv_bin_tables *concentrated, int lobe)
{
    const float h = grid->g.cell_size;
    float3 dims = (float3)((float)grid->g.dims[0], (float)grid->g.dims[1], (float)grid->g.dims[2]);
    /* In cell units, relative to the grid's corner. */
    float3 o = (origin - lv_grid_origin(grid)) / h;
    float3 inv = lv_safe_inverse(dir);
    float3 lo = (0.0f - o) * inv, hi = (dims - o) * inv;
    float3 tn = min(lo, hi), tf = max(lo, hi); /* finite: min and max as in lv_child_entries */
    float s0 = max(t0 / h, max(tn.x, max(tn.y, tn.z)));
    float s1 = min(t1 / h, min(tf.x, min(tf.y, tf.z)));
    if (!(s0 < s1)) return;

    float3 p = o + dir * (0.5f * (s0 + fmin(s1, s0 + 1e-3f)));
    int3 cell = clamp(convert_int3(floor(p)), (int3)(0), convert_int3(dims) - 1);
    int3 step = (int3)(dir.x >= 0.0f ? 1 : -1, dir.y >= 0.0f ? 1 : -1, dir.z >= 0.0f ? 1 : -1);
    float3 next_boundary = convert_float3(cell) + select((float3)(0.0f), (float3)(1.0f), step > 0);
    /* Axes the segment runs parallel to are never crossed. */
    float3 s_next = select((next_boundary - o) * inv, (float3)(LV_FAR), fabs(dir) < 1e-30f);
    float3 s_delta = fabs(inv);
    float s = s0;
    int3 idims = convert_int3(dims);
    lv_tally_batch batch;
    batch.count = 0u;
    /* A last piece shorter than the sliver lies past the wall the segment
     * ended on (or is a rounding error's worth of light): left out. */
    const float s_end = s1 - LV_SEGMENT_END_SLIVER;
    while (s < s_end) {
        float s_exit = min(s1, min(s_next.x, min(s_next.y, s_next.z)));
        uint entry = grid->cell_slot[cell.x + idims.x * (cell.y + idims.y * cell.z)];
        if (entry != LV_EMPTY_CELL && s_exit > s && !(entry & LV_CUT_CELL)) {
            /* No planes: one piece, and no read of the region table. */
            float3 corner = o - convert_float3(cell);
            lv_tally_piece(grid, &batch, entry, corner, dir, s, s_exit, h, t0, bins, weight, sigma, concentrated, lobe);
        } else if (entry != LV_EMPTY_CELL && s_exit > s) {
            uint base = entry & ~LV_CUT_CELL;
            float3 corner = o - convert_float3(cell); /* the origin relative to the cell's corner */
            __global const lv_cell_cut *c = lv_cell_cut_of(grid, base);
            uint planes = c->plane_count;
            /* Where the piece crosses the cell's planes, in order: each
             * sub-piece goes to the region of its midpoint. */
            float cut[LV_REGION_PLANES];
            uint cuts = 0u;
            for (uint i = 0; i < planes; i++) {
                float3 n = (float3)(c->planes[i][0], c->planes[i][1], c->planes[i][2]);
                float dn = dot(n, dir);
                if (fabs(dn) < 1e-20f) continue;
                float at = (c->planes[i][3] - dot(n, corner)) / dn;
                /* A plane within the sliver of either end of the segment
                 * is the surface it left or ended on: not crossed. */
                if (at > s && at < s_exit && at > s0 + LV_SEGMENT_END_SLIVER && at < s_end) {
                    uint j = cuts++;
                    for (; j > 0u && cut[j - 1u] > at; j--) cut[j] = cut[j - 1u];
                    cut[j] = at;
                }
            }
            float a = s;
            for (uint j = 0; j <= cuts; j++) {
                float b = j < cuts ? cut[j] : s_exit;
                uint slot = base + LV_REGION_OFFSET(c, lv_region_of(c, corner + dir * (0.5f * (a + b))));
                lv_tally_piece(grid, &batch, slot, corner, dir, a, b, h, t0, bins, weight, sigma, concentrated, lobe);
                a = b;
            }
        }
        s = s_exit;
        /* On to the cell past the nearest boundary (x before y before z on
         * ties), by selects: the axis changes from cell to cell, and as a
         * branch it was mispredicted often enough to cost 3% of the trace. */
        int x_first = s_next.x <= s_next.y && s_next.x <= s_next.z;
        int y_first = !x_first && s_next.y <= s_next.z;
        int3 across = (int3)(x_first ? -1 : 0, y_first ? -1 : 0, x_first || y_first ? 0 : -1);
        cell += select((int3)(0), step, across);
        s_next = select(s_next, s_next + s_delta, across);
        if (any(cell < 0) || any(cell >= idims)) break;
    }
    lv_tally_flush(&batch);
}

#endif
