/* Adaptive sampling (docs/design.md, "Adaptive sampling"): after a first
 * epoch of uniform samples, each further epoch hands its samples to the
 * pixels in proportion to the error a sample there removes, as estimated
 * from the pixel's neighbours. */
#ifndef LVCL_ADAPTIVE_SAMPLING_H
#define LVCL_ADAPTIVE_SAMPLING_H

#include <stddef.h>
#include <stdint.h>

/* Samples per pixel of one epoch (the first is uniform). */
#define LVCL_EPOCH_SPP 8

/* The most samples one pixel may get in one epoch, in epochs' spp: a few
 * pixels of extreme variance cannot take a whole epoch. */
#define LVCL_EPOCH_MAX_SHARE 8

/* Shares `samples` samples over the width x height pixels whose running
 * sums are sum (RGB and count, 4 floats per pixel) and sum_sq (the sum of
 * each sample's squared channel mean). A pixel's share follows
 * sqrt(v / (m^2 + 0.01)), v the variance of one sample and m the mean, both
 * averaged over the 24 pixels around it (5 x 5) and not the pixel itself, so that how
 * many samples it gets does not depend on its own and its mean stays
 * unbiased; a tenth of the mean share is added everywhere, so that no pixel
 * is starved by an unlucky estimate. Rounding is dithered by a hash of the
 * pixel and `epoch`, deterministic. Writes into list the pixels with a
 * share, most first (ties in pixel order), and into rounds[j] how many of
 * them take a sample in round j (those with more than j); returns the
 * number of rounds. list holds width x height entries, rounds
 * LVCL_EPOCH_MAX_SHARE x LVCL_EPOCH_SPP. */
int lvcl_adaptive_plan(const float *sum, const float *sum_sq, uint32_t width, uint32_t height, size_t samples,
                       uint32_t epoch, uint32_t *list, uint32_t *rounds);

/* The error per sample that pixel i's share follows, into weight[i]:
 * sqrt(v / g) over the 24 pixels around it (5 x 5, not itself), v their
 * summed variance of one sample and g their summed relMSE weight
 * (m^2 + LVCL_RELMSE_GUARD). Returns the weights' sum. A pixel's share is
 * its weight plus LVCL_ADAPTIVE_SHARE_FLOOR times the mean weight. */
double lvcl_adaptive_weights(const double *variance, const double *guard, uint32_t width, uint32_t height,
                             double *weight);

/* The share every pixel gets on top, in units of the mean weight, so that
 * no pixel is starved by an unlucky estimate. */
#define LVCL_ADAPTIVE_SHARE_FLOOR 0.1

#endif
