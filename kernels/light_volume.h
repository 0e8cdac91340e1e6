/* The light volume: tallying particle segments into cells (paper eq. 5) and
 * reading radiance back. See lv_grid_info in shared_types.h for the layout:
 * cell_slot maps a cell (x + dims.x (y + dims.y z)) to its slot or
 * LV_EMPTY_CELL; slot s, bin b, channel c is, with q = slots_per_part,
 * tallies[s / q][((s % q) * bins + b) * 3 + c]. */
#ifndef LV_LIGHT_VOLUME_H
#define LV_LIGHT_VOLUME_H

#if defined(cl_khr_int64_base_atomics) && !defined(LV_EMULATE_INT64_ATOMICS)
#pragma OPENCL EXTENSION cl_khr_int64_base_atomics : enable
#define LV_NATIVE_INT64_ATOMICS
#elif !defined(__ENDIAN_LITTLE__)
#error "64-bit tallies from two 32-bit atomics need a little-endian device"
#endif

#include "direction_map.h"
#include "rng.h"
#include "traverse.h"

typedef struct {
    lv_grid_info g;
    __global const uint *cell_slot;
    __global uint *subcells; /* LV_SUBCELL_STRIDE words per slot (shared_types.h) */
    __global const float *lit_volume; /* per slot, lv_cell_lit_volume after the trace (lookups only) */
    __global long *tallies[LV_TALLY_PARTS];
} lv_grid;

/* The three (RGB) tallies of one bin of a stored cell. */
inline __global long *lv_tally_bin(const lv_grid *grid, uint slot, uint bin)
{
    /* Most grids fit one buffer: skip the division there. */
    uint part = slot < grid->g.slots_per_part ? 0u : slot / grid->g.slots_per_part;
    uint local_slot = slot - part * grid->g.slots_per_part;
    return grid->tallies[part] + ((size_t)local_slot * grid->g.bins + bin) * 3;
}

inline float3 lv_grid_origin(const lv_grid *grid)
{
    return LV_F3(grid->g.origin);
}

/* The slot of the cell holding point p, or LV_EMPTY_CELL. */
inline uint lv_grid_slot_at(const lv_grid *grid, float3 p)
{
    float3 c = (p - lv_grid_origin(grid)) / grid->g.cell_size;
    if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) return LV_EMPTY_CELL;
    uint x = (uint)c.x, y = (uint)c.y, z = (uint)c.z;
    if (x >= grid->g.dims[0] || y >= grid->g.dims[1] || z >= grid->g.dims[2]) return LV_EMPTY_CELL;
    return grid->cell_slot[x + grid->g.dims[0] * (y + grid->g.dims[1] * z)];
}

/* Adds a positive amount to a 64-bit tally. A device without 64-bit
 * atomics (cl_khr_int64_base_atomics is optional; tests force this path
 * with LV_EMULATE_INT64_ATOMICS) adds the low word and carries into the
 * high one: every add's carry lands exactly once, so the tally is exact
 * once the trace has finished, which is when it is read. */
inline void lv_tally_atomic_add(__global long *tally, long units)
{
#ifdef LV_NATIVE_INT64_ATOMICS
    atom_add((volatile __global long *)tally, units);
#else
    volatile __global uint *word = (volatile __global uint *)tally;
    uint low = (uint)units, high = (uint)((ulong)units >> 32);
    uint before = atomic_add(&word[0], low);
    if (before + low < before) high++;
    if (high) atomic_add(&word[1], high);
#endif
}

/* Adds an RGB amount (in tally units of 1) to one bin. Non-finite or
 * negative amounts are dropped; huge ones are clamped, so no bin can
 * overflow (see LV_TALLY_MAX_CONTRIBUTION). */
inline void lv_tally_add(const lv_grid *grid, uint slot, uint bin, float3 amount)
{
    __global long *t = lv_tally_bin(grid, slot, bin);
    float a[3] = {amount.x, amount.y, amount.z};
    for (int c = 0; c < 3; c++) {
        if (!(a[c] > 0.0f) || !isfinite(a[c])) continue;
        long units = (long)(fmin(a[c], LV_TALLY_MAX_CONTRIBUTION) * LV_TALLY_SCALE);
        if (units > 0) lv_tally_atomic_add(&t[c], units);
    }
}

/* Switches on the subcells that a piece of segment passes in one cell:
 * from `entry` (in cell units, relative to the cell's corner) along dir for
 * `length` cell units. Points every 1/(2k) of the piece stand in for an
 * exact walk: a piece that only clips a subcell's corner may miss it. */
inline void lv_mark_subcells(const lv_grid *grid, uint slot, float3 entry, float3 dir, float length)
{
    uint k = grid->g.subcells;
    __global uint *mask = grid->subcells + (size_t)slot * LV_SUBCELL_STRIDE;
    /* Most cells fill up after a few particles; a plain read of a stale
     * value only costs the walk below, never a lost bit. */
    uint full = k == 4u ? 0xffffffffu : (1u << (k * k * k)) - 1u;
    if (mask[0] == full && (k < 4u || mask[1] == full)) return;
    uint m = 2u * k;
    uint bits[2] = {0u, 0u};
    for (uint j = 0; j < m; j++) {
        float3 p = entry + dir * (length * ((float)j + 0.5f) / (float)m);
        uint3 c = min(convert_uint3(clamp(p, 0.0f, 1.0f) * (float)k), (uint3)(k - 1u));
        uint bit = c.x + k * (c.y + k * c.z);
        bits[bit >> 5] |= 1u << (bit & 31u);
    }
    for (int w = 0; w < 2; w++)
        if (bits[w] && (mask[w] & bits[w]) != bits[w]) atomic_or(&mask[w], bits[w]);
}

/* Pieces shorter than this (in cell units) switch no subcell on. */
#define LV_MARK_MIN_PIECE 1e-3f

/* Adds the segment origin + t dir, t in [t0, t1] (dir unit, t in metres),
 * carrying `weight` (power over total power, over particle count) at t0, to
 * every stored cell it crosses, in bin `bin`. sigma > 0 absorbs along the
 * segment (inside glass). A 3-D DDA (Amanatides and Woo) walks the cells. */
inline void lv_tally_segment(const lv_grid *grid, float3 origin, float3 dir, float t0,
                             float t1, uint bin, float3 weight, float3 sigma)
{
    const float h = grid->g.cell_size;
    float3 dims = (float3)((float)grid->g.dims[0], (float)grid->g.dims[1], (float)grid->g.dims[2]);
    /* In cell units, relative to the grid's corner. */
    float3 o = (origin - lv_grid_origin(grid)) / h;
    float3 inv = lv_safe_inverse(dir);
    float3 lo = (0.0f - o) * inv, hi = (dims - o) * inv;
    float3 tn = fmin(lo, hi), tf = fmax(lo, hi);
    float s0 = fmax(t0 / h, fmax(tn.x, fmax(tn.y, tn.z)));
    float s1 = fmin(t1 / h, fmin(tf.x, fmin(tf.y, tf.z)));
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
    while (s < s1) {
        float s_exit = fmin(s1, fmin(s_next.x, fmin(s_next.y, s_next.z)));
        uint slot = grid->cell_slot[cell.x + idims.x * (cell.y + idims.y * cell.z)];
        if (slot != LV_EMPTY_CELL && s_exit > s) {
            /* A segment ending on a wall that lies on a cell boundary pokes
             * a rounding error's length into the cell behind it; marking
             * that would call the space behind the wall lit. */
            if (grid->g.subcells && s_exit - s > LV_MARK_MIN_PIECE)
                lv_mark_subcells(grid, slot, o + dir * s - convert_float3(cell), dir, s_exit - s);
            /* Track length in cell units, with the absorption integrated over it. */
            float3 amount;
            if (sigma.x > 0.0f || sigma.y > 0.0f || sigma.z > 0.0f) {
                float3 a = exp(-sigma * (s * h - t0)), b = exp(-sigma * (s_exit * h - t0));
                amount = select((a - b) / (sigma * h), (float3)(s_exit - s), sigma <= 0.0f);
            } else {
                amount = (float3)(s_exit - s);
            }
            lv_tally_add(grid, slot, bin, weight * amount);
        }
        s = s_exit;
        if (s_next.x <= s_next.y && s_next.x <= s_next.z) {
            cell.x += step.x;
            s_next.x += s_delta.x;
        } else if (s_next.y <= s_next.z) {
            cell.y += step.y;
            s_next.y += s_delta.y;
        } else {
            cell.z += step.z;
            s_next.z += s_delta.z;
        }
        if (any(cell < 0) || any(cell >= idims)) break;
    }
}

/* The lit volume of a stored cell, in cell units (1 = the whole cell), by
 * paper 4.1: the subcells that tallied segments passed, each weighted by the
 * fraction of its visibility rays that reached their particle's origin (1 if
 * no particle hit a surface in it); the whole cell without subcells. */
inline float lv_cell_lit_volume(const lv_grid *grid, uint slot)
{
    uint k = grid->g.subcells;
    if (k == 0u) return 1.0f;
    __global const uint *rec = grid->subcells + (size_t)slot * LV_SUBCELL_STRIDE;
    float lit = 0.0f;
    for (uint i = 0; i < k * k * k; i++) {
        if (!(rec[i >> 5] & (1u << (i & 31u)))) continue;
        uint cast = rec[LV_SUBCELL_CAST + i];
        lit += cast ? (float)rec[LV_SUBCELL_OPEN + i] / (float)cast : 1.0f;
    }
    /* Never below one subcell: some light passed, or the tallies are 0. */
    return fmax(lit, 1.0f) / (float)(k * k * k);
}

/* The index of the subcell holding p within its cell; also the cell's and
 * the subcell's integer coordinates (as floats). */
inline uint lv_subcell_at(const lv_grid *grid, float3 p, float3 *cell, float3 *sub)
{
    uint k = grid->g.subcells;
    float3 c = (p - lv_grid_origin(grid)) / grid->g.cell_size;
    *cell = floor(c);
    *sub = clamp(floor((c - *cell) * (float)k), 0.0f, (float)(k - 1u));
    return (uint)sub->x + k * ((uint)sub->y + k * (uint)sub->z);
}

/* The world-space point at u (each in [0, 1]) within subcell sub of cell
 * `cell` (integer coordinates as lv_subcell_at gives them). */
inline float3 lv_subcell_point(const lv_grid *grid, float3 cell, float3 sub, float3 u)
{
    return lv_grid_origin(grid) + (cell + (sub + u) / (float)grid->g.subcells) * grid->g.cell_size;
}

/* Visibility rays (paper 4.1): where a particle that came from `from` hit a
 * surface at p, one ray from a random point of p's subcell back to `from`;
 * whether it got through estimates how much of the subcell that light
 * reaches (a wall through the subcell blocks the points behind it).
 * Returns the number of rays cast. */
inline uint lv_sample_subcell_visibility(const lv_grid *grid, const lv_scene *sc, float3 p, float3 from, lv_rng *rng)
{
    uint slot = lv_grid_slot_at(grid, p);
    if (slot == LV_EMPTY_CELL) return 0u;
    float3 cell, sub;
    uint i = lv_subcell_at(grid, p, &cell, &sub);
    float3 q = lv_subcell_point(grid, cell, sub, (float3)(lv_rng_next2(rng), lv_rng_next(rng)));
    __global uint *rec = grid->subcells + (size_t)slot * LV_SUBCELL_STRIDE;
    atomic_inc(&rec[LV_SUBCELL_CAST + i]);
    if (!lv_occluded(sc, q, from - q, 0.999f, LV_NO_HIT, LV_NO_HIT)) atomic_inc(&rec[LV_SUBCELL_OPEN + i]);
    return 1u;
}

/* Offers q, a point light reached, as its subcell's lit point. The word
 * kept is the largest offered (a random priority, then the position), so
 * it does not depend on the order particles ran in. */
inline void lv_offer_lit_point(const lv_grid *grid, float3 q, lv_rng *rng)
{
    uint slot = lv_grid_slot_at(grid, q);
    if (slot == LV_EMPTY_CELL) return;
    float3 cell, sub;
    uint i = lv_subcell_at(grid, q, &cell, &sub);
    float3 u = (q - lv_grid_origin(grid)) / grid->g.cell_size - cell;
    uint3 at = min(convert_uint3(clamp(u * (float)grid->g.subcells - sub, 0.0f, 1.0f) * 256.0f), (uint3)(255u));
    uint priority = 1u + min((uint)(lv_rng_next(rng) * 255.0f), 254u);
    atomic_max(&grid->subcells[(size_t)slot * LV_SUBCELL_STRIDE + LV_SUBCELL_LIT_POINT + i],
               priority << 24 | at.x << 16 | at.y << 8 | at.z);
}

/* What turns a bin's raw tally (fixed-point units) into radiance, in a
 * stored cell whose lit volume is `lit` cells (paper eq. 5). */
inline float lv_tally_to_radiance(const lv_grid *grid, float lit)
{
    float h = grid->g.cell_size;
    return grid->g.total_power / (LV_TALLY_SCALE * h * h * lit * lv_bin_solid_angle(grid->g.dirs));
}

/* A bin's raw RGB tally, as floats. */
inline float3 lv_bin_tally(__global const long *t)
{
    return (float3)((float)t[0], (float)t[1], (float)t[2]);
}

/* Radiance (W m^-2 sr^-1) of one bin of a stored cell. */
inline float3 lv_bin_radiance(const lv_grid *grid, uint slot, uint bin, float lit)
{
    return lv_bin_tally(lv_tally_bin(grid, slot, bin)) * lv_tally_to_radiance(grid, lit);
}

/* Radiance of the light travelling along `dir` through the cell at p. */
inline float3 lv_volume_radiance(const lv_grid *grid, float3 p, float3 dir)
{
    uint slot = lv_grid_slot_at(grid, p);
    if (slot == LV_EMPTY_CELL) return (float3)(0.0f);
    return lv_bin_radiance(grid, slot, lv_direction_bin(dir, grid->g.dirs), grid->lit_volume[slot]);
}

/* The middle of the subcell-thick layer in front of p. */
inline float3 lv_front_point(const lv_grid *grid, float3 p, float3 n)
{
    return p + n * (0.5f * grid->g.cell_size / (float)grid->g.subcells);
}

/* A uniform point in the cell-sized box around p (paper section 4.2: the
 * lookup then averages neighbouring cells, which hides the grid), folded to
 * the side of the surface that the light arrives on: the half of the box
 * behind the surface holds no light that can reach p, and reading it would
 * darken every surface by about half. n is that side's normal. */
inline float3 lv_jitter_lookup(const lv_grid *grid, float3 p, float3 n, lv_rng *rng)
{
    float h = grid->g.cell_size;
    float3 offset = ((float3)(lv_rng_next2(rng), lv_rng_next(rng)) - 0.5f) * h;
    float behind = dot(offset, n);
    if (behind < 0.0f) offset -= 2.0f * behind * n;
    return p + offset;
}

/* Whether the light the volume holds reached q (with subcells). A tallied
 * segment must have passed q's subcell, and q must lie in its lit part. A
 * subcell without a lit point had no particle hit a surface in it and is
 * lit throughout. In one that holds a surface, the lit part is the side of
 * its lit point (just off a particle's hit), and q must see that point
 * (the subcell is convex, so only a surface through it can block the way).
 * This keeps a lookup on the dark face of a wall thinner than a subcell
 * from reading the light on the other face. */
inline int lv_point_lit(const lv_grid *grid, const lv_scene *sc, float3 q)
{
    uint slot = lv_grid_slot_at(grid, q);
    if (slot == LV_EMPTY_CELL) return 0;
    float3 cell, sub;
    uint i = lv_subcell_at(grid, q, &cell, &sub);
    __global const uint *rec = grid->subcells + (size_t)slot * LV_SUBCELL_STRIDE;
    if (!(rec[i >> 5] >> (i & 31u) & 1u)) return 0;
    uint word = rec[LV_SUBCELL_LIT_POINT + i];
    if (word == 0u) return 1;
    float3 at = ((float3)((float)(word >> 16 & 255u), (float)(word >> 8 & 255u), (float)(word & 255u)) + 0.5f) / 256.0f;
    float3 lit = lv_subcell_point(grid, cell, sub, at);
    return !lv_occluded(sc, q, lit - q, 1.0f, LV_NO_HIT, LV_NO_HIT);
}

/* Where the gather at surface point p (front normal n) reads the volume.
 * With subcells: the jittered point if light reached it and p sees it (near
 * a corner the box reaches behind the other wall); else the layer in front
 * of p if light reached that; else 0: no light the volume holds reaches p. */
inline int lv_lookup_point(const lv_grid *grid, const lv_scene *sc, float3 p, float3 n, lv_rng *rng, float3 *q)
{
    *q = lv_jitter_lookup(grid, p, n, rng);
    if (grid->g.subcells == 0u) return 1;
    float3 from = lv_offset_origin(p, n, sc->info.scene_scale);
    if (lv_point_lit(grid, sc, *q) && !lv_occluded(sc, from, *q - from, 1.0f, LV_NO_HIT, LV_NO_HIT)) return 1;
    *q = lv_front_point(grid, p, n);
    return lv_point_lit(grid, sc, *q);
}

#endif
