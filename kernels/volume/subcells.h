/* Subcells (paper 4.1): which part of a cell the light that a cell holds
 * actually reached. Segments mark the subcells they pass (segment.h);
 * visibility rays estimate how much of a subcell holding a surface is lit,
 * and a lit point per subcell tells the lit side of that surface. */
#ifndef LV_VOLUME_SUBCELLS_H
#define LV_VOLUME_SUBCELLS_H

#include "../bvh/traverse.h"
#include "../util/rng.h"
#include "grid.h"

/* How far a region's lit volume may pass its volume by the rounding of its
 * subcells' shares against the region's, computed apart. */
#define LV_LIT_ROUNDING 1.0001f

/* The lit volume of a region slot, in cell units (1 = the whole cell), by
 * paper 4.1 within the region: the subcells that tallied segments passed
 * in it, each weighted by the fraction of its visibility rays that reached
 * their particle's origin (1 if none was cast) and by the exact share of
 * the subcell inside the region (region_shares, computed on the host).
 * Without subcells: the region's volume (the whole cell for a cell without
 * planes). Either way never more than the region's volume less the solids
 * in it: light fills only its air. (A thin ceiling's plane left a cell a
 * region of the ceiling's lower half and 0.3 mm of air below it; segments
 * to the ceiling marked its subcells, but their lit points fell in the
 * cell below, so no visibility ray weighed them, and the region counted
 * their whole shares, twenty times its air: a corridor's corner read 6%
 * dark.) A region of no volume holds no point, so nothing reads it. */
inline float lv_cell_lit_volume(const lv_grid *grid, uint slot)
{
    uint k = grid->g.subcells;
    __global const lv_slot_region *r = grid->regions + slot;
    __global const float *share = grid->region_shares + (r->shares == LV_NO_SHARES ? 0u : r->shares);
    float region = r->shares == LV_NO_SHARES ? 1.0f : share[0];
    if (!(region > 0.0f)) return 1.0f;
    if (k == 0u) return region;
    __global const uint *marks = grid->subcell_marks + (size_t)slot * LV_MARK_WORDS;
    float lit = 0.0f, n = (float)(k * k * k);
    int unmarked = 0; /* a subcell of the region no segment passed */
    for (uint i = 0, e = 0; i < k * k * k; i++) {
        if (!(r->present[i >> 5] & (1u << (i & 31u)))) continue;
        uint entry = e++;
        if (!(marks[i >> 5] & (1u << (i & 31u)))) {
            unmarked = 1;
            continue;
        }
        __global const uint *rays = grid->subcell_rays + (size_t)(r->entries + entry) * LV_RAY_WORDS;
        float open = rays[0] ? (float)rays[1] / (float)rays[0] : 1.0f;
        lit += (r->shares == LV_NO_SHARES ? 1.0f : share[1u + entry]) * open;
    }
    /* Where segments passed every subcell of the region, the sum is the
     * whole estimate; else never below one subcell (some light passed, or
     * the tallies are 0), or the region's volume where that is smaller: few
     * particles leave subcells unmarked. (Everywhere, that floor counted a
     * wall's air side narrower than a subcell as a whole one: 2% dark at
     * --subcells 2.) The region's volume leaves out the solids in it (a
     * thin wall's half whose plane the region shares): a corner's sliver of
     * air beside such a wall read 6-9% dark. */
    float sum = unmarked || !(lit > 0.0f) ? fmax(lit / n, fmin(1.0f / n, region)) : lit / n;
    return sum > region * LV_LIT_ROUNDING ? region : sum;
}

/* Where subcell i of slot's region keeps its rays and lit point, or
 * LV_NO_ENTRY where the region has no volume in it (a point on its
 * boundary, by rounding). */
inline uint lv_subcell_entry(const lv_grid *grid, uint slot, uint i)
{
    __global const lv_slot_region *r = grid->regions + slot;
    uint lo = r->present[0], hi = r->present[1];
    if (!(r->present[i >> 5] >> (i & 31u) & 1u)) return LV_NO_ENTRY;
    return r->entries + LV_ENTRIES_BELOW(lo, hi, i);
}

/* The index of the subcell of cell `cell` (integer coordinates, as floats)
 * that holds p, or the nearest where p lies outside the cell (on its
 * face, by rounding); also the subcell's integer coordinates. */
inline uint lv_subcell_in(const lv_grid *grid, float3 p, float3 cell, float3 *sub)
{
    uint k = grid->g.subcells;
    *sub = clamp(floor(((p - lv_grid_origin(grid)) / grid->g.cell_size - cell) * (float)k), 0.0f, (float)(k - 1u));
    return (uint)sub->x + k * ((uint)sub->y + k * (uint)sub->z);
}

/* The index of the subcell holding p within its cell; also the cell's and
 * the subcell's integer coordinates (as floats). */
inline uint lv_subcell_at(const lv_grid *grid, float3 p, float3 *cell, float3 *sub)
{
    *cell = floor((p - lv_grid_origin(grid)) / grid->g.cell_size);
    return lv_subcell_in(grid, p, *cell, sub);
}

/* The world-space point at u (each in [0, 1]) within subcell sub of cell
 * `cell` (integer coordinates as lv_subcell_at gives them). */
inline float3 lv_subcell_point(const lv_grid *grid, float3 cell, float3 sub, float3 u)
{
    return lv_grid_origin(grid) + (cell + (sub + u) / (float)grid->g.subcells) * grid->g.cell_size;
}

/* Visibility rays (paper 4.1): where a particle that came from `from` hit a
 * surface at p, with q the point just off the hit on its side (the lit
 * point it offers), one ray from a random point of the subcell holding p,
 * within q's cell and region, back to `from`; whether it got through
 * estimates how much of that part of the subcell the light reaches (a wall
 * through the subcell blocks the points behind it). The subcell is p's,
 * not q's: where a surface lies within q's offset of a subcell's face, q
 * falls in the next subcell, and the one the surface crosses got no rays
 * and counted as lit throughout, a thin wall's inside too (the dim room
 * read 5-11% dark). The point is uniform in the subcell's part of the
 * region, by rejection: after eight draws outside it no ray is cast (q in
 * their place counted its open view for what lies behind the wall).
 * Counted in q's region slot. Returns the rays cast. */
inline uint lv_sample_subcell_visibility(const lv_grid *grid, const lv_scene *sc, float3 p, float3 q, float3 from,
                                         lv_rng *rng)
{
    uint slot = lv_grid_slot_at(grid, q);
    if (slot == LV_EMPTY_CELL) return 0u;
    float3 cell, sub, at;
    uint entry = lv_subcell_entry(grid, slot, lv_subcell_at(grid, q, &cell, &sub));
    /* p's subcell, counted in q's cell (p may lie on its face), where the
     * region has a part of it. */
    uint hit_entry = lv_subcell_entry(grid, slot, lv_subcell_in(grid, p, cell, &at));
    if (hit_entry != LV_NO_ENTRY) {
        entry = hit_entry;
        sub = at;
    }
    float3 x = lv_subcell_point(grid, cell, sub, lv_rng_next3(rng));
    if (entry == LV_NO_ENTRY) return 0u;
    __global const lv_slot_region *r = grid->regions + slot;
    if (r->cut != LV_NO_CUT) {
        float3 corner = lv_grid_origin(grid) + cell * grid->g.cell_size;
        __global const lv_cell_cut *c = grid->cuts + r->cut;
        uint own = slot - r->base_slot;
        for (int tries = 1; LV_REGION_OFFSET(c, lv_region_of(c, (x - corner) / grid->g.cell_size)) != own; tries++) {
            if (tries == 8) return 0u;
            x = lv_subcell_point(grid, cell, sub, lv_rng_next3(rng));
        }
    }
    __global uint *rays = grid->subcell_rays + (size_t)entry * LV_RAY_WORDS;
    atomic_inc(&rays[0]);
    if (!lv_occluded(sc, x, from - x, 0.999f, LV_NO_HIT, LV_NO_HIT)) atomic_inc(&rays[1]);
    return 1u;
}

/* A lit point offered: where its subcell keeps it (LV_NO_ENTRY: nowhere)
 * and the word (lv_lit_point_offer). */
typedef struct {
    uint entry, word;
} lv_lit_offer;

/* Offers q, a point light reached, as its subcell's lit point (in q's
 * region slot); lv_lit_point_keep stores it. The word kept is the largest
 * offered (a random priority, then the position), so it does not depend
 * on the order particles ran in. Apart, so that the word's line, a random
 * one of the subcell records, is fetched while the particle's segment is
 * tallied (on CPU devices, LV_PRELOAD_TALLIES). */
inline lv_lit_offer lv_lit_point_offer(const lv_grid *grid, float3 q, lv_rng *rng)
{
    lv_lit_offer o = {LV_NO_ENTRY, 0u};
    uint slot = lv_grid_slot_at(grid, q);
    if (slot == LV_EMPTY_CELL) return o;
    float3 cell, sub;
    o.entry = lv_subcell_entry(grid, slot, lv_subcell_at(grid, q, &cell, &sub));
    float3 u = (q - lv_grid_origin(grid)) / grid->g.cell_size - cell;
    uint3 at = min(convert_uint3(clamp(u * (float)grid->g.subcells - sub, 0.0f, 1.0f) * 256.0f), (uint3)(255u));
    uint priority = 1u + min((uint)(lv_rng_next(rng) * 255.0f), 254u);
    o.word = priority << 24 | at.x << 16 | at.y << 8 | at.z;
#ifdef LV_PRELOAD_TALLIES
    if (o.entry != LV_NO_ENTRY) __builtin_prefetch((const void *)(size_t)(grid->lit_points + o.entry), 1, 3);
#endif
    return o;
}

inline void lv_lit_point_keep(const lv_grid *grid, lv_lit_offer o)
{
    if (o.entry != LV_NO_ENTRY) atomic_max(&grid->lit_points[o.entry], o.word);
}

/* Whether the light the volume holds reached q (with subcells). A tallied
 * segment must have passed q's subcell in q's region, and q must lie in its lit part. A
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
    if (!(grid->subcell_marks[(size_t)slot * LV_MARK_WORDS + (i >> 5)] >> (i & 31u) & 1u)) return 0;
    uint entry = lv_subcell_entry(grid, slot, i);
    uint word = entry == LV_NO_ENTRY ? 0u : grid->lit_points[entry];
    if (word == 0u) return 1;
    float3 at = ((float3)((float)(word >> 16 & 255u), (float)(word >> 8 & 255u), (float)(word & 255u)) + 0.5f) / 256.0f;
    float3 lit = lv_subcell_point(grid, cell, sub, at);
    return !lv_occluded(sc, q, lit - q, 1.0f, LV_NO_HIT, LV_NO_HIT);
}

#endif
