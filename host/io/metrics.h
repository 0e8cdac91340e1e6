/* Image error metrics, as the tests and lvcl-compare report them. `ref` is the reference. */
#ifndef LVCL_METRICS_H
#define LVCL_METRICS_H

#include <stddef.h>

/* relMSE's guard against dark pixels: the 0.01 in its denominator, which
 * the light volume's time budget and adaptive sampling weigh errors by too. */
#define LVCL_RELMSE_GUARD 0.01

/* mean((a - ref)^2 / (ref^2 + LVCL_RELMSE_GUARD)) over pixels and channels. */
double lvcl_relmse(const float *a, const float *ref, size_t count);

/* sqrt(mean((a - ref)^2)). */
double lvcl_rmse(const float *a, const float *ref, size_t count);

/* Mean of each of the three channels of n RGB pixels. */
void lvcl_mean_rgb(const float *rgb, size_t n, double mean[3]);

/* The least and the largest ratio, over the whole size x size blocks of
 * two w x h RGB images, of a's block sum (all channels) over ref's, among
 * blocks where ref's is positive: where an image is locally too dark or
 * bright, which its mean hides. Returns the blocks compared (0: *lo and
 * *hi are 1). */
size_t lvcl_block_ratios(const float *a, const float *ref, int w, int h, int size, double *lo, double *hi);

#endif
