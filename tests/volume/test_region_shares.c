/* The exact shares of the regions of cut cells (host/render/volume_shares.c):
 * closed forms for one plane (an axis-aligned wall, a corner cut by a
 * slanted one), and for three slanted planes a fine lattice of points;
 * the regions' shares of every subcell add up to 1. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../../host/render/light_volume_internal.h"
#include "../check.h"

#define PER(k) (1u + ((k) ? (k) * (k) * (k) : 1u))

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
    CHECK_EXIT();
}
