/* The guide of guided path tracing (kernels/volume/guide.h) on one cell's
 * bins: its density integrates to 1 over the sphere, its samples fall in
 * the bins as often as the density says (chi-square against weights
 * computed here from the bin table: luminance times the clamped cosine of
 * each bin's central direction), and each sample's density is the one
 * lv_guide_pdf gives for its direction. Varied: bins per hemisphere (4, 8
 * and 16, a fine set's), the normals (axes, random, a shading normal tilted
 * from the true one), and the light (smooth, one bright bin among dim
 * ones, most bins dark). A cell with no light in front has no guide. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_BIN_TABLE_ARGS) t_bin_table_args;
typedef LVCL_KERNEL_ARGS(T_GUIDE_SAMPLING_ARGS) t_guide_sampling_args;
/* clang-format off */
static LVCL_DEFINE_BINDER(t_bin_table, T_BIN_TABLE_ARGS, t_bin_table_args)
static LVCL_DEFINE_BINDER(t_guide_sampling, T_GUIDE_SAMPLING_ARGS, t_guide_sampling_args)
/* clang-format on */

#define ITEMS 256
#define PER_ITEM 1024

    typedef enum {
        LIGHT_SMOOTH,
        LIGHT_PEAK,
        LIGHT_SPARSE,
        LIGHT_BEHIND
    } light_kind;
static const char *light_names[] = {"smooth light", "one bright bin", "most bins dark", "light only behind"};

static void unit(float *v)
{
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    for (int i = 0; i < 3; i++) v[i] /= l;
}

/* The bins' central directions (the direction light travels), from the table. */
static void bin_centres(cl_mem table, unsigned bins, float (*centre)[3])
{
    size_t floats = LV_BIN_TABLE_FLOATS(bins);
    float *t = malloc(floats * sizeof *t);
    harness_read(&dev, table, floats * sizeof *t, t);
    for (unsigned b = 0; b < bins; b++) {
        const float *group = t + (size_t)(b / LV_BIN_GROUP) * LV_BIN_GROUP_FLOATS + b % LV_BIN_GROUP;
        for (int c = 0; c < 3; c++) centre[b][c] = group[c * LV_BIN_GROUP];
    }
    free(t);
}

static float dot3(const float *a, const float *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static void test_case(unsigned n, const float ns_in[3], const float ng_in[3], light_kind light, const char *normals)
{
    unsigned bins = 2 * n * n;
    float ns[3] = {ns_in[0], ns_in[1], ns_in[2]}, ng[3] = {ng_in[0], ng_in[1], ng_in[2]};
    unit(ns);
    unit(ng);
    lvcl_status st = {0};
    t_bin_table_args t = {.n = n, .table = harness_buffer(&dev, NULL, LV_BIN_TABLE_FLOATS(bins) * sizeof(float))};
    cl_kernel kt = harness_kernel(&prog, "t_bin_table");
    harness_ok(lvcl_bind_t_bin_table(kt, &t, &st), &st, "setting arguments");
    harness_run(&dev, kt, LV_BIN_GROUPS(bins) * LV_BIN_GROUP);
    float(*centre)[3] = malloc(bins * sizeof *centre);
    bin_centres(t.table, bins, centre);

    /* The light, and the weights the guide should give each bin. */
    float *lum = calloc(bins + LV_BIN_GROUP, sizeof *lum);
    double *weight = calloc(bins, sizeof *weight), total = 0;
    harness_rng rng = {n * 7919u + (unsigned)light};
    for (unsigned b = 0; b < bins; b++) {
        float from[3] = {-centre[b][0], -centre[b][1], -centre[b][2]};
        int front = dot3(from, ns) > 0 && dot3(from, ng) > 0;
        switch (light) {
        case LIGHT_SMOOTH:
            lum[b] = (float)(1.0 + harness_uniform(&rng));
            break;
        case LIGHT_PEAK:
            lum[b] = b == bins / 3 ? 1e4f : 1.0f;
            break;
        case LIGHT_SPARSE:
            lum[b] = harness_uniform(&rng) < 0.1 ? (float)(1e3 * harness_uniform(&rng)) : 0.0f;
            break;
        case LIGHT_BEHIND:
            lum[b] = front ? 0.0f : 5.0f;
            break;
        }
        weight[b] = front ? dot3(from, ns) * lum[b] : 0.0;
        total += weight[b];
    }
    float normal_pair[8] = {ns[0], ns[1], ns[2], 0, ng[0], ng[1], ng[2], 0};
    unsigned *counts = calloc(bins, sizeof *counts);
    float results[ITEMS][4];
    t_guide_sampling_args g = {.n = n,
                               .table = t.table,
                               .luminance = harness_buffer(&dev, lum, (bins + LV_BIN_GROUP) * sizeof(float)),
                               .normals = harness_buffer(&dev, normal_pair, sizeof normal_pair),
                               .per_item = PER_ITEM,
                               .counts = harness_buffer(&dev, counts, bins * sizeof *counts),
                               .results = harness_buffer(&dev, NULL, sizeof results)};
    cl_kernel kg = harness_kernel(&prog, "t_guide_sampling");
    harness_ok(lvcl_bind_t_guide_sampling(kg, &g, &st), &st, "setting arguments");
    harness_run(&dev, kg, ITEMS);
    harness_read(&dev, g.counts, bins * sizeof *counts, counts);
    harness_read(&dev, g.results, sizeof results, results);

    char name[160];
    snprintf(name, sizeof name, "guide n=%u, %s, %s", n, normals, light_names[light]);
    if (light == LIGHT_BEHIND) {
        CHECK(name, results[0][0] == -1.0f, "a guide was set up where no light arrives from the front");
    } else {
        double integral = 0, mismatches = 0, none = 0;
        for (int i = 0; i < ITEMS; i++) {
            integral += results[i][0] / ITEMS;
            mismatches += results[i][1];
            none += results[i][2];
        }
        double samples = (double)ITEMS * PER_ITEM;
        /* The pdf times 4 pi at a uniform direction is bins p_b in bin b
         * (chosen with probability p_b by the guide): its variance is
         * bins sum p_b^2 - 1; allow 5 standard errors. */
        double sum_p2 = 0;
        for (unsigned b = 0; b < bins; b++) sum_p2 += (weight[b] / total) * (weight[b] / total);
        double tolerance = 5.0 * sqrt((bins * sum_p2 - 1.0) / samples) + 1e-4;
        snprintf(name, sizeof name, "guide n=%u, %s, %s: density integrates to 1", n, normals, light_names[light]);
        CHECK(name, fabs(integral - 1.0) < tolerance, "integral %.4f, allowed 1 +- %.4f", integral, tolerance);
        /* Chi-square over the bins the weights expect at least 20 samples
         * in; the rest together must hold what they expect, within 5
         * standard deviations, and no sample may land where the weight is 0
         * (but for rounding on a bin's edge). */
        double chi2 = 0, rare_expected = 0, rare = 0, stray = 0;
        int dof = 0;
        for (unsigned b = 0; b < bins; b++) {
            double expect = samples * weight[b] / total;
            if (weight[b] == 0) stray += counts[b];
            else if (expect < 20) {
                rare_expected += expect;
                rare += counts[b];
            } else {
                chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
                dof++;
            }
        }
        snprintf(name, sizeof name, "guide n=%u, %s, %s: samples follow the weights", n, normals, light_names[light]);
        CHECK(name,
              fabs(chi2 - dof) < 5.0 * sqrt(2.0 * dof + 1) &&
                  fabs(rare - rare_expected) < 5.0 * sqrt(rare_expected + 1) && stray < 1e-4 * samples,
              "chi2 %.1f for %d bins, rare bins %.0f against %.1f, %.0f in bins of weight 0", chi2, dof, rare,
              rare_expected, stray);
        snprintf(name, sizeof name, "guide n=%u, %s, %s: each sample's density is lv_guide_pdf's", n, normals,
                 light_names[light]);
        CHECK(name, mismatches < 1e-4 * samples && none == 0, "%.0f of %.0f differ, %.0f samples failed", mismatches,
              samples, none);
    }
    clReleaseKernel(kt);
    clReleaseKernel(kg);
    clReleaseMemObject(t.table);
    clReleaseMemObject(g.luminance);
    clReleaseMemObject(g.normals);
    clReleaseMemObject(g.counts);
    clReleaseMemObject(g.results);
    free(centre);
    free(lum);
    free(weight);
    free(counts);
}

int main(void)
{
    harness_open(NULL, &dev, &prog);
    const float up[3] = {0, 0, 1}, side[3] = {-1, 0, 0}, odd[3] = {0.3f, -0.5f, 0.8f}, tilted[3] = {0.45f, -0.4f, 0.8f};
    const unsigned ns_list[] = {4, 8, 16};
    for (int i = 0; i < 3; i++) {
        unsigned n = ns_list[i];
        for (int light = LIGHT_SMOOTH; light <= LIGHT_BEHIND; light++) {
            test_case(n, up, up, (light_kind)light, "normal +z");
            test_case(n, odd, odd, (light_kind)light, "random normal");
        }
        test_case(n, side, side, LIGHT_SPARSE, "normal -x");
        test_case(n, tilted, odd, LIGHT_SMOOTH, "shading normal tilted from the true one");
    }
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
