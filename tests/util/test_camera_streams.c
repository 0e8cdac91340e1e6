/* The camera passes' random numbers (kernels/util/rng.h): a sample's first
 * LV_LATTICE_DIMS numbers step through a shifted rank-1 lattice from one
 * sample of a pixel to the next, every number is uniform over the pixels
 * (what keeps each sample unbiased), and the numbers past the lattice are
 * independent. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_CAMERA_STREAMS_ARGS) t_camera_streams_args;
static LVCL_DEFINE_BINDER(t_camera_streams, T_CAMERA_STREAMS_ARGS, t_camera_streams_args)

    enum {
        PIXELS = 1024,
        SAMPLES = 256,
        DIMS = LV_LATTICE_DIMS + 4,
        GRID = 16
    };

/* chi2 of one pixel's samples in dimensions (a, b) over a GRID x GRID grid
 * (expected count 1 per square). */
static double pair_chi2(const float *v, int pixel, int a, int b)
{
    int counts[GRID * GRID] = {0};
    for (int s = 0; s < SAMPLES; s++) {
        const float *x = v + ((size_t)pixel * SAMPLES + s) * DIMS;
        counts[(int)(x[a] * GRID) * GRID + (int)(x[b] * GRID)]++;
    }
    double chi2 = 0;
    for (int k = 0; k < GRID * GRID; k++) chi2 += (counts[k] - 1.0) * (counts[k] - 1.0);
    return chi2;
}

int main(void)
{
    harness_open(NULL, &dev, &prog);
    size_t n = (size_t)PIXELS * SAMPLES * DIMS;
    float *v = malloc(n * sizeof *v);
    lvcl_status st = {0};
    t_camera_streams_args a = {
        .seed = 5, .samples = SAMPLES, .dims = DIMS, .out = harness_buffer(&dev, NULL, n * sizeof *v)};
    cl_kernel k = harness_kernel(&prog, "t_camera_streams");
    harness_ok(lvcl_bind_t_camera_streams(k, &a, &st), &st, "setting arguments");
    harness_run(&dev, k, (size_t)PIXELS * SAMPLES);
    harness_read(&dev, a.out, n * sizeof *v, v);

    /* Sample s + 1 is sample s moved by the generator, mod 1 (to the 2^-24
     * the numbers keep). */
    static const uint32_t generator[LV_LATTICE_DIMS] = LV_LATTICE_GENERATORS;
    double worst_step = 0;
    for (int p = 0; p < PIXELS; p++)
        for (int q = 0; q + 1 < SAMPLES; q++)
            for (int d = 0; d < LV_LATTICE_DIMS; d++) {
                const float *x = v + ((size_t)p * SAMPLES + q) * DIMS;
                double step = x[DIMS + d] - x[d] - generator[d] * 0x1p-32;
                step -= floor(step + 0.5);
                worst_step = fmax(worst_step, fabs(step));
            }
    CHECK("camera streams: consecutive samples of a pixel step by the lattice's generator", worst_step < 1e-6,
          "off by %.2e", worst_step);

    /* Past the lattice the numbers are independent: a pixel's 256 samples
     * in two such dimensions over a 16 x 16 grid give chi2 near 255 (sd
     * about 23). */
    double least_after = 1e30;
    for (int p = 0; p < PIXELS; p++)
        least_after = fmin(least_after, pair_chi2(v, p, LV_LATTICE_DIMS, LV_LATTICE_DIMS + 1));
    CHECK("camera streams: numbers after the lattice are independent", least_after > 128,
          "least chi2 %.0f (independent points: about 255)", least_after);

    /* Over the pixels, each sample's numbers are uniform: one sample's
     * values in one dimension over the pixels in 16 bins, chi2 against 15
     * degrees of freedom. (A pixel's consecutive samples step by the
     * generator, so pooling them would not give a chi2 distribution.) */
    double worst_uniform = 0;
    for (int d = 0; d < DIMS; d++)
        for (int s = 0; s < SAMPLES; s += 16) {
            int counts[16] = {0};
            for (int p = 0; p < PIXELS; p++) counts[(int)(v[((size_t)p * SAMPLES + s) * DIMS + d] * 16)]++;
            double expect = PIXELS / 16.0, chi2 = 0;
            for (int b = 0; b < 16; b++) chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
            worst_uniform = fmax(worst_uniform, chi2);
        }
    /* 256 tests of chi2 with 15 degrees of freedom: the largest stays
     * below 55 with probability 1 - 5e-4. */
    CHECK("camera streams: every dimension is uniform over the pixels", worst_uniform < 55,
          "worst chi2 %.1f for 15 degrees of freedom", worst_uniform);
    clReleaseKernel(k);
    clReleaseMemObject(a.out);
    free(v);
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
