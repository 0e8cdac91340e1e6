/* Adaptive sampling's plan (host/render/adaptive_sampling.c): the shares
 * add up to the epoch's samples, follow the square root of the neighbours'
 * error (5 x 5 around the pixel), never read the pixel's own sums (which keeps its mean unbiased),
 * are capped, deterministic, and listed most first with the right rounds. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/render/adaptive_sampling.h"
#include "../check.h"

enum { W = 96, H = 64, N = W * H, SPP = 8 };

static float sum[4 * N], sum_sq[N];
static uint32_t list[N], rounds[LVCL_EPOCH_MAX_SHARE * LVCL_EPOCH_SPP];

/* Pixel i as if n samples of mean m and variance v had been taken. */
static void set_pixel(int i, double n, double m, double v)
{
    for (int c = 0; c < 3; c++) sum[4 * i + c] = (float)(n * m);
    sum[4 * i + 3] = (float)n;
    sum_sq[i] = (float)((n - 1) * v + n * m * m);
}

/* Every pixel's share, from the list and rounds of one plan. */
static int plan(size_t samples, uint32_t epoch, int *share)
{
    int count = lvcl_adaptive_plan(sum, sum_sq, W, H, samples, epoch, list, rounds);
    memset(share, 0, N * sizeof *share);
    for (int j = 0; j < count; j++)
        for (uint32_t k = 0; k < rounds[j]; k++) share[list[k]]++;
    return count;
}

static long total(const int *share)
{
    long t = 0;
    for (int i = 0; i < N; i++) t += share[i];
    return t;
}

int main(void)
{
    static int a[N], b[N];
    size_t samples = (size_t)SPP * N;

    /* No variance anywhere: the epoch stays uniform. */
    for (int i = 0; i < N; i++) set_pixel(i, 8, 0.5, 0);
    plan(samples, 1, a);
    int uniform = 1;
    for (int i = 0; i < N; i++) uniform &= a[i] == SPP;
    CHECK("adaptive plan: no variance gives every pixel the same share", uniform, "shares differ");

    /* A bright noisy block (x 20..39, y 10..29) of variance 100 times the rest's. */
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) set_pixel(y * W + x, 8, 0.5, x >= 20 && x < 40 && y >= 10 && y < 30 ? 1.0 : 0.01);
    int count = plan(samples, 1, a);
    long t = total(a);
    CHECK("adaptive plan: the shares add up to the epoch's samples (within 0.5%)",
          fabs((double)t - (double)samples) < 0.005 * (double)samples, "%ld against %zu", t, samples);
    double inside = 0, outside = 0;
    int n_in = 0, n_out = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            /* Away from the block's edge, where the neighbours are mixed. */
            if (x >= 23 && x < 37 && y >= 13 && y < 27) inside += a[y * W + x], n_in++;
            else if (x < 17 || x >= 43 || y < 7 || y >= 33) outside += a[y * W + x], n_out++;
        }
    /* sqrt(100) = 10 times the error weight, plus the floor of a tenth of
     * the mean weight everywhere. */
    double ratio = (inside / n_in) / (outside / n_out);
    double mean_weight = (400.0 * 1.0 + (N - 400.0) * 0.1) / N;
    double expected = (1.0 + 0.1 * mean_weight) / (0.1 + 0.1 * mean_weight);
    CHECK("adaptive plan: shares follow the square root of the neighbours' variance", fabs(ratio / expected - 1) < 0.05,
          "inside / outside %.3f, expected %.3f", ratio, expected);

    /* Rounds: round j takes the pixels with more than j samples, which the
     * list holds first. */
    int rounds_ok = count > 0 && rounds[0] == (uint32_t)(N - 0);
    for (int i = 0; i < N; i++) rounds_ok &= a[i] >= 1; /* the floor reaches every pixel here */
    for (int j = 0; j + 1 < count; j++) rounds_ok &= rounds[j + 1] <= rounds[j];
    for (int k = 0; k + 1 < (int)rounds[0]; k++) rounds_ok &= a[list[k]] >= a[list[k + 1]];
    CHECK("adaptive plan: the list is sorted most first and the rounds count down", rounds_ok, "count %d", count);

    /* Deterministic, and the epoch only moves the dither. */
    plan(samples, 1, b);
    CHECK("adaptive plan: the same sums give the same plan", !memcmp(a, b, sizeof a), "plans differ");
    plan(samples, 2, b);
    int close = 1;
    for (int i = 0; i < N; i++) close &= abs(a[i] - b[i]) <= 1;
    CHECK("adaptive plan: another epoch changes only the rounding", close, "a share moved by more than one");

    /* A pixel's own sums do not change its share. */
    int centre = 20 * W + 60;
    set_pixel(centre, 8, 3.0, 50.0);
    plan(samples, 1, b);
    CHECK("adaptive plan: a pixel's share ignores its own samples", a[centre] == b[centre], "%d against %d", b[centre],
          a[centre]);
    int neighbour_gains = b[centre + 1] > a[centre + 1];
    CHECK("adaptive plan: its neighbours' shares grow with its variance", neighbour_gains, "%d against %d",
          b[centre + 1], a[centre + 1]);

    /* One pixel of extreme variance cannot take the epoch. */
    for (int i = 0; i < N; i++) set_pixel(i, 8, 0.5, 0.0);
    for (int dy = -2; dy <= 2; dy++)
        for (int dx = -2; dx <= 2; dx++)
            if (dx || dy) set_pixel((30 + dy) * W + 50 + dx, 8, 0.5, 1e6);
    plan(samples, 1, a);
    int cap = LVCL_EPOCH_MAX_SHARE * LVCL_EPOCH_SPP;
    CHECK("adaptive plan: one pixel's share is capped", a[30 * W + 50] == cap, "share %d, cap %d", a[30 * W + 50], cap);
    CHECK_EXIT();
}
