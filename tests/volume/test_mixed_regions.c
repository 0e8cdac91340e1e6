/* Regions that mix the two sides of a surface (host/render/volume_planes.c,
 * mixed_patterns), on the host alone. A cell's planes are flat; a curved
 * wall is not, and where it bends by more than it is thick across a cell,
 * the air on one side of it falls, in a thin band, into the region of the
 * other side. Even a band a tenth of a millimetre thick carries a lit
 * room's light into a dim one at 1000:1 (the particles' track lengths in
 * it, weighed by the bright light). Such regions must be flagged
 * LV_REGION_MIXED, so that no lookup reads them.
 *
 * Checked: points just in front of a surface (0.1 mm to 1 cm off it) and
 * points just behind it (on the far side of the wall) never share a region
 * that is not flagged, for closed shells (a sphere of 0.5 to 15 cm walls,
 * a cylinder) in a room and for a curved partition of one polygon between
 * two rooms (one row of quads, or five, so that most of its triangles have
 * no open edge of their own), 12 to 40 cells at grid offsets 0 and 0.37,
 * and for that partition with a cupboard standing against its apex (the
 * wedge of air between them), turned three ways, offsets 0 to 0.5.
 * And where the partition meets a ceiling with a lamp 1 mm under it, the
 * air of that layer on its two sides; and the partition's two sides with
 * such a lamp in front of it on grids of 3 to 6 cells. And a closed box
 * of one-polygon faces with a lamp inside: hollow, lit air behind its
 * faces, not a solid.
 * And the flags stay off where nothing mixes: flat walls between rooms (one
 * polygon, or a solid, turned), a rippled tile on a wall (its back a
 * pocket against the wall) and a hollow block standing on the floor (its
 * open bottom closed by the floor): no slot flagged. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/render/light_volume_internal.h"
#include "../check.h"
#include "../harness.h"

#define PI 3.14159265358979
#define MAX_TRIS 8192
/* The room the shapes stand in: x, z in [-2, 2] and [-1, 1], y in [0, 2.5]. */
static const float ROOM_LO[3] = {-2.0f, 0.0f, -1.0f}, ROOM_HI[3] = {2.0f, 2.5f, 1.0f};

/* Appends triangle a, b, c, wound to face along `facing`. */
static size_t add_triangle(float *t, size_t n, const double a[3], const double b[3], const double c[3],
                           const double facing[3])
{
    double e1[3], e2[3], nrm[3];
    for (int k = 0; k < 3; k++) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
    lvcl_cross3(e1, e2, nrm);
    int flip = lvcl_dot3(nrm, facing) < 0;
    const double *v[3] = {a, flip ? c : b, flip ? b : c};
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) t[9 * n + 3 * i + k] = (float)v[i][k];
    return n + 1;
}

/* A UV sphere of radius r round c, facing out (or in). */
static size_t add_sphere(float *t, size_t n, const double c[3], double r, int seg, int inward)
{
    for (int j = 0; j < seg / 2; j++)
        for (int i = 0; i < seg; i++) {
            double p[4][3];
            for (int q = 0; q < 4; q++) {
                double th = PI * (j + (q / 2)) / (seg / 2), ph = 2 * PI * (i + (q == 1 || q == 2)) / seg;
                p[q][0] = c[0] + r * sin(th) * cos(ph), p[q][1] = c[1] + r * cos(th),
                p[q][2] = c[2] + r * sin(th) * sin(ph);
            }
            double mid[3];
            for (int k = 0; k < 3; k++) mid[k] = ((p[0][k] + p[2][k]) / 2 - c[k]) * (inward ? -1 : 1);
            if (j > 0) n = add_triangle(t, n, p[0], p[1], p[2], mid);
            if (j < seg / 2 - 1) n = add_triangle(t, n, p[0], p[2], p[3], mid);
        }
    return n;
}

/* A closed cylinder (axis along y) of radius r and height 2 half round c. */
static size_t add_cylinder(float *t, size_t n, const double c[3], double r, double half, int seg, int inward)
{
    double s = inward ? -1 : 1;
    for (int i = 0; i < seg; i++) {
        double a0 = 2 * PI * i / seg, a1 = 2 * PI * (i + 1) / seg, am = (a0 + a1) / 2;
        double p0[3] = {c[0] + r * cos(a0), c[1] - half, c[2] + r * sin(a0)};
        double p1[3] = {c[0] + r * cos(a1), c[1] - half, c[2] + r * sin(a1)};
        double q0[3] = {p0[0], c[1] + half, p0[2]}, q1[3] = {p1[0], c[1] + half, p1[2]};
        double out[3] = {s * cos(am), 0, s * sin(am)}, up[3] = {0, s, 0}, down[3] = {0, -s, 0};
        double bottom[3] = {c[0], c[1] - half, c[2]}, top[3] = {c[0], c[1] + half, c[2]};
        n = add_triangle(t, n, p0, p1, q1, out);
        n = add_triangle(t, n, p0, q1, q0, out);
        n = add_triangle(t, n, bottom, p0, p1, down);
        n = add_triangle(t, n, top, q0, q1, up);
    }
    return n;
}

/* The curved partition of one polygon: x = x0 + bend cos(pi z / 2) over
 * the room's depth and height, `seg` columns and `rows` rows of quads
 * facing +x. */
static double partition_x(double z, double bend)
{
    return 0.37 + bend * cos(PI * z / 2);
}

static size_t add_partition(float *t, size_t n, double bend, int seg, int rows)
{
    for (int i = 0; i < seg; i++)
        for (int j = 0; j < rows; j++) {
            double z0 = -1 + 2.0 * i / seg, z1 = -1 + 2.0 * (i + 1) / seg, y0 = 2.5 * j / rows,
                   y1 = 2.5 * (j + 1) / rows;
            double a[3] = {partition_x(z0, bend), y0, z0}, b[3] = {partition_x(z1, bend), y0, z1},
                   c[3] = {partition_x(z1, bend), y1, z1}, d[3] = {partition_x(z0, bend), y1, z0}, f[3] = {1, 0, 0};
            n = add_triangle(t, n, a, b, c, f);
            n = add_triangle(t, n, a, c, d, f);
        }
    return n;
}

static size_t mixed_slots(const harness_regions *r)
{
    size_t mixed = 0;
    for (uint32_t s = 0; s < r->g.slot_count; s++) mixed += (r->regions.slots[s].flags & LV_REGION_MIXED) != 0;
    return mixed;
}

/* Which side each slot has seen points of (bit 0: front, bit 1: back). */
typedef struct {
    uint8_t *seen;
    int shared, flagged; /* slots holding both sides: not flagged, flagged */
} sides;

static void see(const harness_regions *r, sides *s, const double p[3], int side)
{
    float q[3] = {(float)p[0], (float)p[1], (float)p[2]};
    uint32_t slot = lvcl_volume_grid_slot_at(&r->g, r->slot, &r->regions, q, NULL);
    if (slot == LV_EMPTY_CELL) return;
    uint8_t before = s->seen[slot];
    s->seen[slot] |= (uint8_t)(1 << side);
    if (before != 3 && s->seen[slot] == 3) {
        if (r->regions.slots[slot].flags & LV_REGION_MIXED) s->flagged++;
        else s->shared++;
    }
}

/* Points off triangles [first, end) of tris: at 0.1 mm, 1 mm and 1 cm
 * along their fronts (side 0) or backs (side 1), a few per triangle. */
static void see_off(const harness_regions *r, sides *s, const float *tris, size_t first, size_t end, int back, int side)
{
    static const double offs[] = {1e-4, 1e-3, 1e-2},
                        bary[][2] = {{1 / 3.0, 1 / 3.0}, {0.1, 0.1}, {0.8, 0.1}, {0.1, 0.8}};
    for (size_t i = first; i < end; i++) {
        const float *v = tris + 9 * i;
        double e1[3], e2[3], nrm[3];
        for (int k = 0; k < 3; k++) e1[k] = v[3 + k] - v[k], e2[k] = v[6 + k] - v[k];
        lvcl_cross3(e1, e2, nrm);
        double len = sqrt(lvcl_dot3(nrm, nrm));
        if (!(len > 0)) continue;
        for (size_t b = 0; b < sizeof bary / sizeof *bary; b++)
            for (size_t o = 0; o < sizeof offs / sizeof *offs; o++) {
                double p[3];
                for (int k = 0; k < 3; k++)
                    p[k] = v[k] + bary[b][0] * e1[k] + bary[b][1] * e2[k] + (back ? -1 : 1) * offs[o] * nrm[k] / len;
                see(r, s, p, side);
            }
    }
}

/* The room with a lamp (first) and its walls; returns the count. */
static size_t room(float *t)
{
    const double a[3] = {-0.3, 2.499, -0.3}, b[3] = {0.3, 2.499, -0.3}, c[3] = {0.3, 2.499, 0.3}, down[3] = {0, -1, 0};
    size_t n = add_triangle(t, 0, a, b, c, down);
    return harness_add_room(t, n, ROOM_LO, ROOM_HI);
}

/* Makes the regions of the n triangles t and counts the slots that hold
 * points off triangles [a0, a1) (side 0) and off [b0, b1) (side 1), off
 * their fronts, or their backs where *_back: *shared those not flagged,
 * *flagged the rest. Frees t. Returns 0 where making the regions failed. */
static int count_sides(float *t, size_t n, int cells, double offset, size_t a0, size_t a1, int a_back, size_t b0,
                       size_t b1, int b_back, int *shared, int *flagged)
{
    harness_regions reg;
    int ok = harness_build_regions("mixed regions", t, n, cells, offset, 0, &reg);
    if (ok) {
        sides s = {calloc(reg.g.slot_count + 1, 1), 0, 0};
        see_off(&reg, &s, t, a0, a1, a_back, 0);
        see_off(&reg, &s, t, b0, b1, b_back, 1);
        *shared = s.shared, *flagged = s.flagged;
        free(s.seen);
        harness_free_regions(&reg);
    }
    free(t);
    return ok;
}

/* A closed shell (shape 0: sphere, 1: cylinder) of wall `thick` in the room:
 * the air outside it against the air inside. */
static int shell_sides(int shape, double thick, int cells, double offset, int *shared, int *flagged)
{
    float *t = malloc(MAX_TRIS * 9 * sizeof *t);
    const double c[3] = {0.05, 1.1, -0.1}, r = 0.6;
    size_t n = room(t), outer = n;
    n = shape ? add_cylinder(t, n, c, r, r, 20, 0) : add_sphere(t, n, c, r, 20, 0);
    size_t inner = n;
    n = shape ? add_cylinder(t, n, c, r - thick, r - thick, 20, 1) : add_sphere(t, n, c, r - thick, 20, 1);
    return count_sides(t, n, cells, offset, outer, inner, 0, inner, n, 0, shared, flagged);
}

/* The partition of one polygon between two rooms: its front's air against its back's. */
static int partition_sides(double bend, int rows, int cells, double offset, int *shared, int *flagged)
{
    float *t = malloc(MAX_TRIS * 9 * sizeof *t);
    size_t n = room(t), first = n;
    n = add_partition(t, n, bend, 16, rows);
    return count_sides(t, n, cells, offset, first, n, 0, first, n, 1, shared, flagged);
}

/* The partition (bend m, rows of quads) with a cupboard 30 cm deep, 90 cm
 * high and 1 m wide standing against its apex in front, the whole turned:
 * the thin wedge of air between the cupboard's back and the curved
 * partition against the air behind the partition; *shared and *flagged
 * as count_sides's, over both checks (the cupboard's fronts, and the
 * partition's, against the partition's backs). */
static int cupboard_sides(double bend, int rows, int cells, double offset, float yaw, float pitch, int *shared,
                          int *flagged)
{
    int ok = 1;
    *shared = *flagged = 0;
    for (int check = 0; check < 2; check++) {
        float *t = malloc(MAX_TRIS * 9 * sizeof *t);
        size_t n = room(t), first = n;
        n = add_partition(t, n, bend, 16, rows);
        size_t box = n;
        const float lo[3] = {(float)partition_x(0, bend), 0.0f, -0.5f},
                    hi[3] = {(float)partition_x(0, bend) + 0.3f, 0.9f, 0.5f};
        n = harness_add_box(t, n, lo, hi);
        for (size_t v = 0; v < 3 * n; v++) harness_turn(&t[3 * v], yaw, pitch);
        int s = 0, f = 0;
        ok &= check ? count_sides(t, n, cells, offset, first, box, 0, first, box, 1, &s, &f)
                    : count_sides(t, n, cells, offset, box, n, 0, first, box, 1, &s, &f);
        *shared += s, *flagged += f;
    }
    return ok;
}

/* The partition with a lamp 1 mm under the ceiling on its front side,
 * 60 cm wide from its apex, so that the lamp's plane cuts the partition's
 * cells at the top: the air of that 1 mm layer just in front of the
 * partition (0.1 mm off its facets) against the layer's air just behind.
 * Found by bench/leak_sweep.py --seed 93 (a point view where such a
 * partition meets the ceiling, red / blue 0.6-5% at 1000:1 in lv, none in
 * pt): the facets' grid of samples stepped over the layer, which then held
 * both rooms' light unflagged. */
static int layer_sides(double bend, int rows, int cells, double offset, int *shared, int *flagged)
{
    float *t = malloc(MAX_TRIS * 9 * sizeof *t);
    size_t n = room(t);
    n = add_partition(t, n, bend, 16, rows);
    const float lamp[3] = {(float)partition_x(0, bend), 2.499f, -0.3f}, across[3] = {0.6f, 0, 0},
                deep[3] = {0, 0, 0.6f};
    n = harness_add_quad(t, n, lamp, across, deep);
    harness_regions reg;
    int ok = harness_build_regions("mixed regions", t, n, cells, offset, 0, &reg);
    if (ok) {
        sides s = {calloc(reg.g.slot_count + 1, 1), 0, 0};
        /* Along the partition, mid-layer, 64 points a column of quads;
         * its facets are the curve's chords over their columns. */
        for (int k = 0; k < 16 * 64; k++) {
            double z = -1 + 2.0 * (k + 0.5) / (16 * 64), z0 = -1 + floor((z + 1) * 8) / 8, z1 = z0 + 0.125;
            double x = partition_x(z0, bend) + (z - z0) / (z1 - z0) * (partition_x(z1, bend) - partition_x(z0, bend));
            for (int side = 0; side < 2; side++) {
                double q[3] = {x + (side ? -1e-4 : 1e-4), 2.4995, z};
                see(&reg, &s, q, side);
            }
        }
        *shared = s.shared, *flagged = s.flagged;
        free(s.seen);
        harness_free_regions(&reg);
    }
    free(t);
    return ok;
}

/* The partition with a lamp 1 mm under the ceiling in front of it, 15 to
 * 75 cm beyond its apex, on coarse grids whose cells hold the lamp and a
 * bowed stretch of the partition in one region: the partition's front
 * air against its back's. The lamp's back is a pocket against the
 * ceiling; its samples spent the rays that tell whether a back is dark
 * for the whole region, and the partition's band was left unflagged
 * (bench/leak_sweep.py --cells 4 --seed 124: red / blue 10.9 in lv, none
 * in pt). */
static int lamp_partition_sides(double bend, int rows, int cells, double offset, int *shared, int *flagged)
{
    float *t = malloc(MAX_TRIS * 9 * sizeof *t);
    size_t n = room(t), first = n;
    n = add_partition(t, n, bend, 16, rows);
    size_t end = n;
    const float lamp[3] = {(float)partition_x(0, bend) + 0.15f, 2.499f, -0.3f}, across[3] = {0.6f, 0, 0},
                deep[3] = {0, 0, 0.6f};
    n = harness_add_quad(t, n, lamp, across, deep);
    return count_sides(t, n, cells, offset, first, end, 0, first, end, 1, shared, flagged);
}

/* A closed box of one-polygon faces (facing out) w x h x d, its foot at
 * `lift` over the floor, turned by `yaw` degrees about its middle, with
 * a lamp (the scene's first triangle) 2 mm under its lid inside, in the
 * room: the air outside its faces against the air inside. Appends the
 * box's faces to t from *first (returned) on; returns the count. */
static size_t lit_box(float *t, double w, double h, double d, double lift, double yaw, size_t *first)
{
    const double c[3] = {-0.6, lift, 0.1}, a = yaw * PI / 180, ca = cos(a), sa = sin(a);
    double lamp[3][3] = {
        {-0.3 * w, h - 0.002, -0.3 * d}, {0.3 * w, h - 0.002, -0.3 * d}, {0.3 * w, h - 0.002, 0.3 * d}};
    double corner[8][3];
    for (int i = 0; i < 8; i++) {
        double x = (i & 1 ? 0.5 : -0.5) * w, z = (i & 4 ? 0.5 : -0.5) * d;
        corner[i][0] = c[0] + ca * x - sa * z, corner[i][1] = c[1] + (i & 2 ? h : 0),
        corner[i][2] = c[2] + sa * x + ca * z;
    }
    for (int i = 0; i < 3; i++) {
        double x = lamp[i][0], z = lamp[i][2];
        lamp[i][0] = c[0] + ca * x - sa * z, lamp[i][1] += c[1], lamp[i][2] = c[2] + sa * x + ca * z;
    }
    const double down[3] = {0, -1, 0};
    size_t n = add_triangle(t, 0, lamp[0], lamp[1], lamp[2], down);
    n = harness_add_room(t, n, ROOM_LO, ROOM_HI);
    *first = n;
    /* Each face: its four corners (bits of the index: x, y, z) and which way it faces. */
    static const int faces[6][4] = {{0, 2, 6, 4}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 1, 3, 2}, {4, 5, 7, 6}};
    for (int f = 0; f < 6; f++) {
        double mid[3] = {0, 0, 0}, out[3];
        for (int k = 0; k < 4; k++)
            for (int j = 0; j < 3; j++) mid[j] += corner[faces[f][k]][j] / 4;
        for (int j = 0; j < 3; j++) out[j] = mid[j] - (c[j] + (j == 1 ? h / 2 : 0));
        n = add_triangle(t, n, corner[faces[f][0]], corner[faces[f][1]], corner[faces[f][2]], out);
        n = add_triangle(t, n, corner[faces[f][0]], corner[faces[f][2]], corner[faces[f][3]], out);
    }
    return n;
}

/* lit_box's outside against its inside. */
static int lit_box_sides(double w, double h, double d, double lift, double yaw, int cells, double offset, int *shared,
                         int *flagged)
{
    float *t = malloc(MAX_TRIS * 9 * sizeof *t);
    size_t first, n = lit_box(t, w, h, d, lift, yaw, &first);
    return count_sides(t, n, cells, offset, first, n, 0, first, n, 1, shared, flagged);
}

/* Slots flagged in a scene where nothing mixes: kind 0, a flat wall of one
 * polygon between two rooms, turned; 1, a 2 cm solid wall, turned; 2, a
 * rippled tile (a height field with open edges) on the room's wall; 3, a
 * hollow block (five sides, open at the bottom) on the floor. -1 where
 * making the regions failed. */
static long flags_where_nothing_mixes(int kind, int cells, double offset)
{
    float *t = malloc(MAX_TRIS * 9 * sizeof *t);
    size_t n = room(t);
    if (kind == 0 || kind == 1) {
        if (kind == 0) {
            const float a[3] = {0.37f, 0, -1}, up[3] = {0, 2.5f, 0}, across[3] = {0, 0, 2};
            n = harness_add_quad(t, n, a, up, across);
        } else {
            const float lo[3] = {0.36f, 0, -1}, hi[3] = {0.38f, 2.5f, 1};
            n = harness_add_box(t, n, lo, hi);
        }
        for (size_t v = 0; v < 3 * n; v++) harness_turn(t + 3 * v, 17, 9); /* the whole scene */
    } else if (kind == 2) {
        /* 24 cm square, 6 mm proud at its middle, 12 x 12 quads, against x = -2. */
        for (int i = 0; i < 12; i++)
            for (int j = 0; j < 12; j++) {
                double p[4][3];
                for (int q = 0; q < 4; q++) {
                    double u = (i + (q == 1 || q == 2)) / 12.0, w = (j + (q / 2)) / 12.0;
                    p[q][0] = -2 + 0.006 * sin(PI * u) * sin(PI * w) * (1 + 0.2 * sin(7 * PI * u));
                    p[q][1] = 1.0 + 0.24 * u, p[q][2] = -0.3 + 0.24 * w;
                }
                const double f[3] = {1, 0, 0};
                n = add_triangle(t, n, p[0], p[1], p[2], f);
                n = add_triangle(t, n, p[0], p[2], p[3], f);
            }
    } else {
        const float lo[3] = {-1.2f, 0, -0.3f}, hi[3] = {-0.4f, 0.3f, 0.3f};
        size_t first = n;
        n = harness_add_box(t, n, lo, hi);
        /* Drop the bottom's two triangles (those with every corner at y = 0). */
        size_t kept = first;
        for (size_t i = first; i < n; i++)
            if (!(t[9 * i + 1] == 0 && t[9 * i + 4] == 0 && t[9 * i + 7] == 0))
                memmove(t + 9 * kept++, t + 9 * i, 9 * sizeof *t);
        n = kept;
    }
    harness_regions reg;
    long mixed = harness_build_regions("mixed regions", t, n, cells, offset, 0, &reg) ? (long)mixed_slots(&reg) : -1;
    if (mixed >= 0) harness_free_regions(&reg);
    free(t);
    return mixed;
}

static const int cell_counts[] = {12, 23, 40};
static const double offsets[] = {0.0, 0.37};

/* Runs a bowed partition's check (partition_sides, layer_sides) at every
 * cell count and offset above; sums *shared and *flagged; returns 0 where
 * making the regions failed. */
static int over_grids(int (*check)(double bend, int rows, int cells, double offset, int *shared, int *flagged),
                      double bend, int rows, int *shared, int *flagged)
{
    int built = 1;
    *shared = *flagged = 0;
    for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
        for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
            int s = 0, f = 0;
            built &= check(bend, rows, cell_counts[ci], offsets[oi], &s, &f);
            *shared += s, *flagged += f;
        }
    return built;
}

int main(void)
{
    const double thicknesses[] = {0.005, 0.03, 0.15};
    for (int shape = 0; shape < 2; shape++)
        for (size_t ti = 0; ti < sizeof thicknesses / sizeof *thicknesses; ti++) {
            int shared = 0, flagged = 0, built = 1;
            for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
                for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                    int s = 0, f = 0;
                    built &= shell_sides(shape, thicknesses[ti], cell_counts[ci], offsets[oi], &s, &f);
                    shared += s, flagged += f;
                }
            char name[160];
            snprintf(name, sizeof name,
                     "mixed regions: a closed %s shell %g cm thick: no region that is read holds air from both sides",
                     shape ? "cylinder" : "sphere", 1e2 * thicknesses[ti]);
            CHECK(name, built && shared == 0, "%d slots hold both sides unflagged (%d flagged)", shared, flagged);
        }
    const double bends[] = {0.3, 0.5};
    for (size_t bi = 0; bi < sizeof bends / sizeof *bends; bi++)
        for (int rows = 1; rows <= 5; rows += 4) {
            int shared, flagged, built = over_grids(partition_sides, bends[bi], rows, &shared, &flagged);
            char name[200];
            snprintf(name, sizeof name,
                     "mixed regions: a curved partition of one polygon (bend %g m, %d row%s of quads): no region that "
                     "is read holds air from both sides",
                     bends[bi], rows, rows > 1 ? "s" : "");
            CHECK(name, built && shared == 0 && flagged > 0, "%d slots hold both sides unflagged (%d flagged)", shared,
                  flagged);
        }
    /* A cupboard against the partition's apex (found by bench/leak_sweep.py
     * --curved --seed 111: red / blue 0.09 at 1000:1 in lv, none in pt):
     * facets sampled 5 x 5 left the air behind the partition, below the
     * cupboard's top, unsampled in a region it shared with the wedge. */
    const float turns[][2] = {{0, 11}, {0, 28.8f}, {23, 7}};
    for (size_t bi = 0; bi < sizeof bends / sizeof *bends; bi++)
        for (int rows = 1; rows <= 5; rows += 4) {
            int shared = 0, flagged = 0, built = 1;
            const int cupboard_cells[] = {12, 24, 40};
            const double cupboard_offsets[] = {0.0, 0.37, 0.5};
            for (size_t ci = 0; ci < sizeof cupboard_cells / sizeof *cupboard_cells; ci++)
                for (size_t oi = 0; oi < sizeof cupboard_offsets / sizeof *cupboard_offsets; oi++)
                    for (size_t ti = 0; ti < sizeof turns / sizeof *turns; ti++) {
                        int s = 0, f = 0;
                        built &= cupboard_sides(bends[bi], rows, cupboard_cells[ci], cupboard_offsets[oi], turns[ti][0],
                                                turns[ti][1], &s, &f);
                        shared += s, flagged += f;
                    }
            char name[200];
            snprintf(name, sizeof name,
                     "mixed regions: a cupboard against a curved partition (bend %g m, %d row%s), turned: no region "
                     "that is read holds the wedge's air and the air behind",
                     bends[bi], rows, rows > 1 ? "s" : "");
            CHECK(name, built && shared == 0, "%d slots hold both sides unflagged (%d flagged)", shared, flagged);
        }
    for (size_t bi = 0; bi < sizeof bends / sizeof *bends; bi++)
        for (int rows = 1; rows <= 5; rows += 4) {
            int shared, flagged, built = over_grids(layer_sides, bends[bi], rows, &shared, &flagged);
            char name[200];
            snprintf(name, sizeof name,
                     "mixed regions: a curved partition (bend %g m, %d row%s) under a ceiling with a lamp 1 mm below "
                     "it: no region that is read holds the 1 mm layer's air from both sides",
                     bends[bi], rows, rows > 1 ? "s" : "");
            CHECK(name, built && shared == 0, "%d slots hold both sides unflagged (%d flagged)", shared, flagged);
        }
    for (size_t bi = 0; bi < sizeof bends / sizeof *bends; bi++) {
        int shared = 0, flagged = 0, built = 1;
        const int coarse[] = {3, 4, 5, 6};
        for (size_t ci = 0; ci < sizeof coarse / sizeof *coarse; ci++)
            for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                int s = 0, f = 0;
                built &= lamp_partition_sides(bends[bi], 1, coarse[ci], offsets[oi], &s, &f);
                shared += s, flagged += f;
            }
        char name[200];
        snprintf(name, sizeof name,
                 "mixed regions: a curved partition (bend %g m) and a lamp under the ceiling in front of it, 3 to 6 "
                 "cells: no region that is read holds air from both sides",
                 bends[bi]);
        CHECK(name, built && shared == 0 && flagged > 0, "%d slots hold both sides unflagged (%d flagged)", shared,
              flagged);
    }
    {
        /* A closed box of one-polygon faces with a lamp inside, 3 cm off
         * the floor or on it, square to the grid or turned: in the build
         * before, its faces were a solid's, the inside taken for dark, and
         * a face without a plane shared the room's region (the room lit by
         * the box's lamp: red / blue 0.47 at 32 cells). */
        static const double boxes[][3] = {{0.33, 0.8, 0.8}, {1.0, 1.07, 0.53}, {0.2, 0.3, 0.25}};
        const double lifts[] = {0.0, 0.03}, yaws[] = {0.0, 12.4, 35.6};
        const int box_cells[] = {12, 23, 32, 40};
        int shared = 0, flagged = 0, built = 1;
        for (size_t bi = 0; bi < sizeof boxes / sizeof *boxes; bi++)
            for (size_t li = 0; li < sizeof lifts / sizeof *lifts; li++)
                for (size_t yi = 0; yi < sizeof yaws / sizeof *yaws; yi++)
                    for (size_t ci = 0; ci < sizeof box_cells / sizeof *box_cells; ci++)
                        for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                            int sh = 0, f = 0;
                            built &= lit_box_sides(boxes[bi][0], boxes[bi][1], boxes[bi][2], lifts[li], yaws[yi],
                                                   box_cells[ci], offsets[oi], &sh, &f);
                            shared += sh, flagged += f;
                        }
        CHECK("mixed regions: a closed box of one-polygon faces with a lamp inside (3 sizes, on the floor or 3 cm "
              "over it, turned 0 to 36 degrees, 12 to 40 cells): no region that is read holds air from both sides",
              built && shared == 0 && flagged > 0, "%d slots hold both sides unflagged (%d flagged)", shared, flagged);
    }
    static const char *const calm[] = {
        "a flat wall of one polygon between two rooms, turned", "a flat 2 cm wall between two rooms, turned",
        "a rippled tile against a wall (its back a pocket)", "a hollow block open at the bottom, on the floor"};
    for (int kind = 0; kind < 4; kind++) {
        long worst = 0;
        for (size_t ci = 0; ci < sizeof cell_counts / sizeof *cell_counts; ci++)
            for (size_t oi = 0; oi < sizeof offsets / sizeof *offsets; oi++) {
                long m = flags_where_nothing_mixes(kind, cell_counts[ci], offsets[oi]);
                worst = m < 0 || worst < 0 ? -1 : (m > worst ? m : worst);
            }
        char name[160];
        snprintf(name, sizeof name, "mixed regions: none flagged for %s", calm[kind]);
        CHECK(name, worst == 0, "up to %ld slots flagged (-1: making the regions failed)", worst);
    }
    CHECK_EXIT();
}
