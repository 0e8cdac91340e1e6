/* The exact shares of the regions of cut cells (host/render/volume_shares.c):
 * closed forms for one plane (an axis-aligned wall, a corner cut by a
 * slanted one), and for three slanted planes a fine lattice of points;
 * the regions' shares of every subcell add up to 1; a region's volume
 * less its parts inside solids (lvcl_region_open_volume) by closed
 * forms and a lattice. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../../host/render/light_volume_internal.h"
#include "../check.h"
#include "../harness.h"

#define PER(k) (1u + ((k) ? (k) * (k) * (k) : 1u))

/* A solid's slab between n . u = lo and hi, over [a_lo, a_hi] along a1 and
 * [b_lo, b_hi] along a2 (n, a1, a2 orthonormal). */
static lvcl_solid_slab slab(const float n[3], float lo, float hi, const float a1[3], float a_lo, float a_hi,
                            const float a2[3], float b_lo, float b_hi)
{
    lvcl_solid_slab t = {.lo = {lo, a_lo, b_lo}, .hi = {hi, a_hi, b_hi}};
    for (int j = 0; j < 3; j++) t.axis[0][j] = n[j], t.axis[1][j] = a1[j], t.axis[2][j] = a2[j];
    return t;
}

/* Region `pattern`'s volume outside the solids by a 120^3 lattice. */
static double lattice_open(const float planes[][4], int count, unsigned pattern, const lvcl_cell_solids *c)
{
    const unsigned m = 120;
    double open = 0;
    for (unsigned z = 0; z < m; z++)
        for (unsigned y = 0; y < m; y++)
            for (unsigned x = 0; x < m; x++) {
                double u[3] = {(x + 0.5) / m, (y + 0.5) / m, (z + 0.5) / m};
                unsigned p = 0;
                for (int j = 0; j < count; j++)
                    if (planes[j][0] * u[0] + planes[j][1] * u[1] + planes[j][2] * u[2] > planes[j][3]) p |= 1u << j;
                int inside = 0;
                for (int i = 0; i < c->count && !inside; i++) {
                    inside = 1;
                    for (int a = 0; a < 3; a++) {
                        const float *ax = c->solid[i].axis[a];
                        double d = ax[0] * u[0] + ax[1] * u[1] + ax[2] * u[2];
                        inside &= d >= c->solid[i].lo[a] && d <= c->solid[i].hi[a];
                    }
                }
                open += p == pattern && !inside;
            }
    return open / ((double)m * m * m);
}

/* Thin solids leave their inside out of the regions' volumes. */
static void test_open_volume(void)
{
    const float x[3] = {1, 0, 0}, y[3] = {0, 1, 0}, z[3] = {0, 0, 1};
    /* A wall 0.1 thick through the middle, its plane at x = 0.5: each side
     * loses 0.05; over half the cell's height, 0.025; with the slab off
     * centre (0.46 to 0.56), the sides lose 0.04 and 0.06. */
    float mid[1][4] = {{1, 0, 0, 0.5f}};
    lvcl_cell_solids whole = {1, {slab(x, 0.45f, 0.55f, y, 0, 1, z, 0, 1)}};
    lvcl_cell_solids half = {1, {slab(x, 0.45f, 0.55f, y, 0, 0.5f, z, 0, 1)}};
    lvcl_cell_solids off = {1, {slab(x, 0.46f, 0.56f, y, 0, 1, z, 0, 1)}};
    double v[6] = {lvcl_region_open_volume((const float(*)[4])mid, 1, 0, &whole),
                   lvcl_region_open_volume((const float(*)[4])mid, 1, 1, &whole),
                   lvcl_region_open_volume((const float(*)[4])mid, 1, 0, &half),
                   lvcl_region_open_volume((const float(*)[4])mid, 1, 1, &half),
                   lvcl_region_open_volume((const float(*)[4])mid, 1, 0, &off),
                   lvcl_region_open_volume((const float(*)[4])mid, 1, 1, &off)};
    const double want[6] = {0.45, 0.45, 0.475, 0.475, 0.46, 0.44};
    double worst = 0;
    for (int i = 0; i < 6; i++) worst = fmax(worst, fabs(v[i] - want[i]));
    CHECK("open volume: a wall through the middle, whole, over half the cell, off centre", worst < 1e-6,
          "off by %.2e (%g %g, %g %g, %g %g)", worst, v[0], v[1], v[2], v[3], v[4], v[5]);
    /* No solid, or one outside the region: its whole volume. */
    lvcl_cell_solids none = {0}, beyond = {1, {slab(x, 0.7f, 0.8f, y, 0, 1, z, 0, 1)}};
    double free_side = lvcl_region_open_volume((const float(*)[4])mid, 1, 0, &none),
           far_side = lvcl_region_open_volume((const float(*)[4])mid, 1, 0, &beyond);
    CHECK("open volume: no solid in the region, its whole volume",
          fabs(free_side - 0.5) < 1e-6 && fabs(far_side - 0.5) < 1e-6, "%g and %g, not 0.5", free_side, far_side);
    /* Most of the region inside (a slab whose plane is one face's): what
     * is left of it, but never under a twentieth of the region. */
    lvcl_cell_solids most = {1, {slab(x, 0.1f, 0.8f, y, 0, 1, z, 0, 1)}};
    lvcl_cell_solids thick = {1, {slab(x, 0.1f, 0.99f, y, 0, 1, z, 0, 1)}};
    double left = lvcl_region_open_volume((const float(*)[4])mid, 1, 1, &most),
           floor_v = lvcl_region_open_volume((const float(*)[4])mid, 1, 1, &thick);
    CHECK("open volume: a region mostly inside a solid keeps what is outside it, at least a twentieth",
          fabs(left - 0.2) < 1e-6 && fabs(floor_v - 0.025) < 1e-6, "%g and %g, not 0.2 and 0.025", left, floor_v);
    /* A slanted wall with a plane through it, a slab of part of its
     * extent, and a second wall across it (their overlap taken once),
     * against a lattice. */
    const float r = (float)(1 / sqrt(2.0)), n[3] = {r, r, 0}, t[3] = {-r, r, 0};
    float two[2][4] = {{r, r, 0, 0.7f}, {0, 0, 1, 0.6f}};
    lvcl_cell_solids crossing = {
        2, {slab(n, 0.65f, 0.75f, t, -0.5f, 0.3f, z, 0.1f, 0.9f), slab(z, 0.57f, 0.63f, x, 0, 1, y, 0.2f, 1)}};
    double lattice_worst = 0;
    for (unsigned p = 0; p < 4; p++) {
        double exact = lvcl_region_open_volume((const float(*)[4])two, 2, p, &crossing);
        lattice_worst = fmax(lattice_worst, fabs(exact - lattice_open((const float(*)[4])two, 2, p, &crossing)));
    }
    printf("(open volume: worst %.2e against the lattice)\n", lattice_worst);
    CHECK("open volume: two slabs and two planes match a 120^3 lattice", lattice_worst < 2e-3, "off by %.2e",
          lattice_worst);
}

/* The regions' volumes in the cells a wall thinner than a quarter cell
 * cuts (tests/harness.c's two rooms, the wall across x): its one plane, in
 * the wall's middle, gives half its inside to each side's region, and each
 * region's volume must be the air it holds, the cell's part beyond the
 * wall's face (in closed form: the wall faces no axis but x), without
 * subcells (where it is the lit volume) and with them (where it caps the
 * lit volume's floor of one subcell; until 2026-12-07 it kept the wall's
 * half there: a corner's sliver of air read 10% dark). Cells away from the
 * rooms' other surfaces, whose one plane is the wall's. */
static void test_region_air(void)
{
    const float walls[] = {0.02f, 0.05f};
    const int cells[] = {12, 20};
    const double offsets[] = {0.3, 0.5, 0.77};
    const int subcells[] = {0, 2, 4};
    for (size_t wi = 0; wi < 2; wi++)
        for (size_t si = 0; si < 3; si++) {
            double worst = 0;
            int checked = 0, built = 1;
            for (size_t ci = 0; ci < 2; ci++)
                for (size_t oi = 0; oi < 3; oi++) {
                    float tris[HARNESS_TWO_ROOMS_TRIANGLES * 9];
                    size_t walls_end, n = harness_two_rooms(tris, walls[wi], 0, 0, 0, 0, 0, &walls_end);
                    harness_regions r;
                    if (!harness_build_regions("region air", tris, n, cells[ci], offsets[oi], subcells[si], &r)) {
                        built = 0;
                        continue;
                    }
                    const double h = r.g.cell_size, lo_face = HARNESS_WALL_X - walls[wi] / 2,
                                 hi_face = HARNESS_WALL_X + walls[wi] / 2;
                    for (uint32_t z = 0; z < r.g.dims[2]; z++)
                        for (uint32_t y = 0; y < r.g.dims[1]; y++)
                            for (uint32_t x = 0; x < r.g.dims[0]; x++) {
                                const double c0[3] = {r.g.origin[0] + h * x, r.g.origin[1] + h * y,
                                                      r.g.origin[2] + h * z};
                                /* The wall's middle in the cell, the cell clear of the rooms' other surfaces. */
                                if (!(c0[0] < HARNESS_WALL_X && c0[0] + h > HARNESS_WALL_X) || c0[1] < h ||
                                    c0[1] + 2 * h > HARNESS_ROOMS_Y || c0[2] < -HARNESS_ROOMS_Z + h ||
                                    c0[2] + 2 * h > HARNESS_ROOMS_Z)
                                    continue;
                                size_t cell = x + (size_t)r.g.dims[0] * (y + (size_t)r.g.dims[1] * z);
                                uint32_t first = r.slot[cell] & ~LV_CUT_CELL;
                                if (r.slot[cell] == LV_EMPTY_CELL || !(r.slot[cell] & LV_CUT_CELL)) continue;
                                const lv_slot_region *e = &r.regions.slots[first];
                                const lv_cell_cut *planes = &r.regions.cuts[e->cut];
                                if (planes->plane_count != 1 || e->shares == LV_NO_SHARES) continue;
                                for (uint32_t j = 0; j < 2; j++) {
                                    const lv_slot_region *q = &r.regions.slots[first + j];
                                    int beyond = (q->region & 1u) == (planes->planes[0][0] > 0 ? 1u : 0u);
                                    double air = beyond ? (c0[0] + h - hi_face) / h : (lo_face - c0[0]) / h;
                                    worst = fmax(worst, fabs(r.regions.shares[q->shares] - fmax(air, 0.0)));
                                    checked++;
                                }
                            }
                    harness_free_regions(&r);
                }
            char name[160];
            snprintf(name, sizeof name, "region air: a %g cm wall, %d subcells: each side's volume is its air",
                     1e2 * walls[wi], subcells[si]);
            CHECK(name, built && checked > 0 && worst < 1e-4, "worst %.2e over %d regions", worst, checked);
        }
}

int main(void)
{
    /* A wall at x = 0.37 cells, 4^3 subcells: the subcells of x index 1
     * (0.25 to 0.5) hold 0.12 / 0.25 of the negative region. */
    float wall[1][4] = {{1, 0, 0, 0.37f}};
    float s[8 * PER(4)];
    lvcl_region_shares((const float(*)[4])wall, 1, 4, s);
    CHECK("region shares: axis-aligned wall, the regions' volumes",
          fabs(s[0] - 0.37) < 1e-5 && fabs(s[PER(4)] - 0.63) < 1e-5, "%g and %g, not 0.37 and 0.63", s[0], s[PER(4)]);
    int sub_ok = 1;
    for (unsigned i = 0; i < 64; i++) {
        double want = i % 4 == 0 ? 1.0 : i % 4 == 1 ? 0.48 : 0.0;
        sub_ok &= fabs(s[1 + i] - want) < 1e-5 && fabs(s[PER(4) + 1 + i] - (1.0 - want)) < 1e-5;
    }
    CHECK("region shares: axis-aligned wall, every subcell's shares", sub_ok, "a subcell's share is off");

    /* A slanted plane cutting the corner x + y + z < 0.6: a tetrahedron of
     * volume 0.6^3 / 6, with and without subcells. */
    float corner[1][4] = {
        {(float)(1 / sqrt(3.0)), (float)(1 / sqrt(3.0)), (float)(1 / sqrt(3.0)), (float)(0.6 / sqrt(3.0))}};
    double tet = 0.6 * 0.6 * 0.6 / 6;
    for (unsigned k = 0; k <= 4; k += 2) {
        lvcl_region_shares((const float(*)[4])corner, 1, k, s);
        char name[96];
        snprintf(name, sizeof name, "region shares: corner cut by a slanted plane, k = %u", k);
        CHECK(name, fabs(s[0] - tet) < 1e-6 && fabs(s[PER(k)] - (1 - tet)) < 1e-6, "%.7f, not %.7f", s[0], tet);
    }

    /* Three slanted planes through the cell: every region against a
     * 200^3 lattice (to 2e-3 of a subcell), every subcell's shares adding
     * up to 1 and the cell's to the subcells' mean. */
    float three[3][4] = {{0.8f, 0.36f, 0.48f, 0.71f}, {-0.28f, 0.96f, 0.0f, 0.23f}, {0.0f, 0.6f, 0.8f, 0.52f}};
    for (int j = 0; j < 3; j++) {
        double l = sqrt(three[j][0] * three[j][0] + three[j][1] * three[j][1] + three[j][2] * three[j][2]);
        for (int a = 0; a < 3; a++) three[j][a] = (float)(three[j][a] / l);
    }
    const unsigned k = 4, per = PER(4), m = 200;
    lvcl_region_shares((const float(*)[4])three, 3, k, s);
    double *lattice = calloc(8 * 64, sizeof *lattice);
    for (unsigned z = 0; z < m; z++)
        for (unsigned y = 0; y < m; y++)
            for (unsigned x = 0; x < m; x++) {
                double u[3] = {(x + 0.5) / m, (y + 0.5) / m, (z + 0.5) / m};
                unsigned pattern = 0;
                for (int j = 0; j < 3; j++)
                    if (three[j][0] * u[0] + three[j][1] * u[1] + three[j][2] * u[2] > three[j][3]) pattern |= 1u << j;
                unsigned sub = x * k / m + k * (y * k / m + k * (z * k / m));
                lattice[pattern * 64 + sub] += 64.0 / ((double)m * m * m);
            }
    double worst = 0, sum_worst = 0, whole_worst = 0;
    for (unsigned i = 0; i < 64; i++) {
        double sum = 0;
        for (unsigned r = 0; r < 8; r++) {
            worst = fmax(worst, fabs(s[r * per + 1 + i] - lattice[r * 64 + i]));
            sum += s[r * per + 1 + i];
        }
        sum_worst = fmax(sum_worst, fabs(sum - 1));
    }
    for (unsigned r = 0; r < 8; r++) {
        double mean = 0;
        for (unsigned i = 0; i < 64; i++) mean += s[r * per + 1 + i] / 64;
        whole_worst = fmax(whole_worst, fabs(s[r * per] - mean));
    }
    printf("(three planes: worst %.2e against the lattice)\n", worst);
    CHECK("region shares: three slanted planes match a 200^3 lattice", worst < 2e-3, "off by %.2e of a subcell", worst);
    CHECK("region shares: three slanted planes, each subcell's shares add up to 1",
          sum_worst < 1e-5 && whole_worst < 1e-6, "sum off by %.2e, the cell's volume by %.2e", sum_worst, whole_worst);
    free(lattice);
    test_open_volume();
    test_region_air();
    CHECK_EXIT();
}
