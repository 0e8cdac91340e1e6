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
