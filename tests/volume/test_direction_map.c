/* The light volume's direction map (kernels/volume): it is equal-area
 * (uniform directions fill its 2 n^2 bins evenly, by chi-square) and
 * invertible (directions drawn inside a bin map back to it); and the bin
 * table's mean cosines, the integrating gather's Lambertian weights, add up
 * to the cosine's integral over any hemisphere. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_DIRECTION_HISTOGRAM_ARGS) t_direction_histogram_args;
typedef LVCL_KERNEL_ARGS(T_DIRECTION_ROUNDTRIP_ARGS) t_direction_roundtrip_args;
typedef LVCL_KERNEL_ARGS(T_BIN_TABLE_ARGS) t_bin_table_args;
typedef LVCL_KERNEL_ARGS(T_BIN_COSINE_ARGS) t_bin_cosine_args;
/* clang-format off */
static LVCL_DEFINE_BINDER(t_direction_histogram, T_DIRECTION_HISTOGRAM_ARGS, t_direction_histogram_args)
static LVCL_DEFINE_BINDER(t_direction_roundtrip, T_DIRECTION_ROUNDTRIP_ARGS, t_direction_roundtrip_args)
static LVCL_DEFINE_BINDER(t_bin_table, T_BIN_TABLE_ARGS, t_bin_table_args)
static LVCL_DEFINE_BINDER(t_bin_cosine, T_BIN_COSINE_ARGS, t_bin_cosine_args)
    /* clang-format on */

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

static void unit(float *v)
{
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++) v[i] /= l;
}

/* The sum over the bins of mean cosine x solid angle is pi for any normal
 * (the integral of the clamped cosine over the sphere), and for a shading
 * normal tilted from the true one it is the dense quadrature's. Normals:
 * the six axes (the bins' edges lie on their planes), random ones, and
 * random pairs tilted by up to about 17 degrees. The bins' central
 * directions, the rule the table replaced, must miss by more than the
 * tolerance, or the check could not tell them apart. */
static void test_bin_cosines(unsigned n)
{
    enum { AXES = 6, RANDOM = 24, TILTED = 16, COUNT = AXES + RANDOM + TILTED };
    float normals[COUNT * 2][4] = {{0}};
    srand(n);
    for (int i = 0; i < COUNT; i++) {
        float *ns = normals[2 * i], *ng = normals[2 * i + 1];
        if (i < AXES) {
            ns[i / 2] = i % 2 ? -1.0f : 1.0f;
        } else {
            for (int c = 0; c < 3; c++) ns[c] = 2.0f * rand() / (float)RAND_MAX - 1.0f;
            unit(ns);
        }
        for (int c = 0; c < 3; c++) ng[c] = ns[c];
        if (i >= AXES + RANDOM) {
            for (int c = 0; c < 3; c++) ng[c] += 0.6f * rand() / (float)RAND_MAX - 0.3f;
            unit(ng);
        }
    }
    unsigned bins = 2 * n * n;
    lvcl_status st = {0};
    t_bin_table_args t = {.n = n, .table = harness_buffer(&dev, NULL, LV_BIN_TABLE_FLOATS(bins) * sizeof(float))};
    cl_kernel k = harness_kernel(&prog, "t_bin_table");
    harness_ok(lvcl_bind_t_bin_table(k, &t, &st), &st, "setting arguments");
    harness_run(&dev, k, LV_BIN_GROUPS(bins) * LV_BIN_GROUP);
    float sums[COUNT][4];
    t_bin_cosine_args c = {.n = n,
                           .table = t.table,
                           .normals = harness_buffer(&dev, normals, sizeof normals),
                           .count = COUNT,
                           .sums = harness_buffer(&dev, NULL, sizeof sums)};
    cl_kernel q = harness_kernel(&prog, "t_bin_cosine");
    harness_ok(lvcl_bind_t_bin_cosine(q, &c, &st), &st, "setting arguments");
    harness_run(&dev, q, COUNT);
    harness_read(&dev, c.sums, sizeof sums, sums);
    double worst = 0, worst_centre = 0;
    int at = 0;
    for (int i = 0; i < COUNT; i++) {
        double want = i < AXES + RANDOM ? 3.14159265358979 : sums[i][2];
        double e = fabs(sums[i][0] / want - 1.0), ec = fabs(sums[i][1] / want - 1.0);
        if (e > worst) worst = e, at = i;
        if (ec > worst_centre) worst_centre = ec;
    }
    /* Sixteen parts per bin leave about 0.1 / n^2 where a horizon cuts bins. */
    const double tolerance = 0.12 / (n * n) + 5e-4;
    char name[80];
    snprintf(name, sizeof name, "bin table n=%u: mean cosines integrate the clamped cosine", n);
    CHECK(name, worst < tolerance && worst_centre > tolerance,
          "worst relative error %.2e (normal pair %d), the central directions' %.2e, tolerance %.1e", worst, at,
          worst_centre, tolerance);
    printf("  n=%u: worst relative error %.2e from the table, %.2e from the central directions (tolerance %.1e)\n", n,
           worst, worst_centre, tolerance);
    clReleaseKernel(k);
    clReleaseKernel(q);
    clReleaseMemObject(t.table);
    clReleaseMemObject(c.normals);
    clReleaseMemObject(c.sums);
}

int main(void)
{
    harness_open(NULL, &dev, &prog);
    test_direction_map(11);
    test_direction_map(4);
    const unsigned sizes[] = {2, 4, 8, 12};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) test_bin_cosines(sizes[i]);
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
