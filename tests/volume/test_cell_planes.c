/* The cells' planes (host/render/volume_planes.c), on the host alone. A
 * shelf over a block (a table top over a leg, a panel beside a cupboard),
 * in a closed room: in every cell the stack cuts, the thin layer of air
 * between the block's top and the shelf must fall in another region than
 * the air just beyond the shelf and than the block's inside, or a lookup
 * in the gap reads light that never reaches it (too bright from beyond,
 * too dark from a region whose volume holds the block's inside). Varied:
 * gaps of 1 mm to 3 cm, shelves 1 and 3 cm thick, a block as wide as the
 * shelf, a leg 4 cm square, and a shelf narrower than the block, 12 to 32
 * cells at grid offsets 0, 0.37 and 0.5, the stack along each axis, and
 * its triangles in three orders. The planes must also be the same
 * whichever order the triangles come in. And where a wall between two
 * rooms shares its cells with three such gaps (two shelves stacked over
 * a block against it), the wall keeps a plane: the gaps take two at most.
 * So does a wall between two rooms built of slabs, where it meets them (a
 * cell holds both faces of each slab: a solid's second face is spare),
 * with the rooms turned so that no wall faces a grid axis, also a wall
 * modelled twice, the copies overlapping. And a panel
 * against a wall, or a second wall of one polygon behind it round a
 * narrow corridor, stays a plane of its own (a layer, not one cluster),
 * and both corridor walls keep their planes where they meet the floor and
 * an outer wall of a room of one-polygon walls (four planes in one cell;
 * corridors 2 to 20 cm wide, four turns, 12 to 32 cells, three offsets;
 * 2 and 3 cm at 5 to 8 cells, where they are 2 to 6% of a cell).
 *
 * Holds while the gap is narrower than a quarter cell: the two surfaces
 * facing each other across it take a cell's first two planes, the
 * heaviest other cluster its third.
 *
 * Also the subcell records' layout (shared_types.h) on some of these
 * grids with k = 1 to 4 subcells: a region's entries are the subcells it
 * has volume in, its shares theirs (against lvcl_region_shares; its volume
 * that, or less where solids' slabs lie in it), the
 * regions of a cell cover every subcell, and the entries follow each other
 * slot by slot. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/render/light_volume_internal.h"
#include "../check.h"
#include "../harness.h"

#define MAX_TRIS 64
#define LATTICE 9 /* points per side over the stack's footprint */

typedef struct {
    float block, shelf;   /* widths, metres */
    float gap, thickness; /* metres */
} stack;

/* Box lo..hi of the stack's frame (x, up, z) placed with `up` along world
 * axis `axis`. */
static size_t add_box_along(float *t, size_t n, int axis, const float lo[3], const float hi[3])
{
    float wlo[3], whi[3];
    for (int k = 0; k < 3; k++) {
        int w = (axis + k + 2) % 3; /* x -> axis + 2, up -> axis, z -> axis + 1 */
        wlo[w] = lo[k];
        whi[w] = hi[k];
    }
    return harness_add_box(t, n, wlo, whi);
}

static void to_world(int axis, const double local[3], float world[3])
{
    for (int k = 0; k < 3; k++) world[(axis + k + 2) % 3] = (float)local[k];
}

/* The stack's triangles, in the order asked, in tris; returns their count. */
static size_t make_stack(const stack *u, int axis, int shelf_first, int reversed, float *tris)
{
    size_t n = 0;
    const float room_lo[3] = {-1, 0, -1}, room_hi[3] = {1, 2, 1};
    const float base = 0.9f, b = 0.5f * u->block, s = 0.5f * u->shelf;
    const float block_lo[3] = {-b, 0, -b}, block_hi[3] = {b, base, b};
    const float shelf_lo[3] = {-s, base + u->gap, -s}, shelf_hi[3] = {s, base + u->gap + u->thickness, s};
    n = add_box_along(tris, n, axis, room_lo, room_hi);
    n = add_box_along(tris, n, axis, shelf_first ? shelf_lo : block_lo, shelf_first ? shelf_hi : block_hi);
    n = add_box_along(tris, n, axis, shelf_first ? block_lo : shelf_lo, shelf_first ? block_hi : shelf_hi);
    if (reversed)
        for (size_t i = 0; i < n / 2; i++)
            for (int k = 0; k < 9; k++) {
                float x = tris[9 * i + k];
                tris[9 * i + k] = tris[9 * (n - 1 - i) + k];
                tris[9 * (n - 1 - i) + k] = x;
            }
    return n;
}

/* Point p's cell (its index, or -1 outside) and the slot of its region. */
static uint32_t slot_at(const harness_regions *r, const float p[3], long *cell)
{
    return lvcl_volume_grid_slot_at(&r->g, r->slot, &r->regions, p, cell);
}

/* Whether points a and b share a cell and its region; counts the pairs
 * that share a cell in *pairs. */
static int share_region(const harness_regions *r, const float a[3], const float b[3], int *pairs)
{
    long ca, cb;
    uint32_t sa = slot_at(r, a, &ca), sb = slot_at(r, b, &cb);
    if (ca != cb || ca < 0) return 0;
    (*pairs)++;
    return sa == sb;
}

/* Of the lattice points over the stack's footprint whose gap point shares
 * a cell with the point beyond the shelf (or inside the block), how many
 * share its region too. */
static int shared_regions(const harness_regions *r, const stack *u, int axis, int *pairs)
{
    const double base = 0.9, half = 0.5 * fmin(u->block, u->shelf) - 1e-3;
    const double ups[3] = {base + 0.5 * u->gap, base + u->gap + u->thickness + 0.5 * u->gap, base - 0.5 * u->gap};
    int shared = 0;
    *pairs = 0;
    for (int i = 0; i < LATTICE; i++)
        for (int j = 0; j < LATTICE; j++) {
            long cells[3];
            uint32_t slots[3];
            for (int q = 0; q < 3; q++) {
                double local[3] = {-half + 2 * half * i / (LATTICE - 1), ups[q], -half + 2 * half * j / (LATTICE - 1)};
                float p[3];
                to_world(axis, local, p);
                slots[q] = slot_at(r, p, &cells[q]);
            }
            for (int q = 1; q < 3; q++)
                if (cells[q] == cells[0]) {
                    (*pairs)++;
                    shared += slots[q] == slots[0];
                }
        }
    return shared;
}

/* Whether two builds gave every cell the same planes (to 10^-5). */
static int same_planes(const harness_regions *a, const harness_regions *b, size_t cells)
{
    if (a->g.slot_count != b->g.slot_count) return 0;
    for (size_t c = 0; c < cells; c++) {
        if (a->slot[c] != b->slot[c]) return 0;
        if (a->slot[c] == LV_EMPTY_CELL || !(a->slot[c] & LV_CUT_CELL)) continue;
        const lv_cell_cut *ca = &a->regions.cuts[a->regions.slots[a->slot[c] & ~LV_CUT_CELL].cut];
        const lv_cell_cut *cb = &b->regions.cuts[b->regions.slots[b->slot[c] & ~LV_CUT_CELL].cut];
        if (ca->plane_count != cb->plane_count) return 0;
        for (uint32_t i = 0; i < ca->plane_count; i++)
            for (int k = 0; k < 4; k++)
                if (fabsf(ca->planes[i][k] - cb->planes[i][k]) > 1e-5f) return 0;
    }
    return 1;
}

/* Two shelves 1 cm thick stacked 2 mm apart over a block, against one
 * side of a wall 2 cm thick between two rooms: a cell holding the wall
 * and the stack's end has three clusters across gaps (the block's top
 * and both shelves), and the wall must keep a plane there. Returns how
 * many point pairs across the wall (at the gaps' and the shelves' heights)
 * share a cell and a region; *pairs counts those sharing a cell. */
static int wall_beside_gaps(int cells, double offset, int *pairs, int *built)
{
    const float wall = 0.37f, base = 0.9f;
    float tris[MAX_TRIS * 9];
    size_t n = 0;
    const float room_lo[3] = {-1, 0, -1}, room_hi[3] = {1, 2, 1};
    const float wall_lo[3] = {wall, 0, -1}, wall_hi[3] = {wall + 0.02f, 2, 1};
    const float block_lo[3] = {wall - 0.6f, 0, -0.3f}, block_hi[3] = {wall, base, 0.3f};
    n = harness_add_box(tris, n, room_lo, room_hi);
    n = harness_add_box(tris, n, wall_lo, wall_hi);
    n = harness_add_box(tris, n, block_lo, block_hi);
    for (int k = 0; k < 2; k++) {
        const float lo[3] = {wall - 0.6f, base + 0.002f + 0.012f * k, -0.3f};
        const float hi[3] = {wall, lo[1] + 0.01f, 0.3f};
        n = harness_add_box(tris, n, lo, hi);
    }
    harness_regions r;
    memset(&r, 0, sizeof r);
    int shared = 0;
    *pairs = 0;
    *built = harness_build_regions("cell planes", tris, n, cells, offset, 0, &r);
    const float heights[4] = {base + 0.001f, base + 0.007f, base + 0.013f, base + 0.019f};
    for (int i = 0; *built && i < 4; i++)
        for (int j = 0; j < LATTICE; j++) {
            float z = -0.2f + 0.4f * (float)j / (LATTICE - 1);
            const float here[3] = {wall - 0.005f, heights[i], z}, there[3] = {wall + 0.025f, heights[i], z};
            shared += share_region(&r, here, there, pairs);
        }
    harness_free_regions(&r);
    return shared;
}

/* Two rooms sharing a wall (harness_two_rooms) in a building of slabs
 * `shell` thick, turned by yaw and pitch (degrees): of the point pairs 4 mm
 * either side of the wall (a lattice over it, up to 4 mm from the floor,
 * the ceiling and the outer walls), returns how many share a cell and a
 * region; *pairs counts those sharing a cell. Where the wall meets an
 * outer wall and the floor, a cell holds five or more clusters (both
 * faces of each slab), and the wall must keep a plane. twin (metres, 0:
 * none): a second copy of the wall that far along x, overlapping it (a
 * wall modelled twice): its ends and foot lie in the outer walls' and
 * the floor's planes beside the first wall's, and together weigh more
 * there than those surfaces' parts in the cell. door, panel (metres, 0:
 * none): a doorway that wide in the first copy, which the second closes,
 * and a cupboard that deep against the wall in the dim room, beside the
 * doorway: the doorway's side and the cupboard's face each other, a few
 * centimetres apart, but each against its own wall. */
static int wall_in_building(float wall, float shell, float twin, float door, float panel, float yaw, float pitch,
                            int cells, double offset, int *pairs, int *built)
{
    float tris[(HARNESS_TWO_ROOMS_TRIANGLES + 12) * 9];
    size_t walls, n = harness_two_rooms(tris, wall, shell, panel, door, 0, 0, &walls);
    if (twin != 0) {
        const float lo[3] = {HARNESS_WALL_X - wall / 2 + twin, 0, -HARNESS_ROOMS_Z},
                    hi[3] = {HARNESS_WALL_X + wall / 2 + twin, HARNESS_ROOMS_Y, HARNESS_ROOMS_Z};
        n = harness_add_box(tris, n, lo, hi);
    }
    for (size_t v = 0; v < 3 * n; v++) harness_turn(&tris[3 * v], yaw, pitch);
    const float near_x = HARNESS_WALL_X + wall / 2 + fmaxf(twin, 0), far_x = HARNESS_WALL_X - wall / 2 + fminf(twin, 0);
    harness_regions r;
    int shared = 0;
    *pairs = 0;
    *built = harness_build_regions("cell planes", tris, n, cells, offset, 0, &r);
    const float inset = 0.004f, y_span = HARNESS_ROOMS_Y - 2 * inset, z_span = 2 * HARNESS_ROOMS_Z - 2 * inset;
    for (int i = 0; *built && i < 2 * LATTICE; i++)
        for (int j = 0; j < 2 * LATTICE; j++) {
            float y = inset + y_span * (float)i / (2 * LATTICE - 1);
            float z = -HARNESS_ROOMS_Z + inset + z_span * (float)j / (2 * LATTICE - 1);
            float here[3] = {near_x + inset, y, z}, there[3] = {far_x - inset, y, z};
            harness_turn(here, yaw, pitch);
            harness_turn(there, yaw, pitch);
            shared += share_region(&r, here, there, pairs);
        }
    if (*built) harness_free_regions(&r);
    return shared;
}

/* Two parallel layers facing the same way, `apart` metres apart, in a
 * closed room, away from its edges: a panel (`panel` 1: a box of that
 * depth standing on the floor against a wall of one polygon, up to 0.9 m)
 * or a corridor (0: a second wall of one polygon behind the first). Both
 * face +x, so neither faces the other across a gap nor backs onto it.
 * Returns how many point pairs sharing a cell share a region: the air
 * just in front of the wall (above the panel) and just behind it, and for
 * the corridor its middle and the air in front and beyond. */
static int layers_apart(int panel, float apart, int cells, double offset, int *pairs, int *built)
{
    const float wall = 0.37f;
    float tris[MAX_TRIS * 9];
    size_t n = 0;
    const float room_lo[3] = {-1, 0, -1}, room_hi[3] = {1, 2, 1};
    n = harness_add_box(tris, n, room_lo, room_hi);
    const float up[3] = {0, 2, 0}, across[3] = {0, 0, 2};
    const float front[3] = {wall, 0, -1}, back[3] = {wall - apart, 0, -1};
    n = harness_add_quad(tris, n, front, up, across); /* facing +x */
    if (panel) {
        const float lo[3] = {wall, 0, -0.5f}, hi[3] = {wall + apart, 0.9f, 0.5f};
        n = harness_add_box(tris, n, lo, hi);
    } else {
        n = harness_add_quad(tris, n, back, up, across);
    }
    harness_regions r;
    int shared = 0;
    *pairs = 0;
    *built = harness_build_regions("cell planes", tris, n, cells, offset, 0, &r);
    const float inset = 0.004f;
    const float xs[3][2] = {{wall + inset, wall - inset}, /* the panel: in front of the wall and behind */
                            {wall - apart / 2, wall + inset},
                            {wall - apart / 2, wall - apart - inset}};
    for (int k = panel ? 0 : 1; *built && k < (panel ? 1 : 3); k++)
        for (int i = 0; i < LATTICE; i++)
            for (int j = 0; j < LATTICE; j++) {
                float y = (panel ? 0.95f : 0.6f) + 0.8f * (float)i / (LATTICE - 1),
                      z = -0.4f + 0.8f * (float)j / (LATTICE - 1);
                const float a[3] = {xs[k][0], y, z}, b[3] = {xs[k][1], y, z};
                shared += share_region(&r, a, b, pairs);
            }
    if (*built) harness_free_regions(&r);
    return shared;
}

/* Two walls of one polygon facing +x (or, `away`, the first facing -x:
 * back to back, as a solid's two faces would be, but open, so the space
 * between them may hold light), `apart` metres apart round a
 * corridor, across a room of one-polygon walls (harness_add_room), turned
 * by yaw and pitch (degrees): of the point pairs from the corridor's
 * middle to 4 mm beyond either wall (a lattice over the walls, up to 4 mm
 * from the floor, the ceiling and the outer walls), returns how many share
 * a cell and a region; *pairs counts those sharing a cell. Where the walls
 * meet the floor and an outer wall a cell holds four distinct planes, and
 * both walls must keep theirs. */
static int corridor_in_room(float apart, int away, float yaw, float pitch, int cells, double offset, int *pairs,
                            int *built)
{
    const float X = HARNESS_ROOMS_X, Y = HARNESS_ROOMS_Y, Z = HARNESS_ROOMS_Z, W = HARNESS_WALL_X;
    float tris[MAX_TRIS * 9];
    const float lo[3] = {-X, 0, -Z}, hi[3] = {X, Y, Z}, up[3] = {0, Y, 0}, across[3] = {0, 0, 2 * Z};
    size_t n = harness_add_room(tris, 0, lo, hi);
    for (int k = 0; k < 2; k++) {
        const float corner[3] = {W + (float)k * apart, 0, -Z};
        n = away && k == 0 ? harness_add_quad(tris, n, corner, across, up)
                           : harness_add_quad(tris, n, corner, up, across);
    }
    for (size_t v = 0; v < 3 * n; v++) harness_turn(&tris[3 * v], yaw, pitch);
    harness_regions r;
    int shared = 0;
    *pairs = 0;
    *built = harness_build_regions("cell planes", tris, n, cells, offset, 0, &r);
    const float inset = 0.004f, y_span = Y - 2 * inset, z_span = 2 * Z - 2 * inset;
    const float beyond[2] = {W - inset, W + apart + inset};
    for (int i = 0; *built && i < 2 * LATTICE; i++)
        for (int j = 0; j < 2 * LATTICE; j++)
            for (int k = 0; k < 2; k++) {
                float y = inset + y_span * (float)i / (2 * LATTICE - 1);
                float z = -Z + inset + z_span * (float)j / (2 * LATTICE - 1);
                float middle[3] = {W + apart / 2, y, z}, out[3] = {beyond[k], y, z};
                harness_turn(middle, yaw, pitch);
                harness_turn(out, yaw, pitch);
                shared += share_region(&r, middle, out, pairs);
            }
    if (*built) harness_free_regions(&r);
    return shared;
}

/* Checks the subcell records' layout of r (k subcells); returns the
 * number of faults, and counts the cut cells in *cut. */
static int record_faults(const harness_regions *r, uint32_t k, size_t cells, int *cut)
{
    enum { PER = 1 + LV_SUBCELL_MAX };
    const uint32_t sub = k * k * k;
    const uint64_t all = sub == 64 ? ~(uint64_t)0 : ((uint64_t)1 << sub) - 1;
    int faults = 0;
    float full[(1 << LV_REGION_PLANES) * PER];
    for (uint32_t s = 0; s < r->g.slot_count; s++) {
        const lv_slot_region *e = &r->regions.slots[s];
        uint64_t present = e->present[0] | (uint64_t)e->present[1] << 32;
        faults += r->regions.slots[s + 1].entries != e->entries + (uint32_t)__builtin_popcountll(present);
        faults += e->cut == LV_NO_CUT && (present != all || e->shares != LV_NO_SHARES);
        faults += e->cut != LV_NO_CUT &&
            (e->cut >= r->regions.cut_count || r->regions.cuts[e->cut].plane_count == 0 ||
             e->cut != r->regions.slots[e->base_slot].cut);
    }
    *cut = 0;
    for (size_t c = 0; c < cells; c++) {
        if (r->slot[c] == LV_EMPTY_CELL || !(r->slot[c] & LV_CUT_CELL)) continue;
        uint32_t base = r->slot[c] & ~LV_CUT_CELL, per = 1 + sub;
        const lv_cell_cut *planes = &r->regions.cuts[r->regions.slots[base].cut];
        (*cut)++;
        lvcl_region_shares((const float(*)[4])planes->planes, (int)planes->plane_count, k, full);
        uint64_t covered = 0;
        for (uint32_t s = base; s < r->g.slot_count && r->regions.slots[s].base_slot == base; s++) {
            const lv_slot_region *e = &r->regions.slots[s];
            const float *want = full + e->region * per, *got = r->regions.shares + e->shares;
            /* The region's volume, less the solids' slabs in it where it
             * holds any (test_region_shares.c checks those against the air). */
            faults += !(got[0] == want[0] || (got[0] < want[0] && got[0] >= 1e-3f * want[0]));
            for (uint32_t i = 0; i < sub; i++) {
                uint32_t entry = lvcl_region_entry(e, i);
                faults += (entry != LV_NO_ENTRY) != (want[1 + i] > 0.0f);
                if (entry != LV_NO_ENTRY) {
                    faults += got[1 + entry - e->entries] != want[1 + i];
                    covered |= (uint64_t)1 << i;
                }
            }
        }
        faults += covered != all;
    }
    return faults;
}

int main(void)
{
    const stack stacks[] = {
        {0.6f, 0.6f, 0.001f, 0.03f},  {0.6f, 0.6f, 0.005f, 0.01f}, {0.04f, 0.8f, 0.001f, 0.03f},
        {0.04f, 0.8f, 0.003f, 0.01f}, {0.6f, 0.3f, 0.002f, 0.03f}, {0.6f, 0.3f, 0.03f, 0.01f},
    };
    const int cell_counts[] = {12, 16, 24, 32};
    const double offsets[] = {0.0, 0.37, 0.5};
    for (size_t si = 0; si < sizeof stacks / sizeof stacks[0]; si++)
        for (int axis = 0; axis < 3; axis++) {
            const stack *u = &stacks[si];
            int shared = 0, pairs = 0, built = 1, same = 1, cases = 0;
            for (size_t ci = 0; ci < sizeof cell_counts / sizeof cell_counts[0]; ci++) {
                int cells = cell_counts[ci];
                double h = 2.0 / cells; /* the room's longest side over the cell count */
                if (u->gap >= 0.25 * h) continue;
                for (size_t oi = 0; oi < sizeof offsets / sizeof offsets[0]; oi++) {
                    harness_regions r[3];
                    memset(r, 0, sizeof r);
                    for (int v = 0; v < 3 && built; v++) {
                        float tris[MAX_TRIS * 9];
                        size_t n = make_stack(u, axis, v == 1, v == 2, tris);
                        built &= harness_build_regions("cell planes", tris, n, cells, offsets[oi], 0, &r[v]);
                    }
                    if (built) {
                        size_t count = (size_t)r[0].g.dims[0] * r[0].g.dims[1] * r[0].g.dims[2];
                        for (int v = 0; v < 3; v++) {
                            int p;
                            shared += shared_regions(&r[v], u, axis, &p);
                            pairs += p;
                        }
                        same &= same_planes(&r[0], &r[1], count) && same_planes(&r[0], &r[2], count);
                        cases++;
                    }
                    for (int v = 0; v < 3; v++) harness_free_regions(&r[v]);
                }
            }
            char name[200];
            snprintf(name, sizeof name,
                     "cell planes: block %g cm under a shelf %g cm wide, gap %g mm, shelf %g cm, along axis %d",
                     1e2 * u->block, 1e2 * u->shelf, 1e3 * u->gap, 1e2 * u->thickness, axis);
            CHECK(name, built && shared == 0 && pairs > 0, "%d of %d point pairs in one cell share a region (%d grids)",
                  shared, pairs, cases);
            snprintf(name, sizeof name,
                     "cell planes: the same whatever the triangles' order (block %g cm, gap %g mm, axis %d)",
                     1e2 * u->block, 1e3 * u->gap, axis);
            CHECK(name, built && same, "the planes differ between orders");
        }
    int shared = 0, pairs = 0, built = 1;
    for (size_t ci = 0; ci < sizeof cell_counts / sizeof cell_counts[0]; ci++)
        for (size_t oi = 0; oi < sizeof offsets / sizeof offsets[0]; oi++) {
            int p, b;
            shared += wall_beside_gaps(cell_counts[ci], offsets[oi], &p, &b);
            pairs += p;
            built &= b;
        }
    CHECK("cell planes: a wall beside three gaps keeps its plane", built && shared == 0 && pairs > 0,
          "%d of %d point pairs across the wall in one cell share a region", shared, pairs);
    const float wall_widths[] = {0.0f, 0.005f, 0.03f, 0.1f, 0.2f}, shells[] = {0.0f, 0.02f, 0.05f, 0.1f, 0.3f};
    const float turns[][2] = {{0, 0}, {12, 7}, {30, 0}, {61, 23}};
    for (size_t wi = 0; wi < sizeof wall_widths / sizeof *wall_widths; wi++)
        for (size_t si = 0; si < sizeof shells / sizeof *shells; si++) {
            int shared = 0, pairs = 0, built = 1;
            for (size_t ti = 0; ti < sizeof turns / sizeof *turns; ti++)
                for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
                    for (size_t oi = 0; oi < 2; oi++) {
                        int p, b;
                        shared += wall_in_building(wall_widths[wi], shells[si], 0, 0, 0, turns[ti][0], turns[ti][1],
                                                   cell_counts[ci], offsets[oi], &p, &b);
                        pairs += p;
                        built &= b;
                    }
            char name[160];
            snprintf(name, sizeof name,
                     "cell planes: a wall %g cm thick between rooms of slabs %g cm thick keeps its plane",
                     1e2 * wall_widths[wi], 1e2 * shells[si]);
            CHECK(name, built && shared == 0 && pairs > 0,
                  "%d of %d point pairs across the wall in one cell share a region", shared, pairs);
        }
    /* A wall modelled twice, the copy shifted by 5 mm to 5 cm either
     * way. */
    const float twins[] = {0.005f, -0.01f, 0.03f, -0.05f};
    const float twin_walls[] = {0.06f, 0.2f}, twin_shells[] = {0.02f, 0.1f};
    for (size_t wi = 0; wi < sizeof twin_walls / sizeof *twin_walls; wi++)
        for (size_t si = 0; si < sizeof twin_shells / sizeof *twin_shells; si++) {
            int shared = 0, pairs = 0, built = 1;
            for (size_t xi = 0; xi < sizeof twins / sizeof *twins; xi++)
                for (size_t ti = 0; ti < sizeof turns / sizeof *turns; ti++)
                    for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
                        for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                            int p, b;
                            shared += wall_in_building(twin_walls[wi], twin_shells[si], twins[xi], 0, 0, turns[ti][0],
                                                       turns[ti][1], cell_counts[ci], offsets[oi], &p, &b);
                            pairs += p;
                            built &= b;
                        }
            char name[160];
            snprintf(name, sizeof name,
                     "cell planes: a wall %g cm thick modelled twice, overlapping, between rooms of slabs %g cm "
                     "thick keeps a plane",
                     1e2 * twin_walls[wi], 1e2 * twin_shells[si]);
            CHECK(name, built && shared == 0 && pairs > 0,
                  "%d of %d point pairs across the walls in one cell share a region", shared, pairs);
        }
    {
        /* The same with a doorway in the first copy, which the second
         * closes, and a cupboard beside it against the second. */
        const float twin_turns_door[][2] = {{0, 0}, {49.3f, 27.1f}, {20, 8}};
        int shared = 0, pairs = 0, built = 1;
        for (size_t xi = 0; xi < 2; xi++)
            for (size_t ti = 0; ti < sizeof twin_turns_door / sizeof *twin_turns_door; ti++)
                for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
                    for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                        int p, b;
                        shared += wall_in_building(0.2f, 0.05f, xi ? 0.03f : 0.01f, 0.6f, 0.3f, twin_turns_door[ti][0],
                                                   twin_turns_door[ti][1], cell_counts[ci], offsets[oi], &p, &b);
                        pairs += p;
                        built &= b;
                    }
        CHECK("cell planes: a wall modelled twice, a doorway in one copy and a cupboard beside it: the doorway's side "
              "and the cupboard's, facing each other but not over each other, are no gap that takes the wall's plane",
              built && shared == 0 && pairs > 0, "%d of %d point pairs across the walls in one cell share a region",
              shared, pairs);
    }
    const float corridors[] = {0.02f, 0.03f, 0.05f, 0.08f, 0.12f, 0.2f};
    for (size_t ai = 0; ai < 2 * sizeof corridors / sizeof *corridors; ai++) {
        const int away = ai % 2;
        const float apart = corridors[ai / 2];
        int shared = 0, pairs = 0, built = 1, grids = 0;
        for (size_t ti = 0; ti < sizeof turns / sizeof *turns; ti++)
            for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
                for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                    if (!away && apart <= 0.012 * 4.0 / cell_counts[ci]) continue; /* see LAYER_OVER_OFFSET */
                    int p, b;
                    shared +=
                        corridor_in_room(apart, away, turns[ti][0], turns[ti][1], cell_counts[ci], offsets[oi], &p, &b);
                    pairs += p;
                    built &= b;
                    grids++;
                }
        char name[160];
        snprintf(name, sizeof name,
                 "cell planes: a corridor %g cm wide between walls of one polygon %s keeps both walls, also where "
                 "they meet the floor and an outer wall",
                 1e2 * apart, away ? "back to back" : "facing one way");
        CHECK(name, built && shared == 0 && pairs > 0 && grids > 0,
              "%d of %d point pairs in one cell share a region (%d grids)", shared, pairs, grids);
    }
    {
        /* Coarse grids, where such a corridor is 2 to 6% of a cell: its
         * walls lie over each other, so they stay two layers. */
        const int coarse[] = {5, 6, 8};
        const float aparts[] = {0.02f, 0.03f};
        int shared = 0, pairs = 0, built = 1, grids = 0;
        for (size_t ai = 0; ai < sizeof aparts / sizeof *aparts; ai++)
            for (size_t ti = 0; ti < sizeof turns / sizeof *turns; ti += 3)
                for (size_t ci = 0; ci < sizeof coarse / sizeof *coarse; ci++)
                    for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                        int p, b;
                        shared += corridor_in_room(aparts[ai], 0, turns[ti][0], turns[ti][1], coarse[ci], offsets[oi],
                                                   &p, &b);
                        pairs += p;
                        built &= b;
                        grids++;
                    }
        CHECK("cell planes: a corridor 2 or 3 cm wide between walls of one polygon facing one way keeps both walls "
              "at 5 to 8 cells",
              built && shared == 0 && pairs > 0 && grids > 0,
              "%d of %d point pairs in one cell share a region (%d grids)", shared, pairs, grids);
    }
    for (int panel = 0; panel < 2; panel++) {
        const float aparts[] = {0.02f, 0.03f, 0.05f};
        int shared = 0, pairs = 0, built = 1, grids = 0;
        for (size_t ai = 0; ai < sizeof aparts / sizeof *aparts; ai++)
            for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
                for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                    double h = 2.0 / cell_counts[ci];
                    if (aparts[ai] <= 0.012 * h || aparts[ai] >= 0.25 * h)
                        continue; /* see LAYER_OVER_OFFSET; beyond a quarter cell no cluster joins them */
                    int p, b;
                    shared += layers_apart(panel, aparts[ai], cell_counts[ci], offsets[oi], &p, &b);
                    pairs += p;
                    built &= b;
                    grids++;
                }
        CHECK(panel ? "cell planes: a panel 2 to 5 cm deep against a wall stays a plane of its own"
                    : "cell planes: a corridor 2 to 5 cm wide between walls of one polygon keeps both walls",
              built && shared == 0 && pairs > 0 && grids > 0,
              "%d of %d point pairs in one cell share a region (%d grids)", shared, pairs, grids);
    }
    for (uint32_t k = 1; k <= 4; k++) {
        int faults = 0, cut = 0, ok = 1;
        for (int v = 0; v < 2 && ok; v++) {
            float tris[MAX_TRIS * 9];
            size_t n = make_stack(&stacks[v ? 4 : 2], v, 0, 0, tris);
            harness_regions r;
            int c = 0;
            ok = harness_build_regions("cell planes", tris, n, v ? 24 : 16, v ? 0.37 : 0.0, (int)k, &r);
            if (ok) faults += record_faults(&r, k, (size_t)r.g.dims[0] * r.g.dims[1] * r.g.dims[2], &c);
            cut += c;
            harness_free_regions(&r);
        }
        char name[160];
        snprintf(name, sizeof name,
                 "cell planes: %u^3 subcells: each region keeps records of the subcells it has volume in", k);
        CHECK(name, ok && faults == 0 && cut > 0, "%d faults over %d cut cells", faults, cut);
    }
    CHECK_EXIT();
}
