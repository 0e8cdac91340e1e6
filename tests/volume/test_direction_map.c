/* The light volume's direction map (kernels/volume): it is equal-area
 * (uniform directions fill its 2 n^2 bins evenly, by chi-square) and
 * invertible (directions drawn inside a bin map back to it). */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_DIRECTION_HISTOGRAM_ARGS) t_direction_histogram_args;
typedef LVCL_KERNEL_ARGS(T_DIRECTION_ROUNDTRIP_ARGS) t_direction_roundtrip_args;
static LVCL_DEFINE_BINDER(t_direction_histogram, T_DIRECTION_HISTOGRAM_ARGS,
                          t_direction_histogram_args) static LVCL_DEFINE_BINDER(t_direction_roundtrip,
                                                                                T_DIRECTION_ROUNDTRIP_ARGS,
                                                                                t_direction_roundtrip_args)

    static void test_direction_map(unsigned n)
{
    unsigned bins = 2 * n * n, per_item = 4096, items = 1024;
    unsigned *counts = calloc(bins, sizeof *counts);
    lvcl_status st = {0};
    t_direction_histogram_args h = {
        .n = n, .per_item = per_item, .counts = harness_buffer(&dev, counts, bins * sizeof(unsigned))};
    cl_kernel k = harness_kernel(&prog, "t_direction_histogram");
    harness_ok(lvcl_bind_t_direction_histogram(k, &h, &st), &st, "setting arguments");
    harness_run(&dev, k, items);
    harness_read(&dev, h.counts, bins * sizeof(unsigned), counts);
    /* Each bin's count is binomial; chi-square over all bins must be near
     * its degrees of freedom (within 5 standard deviations). */
    double total = (double)per_item * items, expect = total / bins, chi2 = 0.0;
    for (unsigned b = 0; b < bins; b++) chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
    double dof = bins - 1;
    char name[64];
    snprintf(name, sizeof name, "direction map n=%u is equal-area", n);
    CHECK(name, fabs(chi2 - dof) < 5.0 * sqrt(2.0 * dof), "chi2 %.1f for %.0f degrees of freedom", chi2, dof);

    unsigned misses = 0, per_bin = 256;
    t_direction_roundtrip_args t = {
        .n = n, .per_item = per_bin, .misses = harness_buffer(&dev, &misses, sizeof misses)};
    cl_kernel r = harness_kernel(&prog, "t_direction_roundtrip");
    harness_ok(lvcl_bind_t_direction_roundtrip(r, &t, &st), &st, "setting arguments");
    harness_run(&dev, r, bins);
    harness_read(&dev, t.misses, sizeof misses, &misses);
    snprintf(name, sizeof name, "direction map n=%u round trip", n);
    CHECK(name, misses == 0, "%u of %u directions came back in another bin", misses, bins * per_bin);
    clReleaseKernel(k);
    clReleaseKernel(r);
    clReleaseMemObject(h.counts);
    clReleaseMemObject(t.misses);
    free(counts);
}

int main(void)
{
    harness_open(NULL, &dev, &prog);
    test_direction_map(11);
    test_direction_map(4);
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
