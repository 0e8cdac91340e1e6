/* Reading radiance back from the light volume (paper eq. 5), and where a
 * gather at a surface reads it (paper section 4.2). */
#ifndef LV_VOLUME_LOOKUP_H
#define LV_VOLUME_LOOKUP_H

#include "direction_map.h"
#include "subcells.h"

/* What turns a bin's raw tally (fixed-point units) into radiance, in a
 * stored cell whose lit volume is `lit` cells and whose set holds n x n
 * bins per hemisphere (paper eq. 5). */
inline float lv_tally_to_radiance(const lv_grid *grid, float lit, uint n)
{
    float h = grid->g.cell_size;
    return grid->g.total_power / (LV_TALLY_SCALE * grid->g.particles * h * h * lit * lv_bin_solid_angle(n));
}

/* A bin's raw RGB tally, as floats. */
inline float3 lv_bin_tally(__global const long *t)
{
    return (float3)((float)t[0], (float)t[1], (float)t[2]);
}

/* Radiance (W m^-2 sr^-1) of one bin of a stored cell. */
inline float3 lv_bin_radiance(const lv_grid *grid, uint slot, uint bin, float lit)
{
    return lv_bin_tally(lv_tally_bin(grid, slot, bin)) * lv_tally_to_radiance(grid, lit, lv_slot_dirs(grid, slot));
}

/* Radiance of the light travelling along `dir` through the cell at p. */
inline float3 lv_volume_radiance(const lv_grid *grid, float3 p, float3 dir)
{
    uint slot = lv_grid_slot_at(grid, p);
    if (slot == LV_EMPTY_CELL) return (float3)(0.0f);
    return lv_bin_radiance(grid, slot, lv_direction_bin(dir, lv_slot_dirs(grid, slot)), grid->lit_volume[slot]);
}

/* The middle of the subcell-thick layer in front of p (without subcells,
 * of the layer an eighth of a cell thick). */
inline float3 lv_front_point(const lv_grid *grid, float3 p, float3 n)
{
    uint k = grid->g.subcells ? grid->g.subcells : 4u;
    return p + n * (0.5f * grid->g.cell_size / (float)k);
}

/* lv_front_point of `from` (p offset off its surface), or, where a
 * surface closer than it faces p (a table top 1 mm above a leg), the point
 * halfway to that surface: a point beyond it reads light that never
 * reaches p (inside a glass slab, the light that total internal reflection
 * traps there). */
inline float3 lv_visible_front_point(const lv_grid *grid, const lv_scene *sc, float3 n, float3 from)
{
    float3 q = lv_front_point(grid, from, n);
    lv_hit h = lv_trace(sc, lv_ray_make(from, q - from, 1.0f, LV_NO_HIT, LV_NO_HIT), 0);
    return h.tri == LV_NO_HIT ? q : from + (q - from) * (0.5f * h.t);
}

/* A uniform point in the cell-sized box around p (paper section 4.2: the
 * lookup then averages neighbouring cells, which hides the grid), folded to
 * the side of the surface that the light arrives on: the half of the box
 * behind the surface holds no light that can reach p, and reading it would
 * darken every surface by about half. n is that side's normal. Where
 * refinement split p's cell for its focused light the box is half a cell,
 * the size of its octants: a whole cell's box would blur what the split
 * resolves (docs/light-volume.md, "Half the box where the light is
 * focused"). */
inline float3 lv_jitter_lookup(const lv_grid *grid, float3 p, float3 n, lv_rng *rng)
{
    float h = grid->g.cell_size;
    uint slot = lv_grid_slot_at(grid, p);
    if (slot != LV_EMPTY_CELL && (grid->regions[slot].flags & LV_REGION_HALF_BOX)) h *= 0.5f;
    float3 offset = (lv_rng_next3(rng) - 0.5f) * h;
    float behind = dot(offset, n);
    if (behind < 0.0f) offset -= 2.0f * behind * n;
    return p + offset;
}

/* What lv_lookup_point found. */
#define LV_POINT_DARK 0      /* no light the volume holds reaches p */
#define LV_POINT_LIT 1       /* *q is where to read it */
#define LV_POINT_UNTRUSTED 2 /* the region there mixes both sides of a surface: a path must answer */

/* Whether the region at q is LV_REGION_MIXED (host volume_planes.c). */
inline int lv_region_mixed(const lv_grid *grid, float3 q)
{
    uint slot = lv_grid_slot_at(grid, q);
    return slot != LV_EMPTY_CELL && (grid->regions[slot].flags & LV_REGION_MIXED);
}

/* Where the gather at a surface point (front normal n) reads the volume;
 * `from` is where its rays leave the point (lv_leave_point), and every
 * point tried is built from it: the surface point itself may lie on
 * another surface's plane (where a wall ends against another), so points
 * built from it lie on that plane too, and the cell's regions may count
 * them on its far side; `from` lies on the side the arriving ray came
 * from. With subcells: the jittered point if light reached it and `from`
 * sees it (near a corner the box reaches behind the other wall); else the
 * layer in front if light reached that; else dark: no light the volume
 * holds reaches the point. Without subcells: the jittered point if `from`
 * sees it, else the layer in front (the region of a cut cell behind a
 * wall holds the other side's light). A jittered point in a mixed region
 * falls back to the layer in front too, and where that is mixed the
 * volume is not read at all. */
inline int lv_lookup_point(const lv_grid *grid, const lv_scene *sc, float3 n, float3 from, lv_rng *rng, float3 *q)
{
    *q = lv_jitter_lookup(grid, from, n, rng);
    int seen = !lv_region_mixed(grid, *q) && !lv_occluded(sc, from, *q - from, 1.0f, LV_NO_HIT, LV_NO_HIT);
    if (grid->g.subcells == 0u) {
        if (!seen) *q = lv_visible_front_point(grid, sc, n, from);
    } else {
        if (seen && lv_point_lit(grid, sc, *q)) return LV_POINT_LIT;
        *q = lv_visible_front_point(grid, sc, n, from);
    }
    if (lv_region_mixed(grid, *q)) return LV_POINT_UNTRUSTED;
    return grid->g.subcells == 0u || lv_point_lit(grid, sc, *q) ? LV_POINT_LIT : LV_POINT_DARK;
}

#endif
