#include "metrics.h"

#include <math.h>

double lvcl_relmse(const float *a, const float *ref, size_t count)
{
    double sum = 0.0;
    for (size_t i = 0; i < count; i++) {
        double d = (double)a[i] - ref[i];
        sum += d * d / ((double)ref[i] * ref[i] + LVCL_RELMSE_GUARD);
    }
    return count ? sum / (double)count : 0.0;
}

double lvcl_rmse(const float *a, const float *ref, size_t count)
{
    double sum = 0.0;
    for (size_t i = 0; i < count; i++) {
        double d = (double)a[i] - ref[i];
        sum += d * d;
    }
    return count ? sqrt(sum / (double)count) : 0.0;
}

void lvcl_mean_rgb(const float *rgb, size_t n, double mean[3])
{
    mean[0] = mean[1] = mean[2] = 0.0;
    for (size_t i = 0; i < n; i++)
        for (int c = 0; c < 3; c++) mean[c] += rgb[3 * i + c];
    for (int c = 0; c < 3; c++) mean[c] = n ? mean[c] / (double)n : 0.0;
}

size_t lvcl_block_ratios(const float *a, const float *ref, int w, int h, int size, double *lo, double *hi)
{
    size_t blocks = 0;
    *lo = *hi = 1.0;
    for (int by = 0; size > 0 && by + size <= h; by += size)
        for (int bx = 0; bx + size <= w; bx += size) {
            double sa = 0.0, sr = 0.0;
            for (int y = by; y < by + size; y++)
                for (int x = bx; x < bx + size; x++)
                    for (int c = 0; c < 3; c++) {
                        size_t i = 3 * ((size_t)y * w + x) + c;
                        sa += a[i], sr += ref[i];
                    }
            if (!(sr > 0.0)) continue;
            double r = sa / sr;
            *lo = blocks ? fmin(*lo, r) : r;
            *hi = blocks ? fmax(*hi, r) : r;
            blocks++;
        }
    return blocks;
}
