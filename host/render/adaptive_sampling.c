#include "adaptive_sampling.h"

#include <math.h>
#include <stdlib.h>

#include "../../kernels/shared_types.h"
#include "../io/metrics.h"

/* The neighbourhood whose error a pixel's share follows: the 24 pixels
 * around it in a 5 x 5 square. A 3 x 3 one followed the path tracer's
 * fireflies on the glass table and lost there (docs/design.md). */
#define REACH 2
#define MAX_SHARE (LVCL_EPOCH_MAX_SHARE * LVCL_EPOCH_SPP)

double lvcl_adaptive_weights(const double *variance, const double *guard, uint32_t width, uint32_t height,
                             double *weight)
{
    double total = 0;
    for (uint32_t y = 0; y < height; y++)
        for (uint32_t x = 0; x < width; x++) {
            double v = 0, g = 0;
            for (int dy = -REACH; dy <= REACH; dy++)
                for (int dx = -REACH; dx <= REACH; dx++) {
                    long nx = (long)x + dx, ny = (long)y + dy;
                    if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= (long)width || ny >= (long)height)
                        continue;
                    size_t j = (size_t)ny * width + (size_t)nx;
                    v += variance[j];
                    g += guard[j];
                }
            size_t i = (size_t)y * width + x;
            weight[i] = g > 0 ? sqrt(v / g) : 0;
            total += weight[i];
        }
    return total;
}

int lvcl_adaptive_plan(const float *sum, const float *sum_sq, uint32_t width, uint32_t height, size_t samples,
                       uint32_t epoch, uint32_t *list, uint32_t *rounds)
{
    size_t pixels = (size_t)width * height;
    /* Zeroed: GCC cannot tell that the loop below writes every entry. */
    double *variance = calloc(pixels ? pixels : 1, sizeof *variance);
    double *guard = calloc(pixels ? pixels : 1, sizeof *guard);
    uint8_t *share = malloc(pixels ? pixels : 1);
    if (!variance || !guard || !share) {
        free(variance);
        free(guard);
        free(share);
        return -1;
    }
    /* Per pixel: the variance of one sample's channel mean, and the
     * metric's weight of its error. */
    for (size_t i = 0; i < pixels; i++) {
        double n = sum[4 * i + 3], m = n > 0 ? (sum[4 * i] + sum[4 * i + 1] + sum[4 * i + 2]) / (3.0 * n) : 0;
        variance[i] = n > 1 ? fmax(0.0, (sum_sq[i] - n * m * m) / (n - 1)) : 0;
        guard[i] = m * m + LVCL_RELMSE_GUARD;
    }
    /* Each pixel's error per sample, from its neighbours only. */
    double *weight = malloc(pixels * sizeof *weight);
    double total = weight ? lvcl_adaptive_weights(variance, guard, width, height, weight) : 0;
    free(variance);
    free(guard);
    if (!weight) {
        free(share);
        return -1;
    }
    double mean = pixels ? total / (double)pixels : 0;
    double scale = mean > 0 ? (double)samples / ((1.0 + LVCL_ADAPTIVE_SHARE_FLOOR) * total) : 0;
    uint32_t count[MAX_SHARE + 1] = {0};
    for (size_t i = 0; i < pixels; i++) {
        /* Without any variance seen the epoch stays uniform. */
        double want =
            mean > 0 ? scale * (weight[i] + LVCL_ADAPTIVE_SHARE_FLOOR * mean) : (double)samples / (double)pixels;
        double dither = (lv_hash(lv_hash((uint32_t)i) ^ (epoch * 0x9e3779b9u)) >> 8) * 0x1p-24;
        double k = floor(want + dither);
        share[i] = (uint8_t)(k > MAX_SHARE ? MAX_SHARE : k);
        count[share[i]]++;
    }
    free(weight);
    /* Counting sort, most samples first, pixel order within. */
    uint32_t start[MAX_SHARE + 1], at = 0;
    for (int k = MAX_SHARE; k >= 1; k--) {
        start[k] = at;
        at += count[k];
    }
    for (size_t i = 0; i < pixels; i++)
        if (share[i]) list[start[share[i]]++] = (uint32_t)i;
    int n = 0;
    for (int j = 0, left = (int)at; j < MAX_SHARE && left > 0; j++) {
        rounds[n++] = (uint32_t)left;
        left -= (int)count[j + 1];
    }
    free(share);
    return n;
}
