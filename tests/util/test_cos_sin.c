/* lv_cos_sin (kernels/util/sampling.h), the samplers' cosine and sine,
 * against double precision over every angle they pass it (|phi| < 3 pi),
 * and on the unit circle. */
#include <math.h>
#include <stdlib.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_COS_SIN_ARGS) t_cos_sin_args;
static LVCL_DEFINE_BINDER(t_cos_sin, T_COS_SIN_ARGS, t_cos_sin_args)

    enum {
        COUNT = 1 << 20
    };

int main(void)
{
    harness_open(NULL, &dev, &prog);
    const double pi = 3.14159265358979323846;
    float *v = malloc(2 * COUNT * sizeof *v), *phis = malloc(COUNT * sizeof *phis);
    /* The angles are made here: a device with fast math may round
     * phi_min + i step its own way, and the check needs the exact input. */
    for (int i = 0; i < COUNT; i++) phis[i] = (float)(-3 * pi + 6 * pi * i / COUNT);
    lvcl_status st = {0};
    t_cos_sin_args a = {.phis = harness_buffer(&dev, phis, COUNT * sizeof *phis),
                        .out = harness_buffer(&dev, NULL, 2 * COUNT * sizeof *v)};
    cl_kernel k = harness_kernel(&prog, "t_cos_sin");
    harness_ok(lvcl_bind_t_cos_sin(k, &a, &st), &st, "setting arguments");
    harness_run(&dev, k, COUNT);
    harness_read(&dev, a.out, 2 * COUNT * sizeof *v, v);
    double worst = 0, worst_phi = 0, worst_norm = 0;
    for (int i = 0; i < COUNT; i++) {
        double phi = phis[i];
        double e = fmax(fabs(v[2 * i] - cos(phi)), fabs(v[2 * i + 1] - sin(phi)));
        if (e > worst) worst = e, worst_phi = phi;
        double norm = fabs((double)v[2 * i] * v[2 * i] + (double)v[2 * i + 1] * v[2 * i + 1] - 1);
        if (norm > worst_norm) worst_norm = norm;
    }
    /* A few float ulps of 1: what cos and sin of a float angle can promise. */
    CHECK("lv_cos_sin within 3e-7 of cos and sin over |phi| <= 3 pi", worst <= 3e-7, "error %.3g at phi %.9g", worst,
          worst_phi);
    CHECK("lv_cos_sin on the unit circle within 1e-6", worst_norm <= 1e-6, "| |(c, s)|^2 - 1 | up to %.3g", worst_norm);
    free(v);
    free(phis);
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
