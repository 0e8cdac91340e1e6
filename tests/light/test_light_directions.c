/* Directions toward candidate lights (kernels/light/light_directions.h),
 * the strategy by which guided paths aim at lamps behind glass: the
 * density integrates to the probability of the candidates that face the
 * point, samples come back with the density lv_light_directions_pdf gives
 * their direction, the mean of 1 / pdf over samples is the solid angle the
 * candidates cover (which a sampler whose points did not follow its
 * density would miss), and samples of candidates that face away fail as
 * often as those candidates are picked. Varied: one triangle; four with
 * unequal weights, one of them twice, one behind another in the same
 * directions, one facing away; a candidate of weight 0; a point close to a
 * large triangle. */
#include <math.h>
#include <stdio.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_LIGHT_DIRECTIONS_ARGS) t_light_directions_args;
/* clang-format off */
static LVCL_DEFINE_BINDER(t_light_directions, T_LIGHT_DIRECTIONS_ARGS, t_light_directions_args)
/* clang-format on */

#define ITEMS 256
#define PER_ITEM 1024
#define MAX_TRIANGLES 4

typedef struct {
    const char *name;
    unsigned count;
    float corners[MAX_TRIANGLES][3][4]; /* the first corner's w: front sign */
    float weights[MAX_TRIANGLES];
    float point[4];
} layout;

/* Whether triangle t's front face looks toward p. */
static int faces(const layout *l, unsigned t, const float *p)
{
    const float(*c)[4] = l->corners[t];
    float e1[3], e2[3], n[3], d[3];
    for (int i = 0; i < 3; i++) {
        e1[i] = c[1][i] - c[0][i];
        e2[i] = c[2][i] - c[0][i];
        d[i] = p[i] - c[0][i];
    }
    n[0] = e1[1] * e2[2] - e1[2] * e2[1];
    n[1] = e1[2] * e2[0] - e1[0] * e2[2];
    n[2] = e1[0] * e2[1] - e1[1] * e2[0];
    return c[0][3] * (n[0] * d[0] + n[1] * d[1] + n[2] * d[2]) > 0;
}

static void test_layout(const layout *l)
{
    lvcl_status st = {0};
    float results[ITEMS][2][4];
    t_light_directions_args a = {
        .corners = harness_buffer(&dev, (void *)l->corners, sizeof l->corners),
        .weights = harness_buffer(&dev, (void *)l->weights, sizeof l->weights),
        .count = l->count,
        .point = harness_buffer(&dev, (void *)l->point, sizeof l->point),
        .per_item = PER_ITEM,
        .results = harness_buffer(&dev, NULL, sizeof results)};
    cl_kernel k = harness_kernel(&prog, "t_light_directions");
    harness_ok(lvcl_bind_t_light_directions(k, &a, &st), &st, "setting arguments");
    harness_run(&dev, k, ITEMS);
    harness_read(&dev, a.results, sizeof results, results);

    double total = 0, facing = 0;
    for (unsigned t = 0; t < l->count; t++) total += l->weights[t];
    for (unsigned t = 0; t < l->count; t++) facing += faces(l, t, l->point) ? l->weights[t] / total : 0;
    double n = (double)ITEMS * PER_ITEM, sum = 0, sum_sq = 0, support = 0, inverse = 0, inverse_sq = 0;
    double mismatches = 0, failed = 0;
    for (int i = 0; i < ITEMS; i++) {
        sum += results[i][0][0];
        sum_sq += results[i][0][1];
        support += results[i][0][2];
        inverse += results[i][1][0];
        inverse_sq += results[i][1][3];
        mismatches += results[i][1][1];
        failed += results[i][1][2];
    }
    double integral = sum / n, sd = sqrt(fmax(sum_sq / n - integral * integral, 0) / n);
    char name[200];
    snprintf(name, sizeof name, "light directions, %s: the density integrates to the facing candidates' probability",
             l->name);
    CHECK(name, fabs(integral - facing) < 5 * sd + 1e-4, "integral %.4f +- %.4f, expected %.4f", integral, sd, facing);
    snprintf(name, sizeof name, "light directions, %s: each sample's density is lv_light_directions_pdf's", l->name);
    CHECK(name, mismatches < 1e-4 * n, "%.0f of %.0f samples differ", mismatches, n - failed);
    /* Failures are Bernoulli with the facing-away candidates' probability. */
    double away = 1 - facing, fail_sd = sqrt(away * (1 - away) / n);
    snprintf(name, sizeof name, "light directions, %s: samples fail as often as facing-away candidates are picked",
             l->name);
    CHECK(name, fabs(failed / n - away) < 5 * fail_sd + 1e-6, "%.5f failed, expected %.5f", failed / n, away);
    /* E[1 / pdf] over all samples (failures adding 0) is the solid angle
     * where the density is positive; uniform directions measure it too. */
    double covered = 4 * CL_M_PI * support / n, covered_sd = 4 * CL_M_PI * sqrt(support / n * (1 - support / n) / n);
    double inverse_sd = sqrt(fmax(inverse_sq / n - (inverse / n) * (inverse / n), 0) / n);
    snprintf(name, sizeof name, "light directions, %s: samples cover the candidates' solid angle as their density says",
             l->name);
    CHECK(name, fabs(inverse / n - covered) < 5 * (covered_sd + inverse_sd) + 1e-3 * covered,
          "mean 1/pdf %.4f +- %.4f sr, uniform directions find %.4f +- %.4f sr", inverse / n, inverse_sd, covered,
          covered_sd);
    clReleaseKernel(k);
    clReleaseMemObject(a.corners);
    clReleaseMemObject(a.weights);
    clReleaseMemObject(a.point);
    clReleaseMemObject(a.results);
}

int main(void)
{
    harness_open(NULL, &dev, &prog);
    const layout layouts[] = {
        {"one triangle above",
         1,
         {{{-0.5f, -0.5f, 1, -1}, {0.7f, -0.4f, 1, 0}, {0, 0.6f, 1, 0}}},
         {1},
         {0, 0, 0, 0}},
        {"four: unequal weights, one twice, one behind another, one facing away",
         4,
         {{{-0.5f, -0.5f, 1, -1}, {0.7f, -0.4f, 1, 0}, {0, 0.6f, 1, 0}},
          {{-0.5f, -0.5f, 1, -1}, {0.7f, -0.4f, 1, 0}, {0, 0.6f, 1, 0}},
          {{-1.0f, -1.0f, 2, -1}, {1.4f, -0.8f, 2, 0}, {0, 1.2f, 2, 0}},
          {{1, -0.5f, -0.5f, 1}, {1, 0.6f, -0.5f, 0}, {1, 0, 0.7f, 0}}},
         {0.5f, 1.0f, 2.0f, 0.7f},
         {0, 0, 0, 0}},
        {"a candidate of weight 0",
         2,
         {{{-0.5f, -0.5f, 1, -1}, {0.7f, -0.4f, 1, 0}, {0, 0.6f, 1, 0}},
          {{-1, 0.5f, -0.5f, -1}, {-1, -0.6f, -0.5f, 0}, {-1, 0, 0.7f, 0}}},
         {0.0f, 1.0f},
         {0, 0, 0, 0}},
        {"a point 1 cm from a large triangle",
         1,
         {{{-20, -20, 0.01f, -1}, {20, -20, 0.01f, 0}, {0, 25, 0.01f, 0}}},
         {1},
         {0.3f, -0.2f, 0, 0}},
    };
    for (size_t i = 0; i < sizeof layouts / sizeof layouts[0]; i++) test_layout(&layouts[i]);
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
