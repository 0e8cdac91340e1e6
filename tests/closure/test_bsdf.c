/* Analytic checks of every BSDF family (kernels/closure): its pdf
 * integrates to its sampling rate, its samples agree with eval and pdf, it
 * conserves energy (delta glass without loss) and is reciprocal. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_BSDF_MOMENTS_ARGS) t_bsdf_moments_args;
static LVCL_DEFINE_BINDER(t_bsdf_moments, T_BSDF_MOMENTS_ARGS, t_bsdf_moments_args)

    typedef struct {
    const char *name;
    float type, r, g, b, alpha, ior, specular, mode;
    int delta_only; /* no smooth lobe: pdf and eval are zero everywhere */
    int transmits;  /* reciprocity is checked for reflection only */
} bsdf_case;

static void test_bsdfs(void)
{
    /* mode 1 = importance transport: no 1/eta^2 scaling, so R + T = 1 for clear glass. */
    static const bsdf_case cases[] = {
        {"diffuse", LV_BSDF_DIFFUSE, 1, 1, 1, 0, 1.5f, 1, 0, 0, 0},
        {"plastic rough", LV_BSDF_PLASTIC, 1, 1, 1, 0.3f, 1.5f, 1, 0, 0, 0},
        {"plastic smooth", LV_BSDF_PLASTIC, 1, 1, 1, 0, 1.5f, 1, 0, 0, 0},
        {"conductor rough", LV_BSDF_CONDUCTOR, 1, 1, 1, 0.3f, 1.5f, 1, 0, 0, 0},
        {"conductor very rough", LV_BSDF_CONDUCTOR, 1, 1, 1, 0.8f, 1.5f, 1, 0, 0, 0},
        {"mirror", LV_BSDF_CONDUCTOR, 1, 1, 1, 0, 1.5f, 1, 0, 1, 0},
        {"glass smooth", LV_BSDF_GLASS, 1, 1, 1, 0, 1.5f, 1, 1, 1, 1},
        {"glass rough", LV_BSDF_GLASS, 1, 1, 1, 0.3f, 1.5f, 1, 1, 0, 1},
        {"thin glass", LV_BSDF_THIN_GLASS, 1, 1, 1, 0, 1.5f, 1, 1, 1, 1},
    };
    const size_t n_cases = sizeof cases / sizeof cases[0];
    /* Viewing directions from normal to grazing, and from inside for glass. */
    static const float wos[][4] = {{0, 0, 1, 0}, {0.5f, 0, 0.866f, 0}, {0.94f, 0, 0.34f, 0}, {0.3f, 0.2f, -0.93f, 0}};
    const unsigned n_wo = 4, samples = 1u << 20;
    float config[8 * 16];
    for (size_t i = 0; i < n_cases; i++) {
        const bsdf_case *c = &cases[i];
        float v[8] = {c->type, c->r, c->g, c->b, c->alpha, c->ior, c->specular, c->mode};
        memcpy(&config[8 * i], v, sizeof v);
    }
    size_t items = n_cases * n_wo;
    t_bsdf_moments_args a = {
        .config = harness_buffer(&dev, config, sizeof config),
        .count = (cl_uint)items,
        .wos = harness_buffer(&dev, wos, sizeof wos),
        .n_wo = n_wo,
        .samples = samples,
        .out = harness_buffer(&dev, NULL, items * 8 * sizeof(float)),
    };
    lvcl_status st = {0};
    cl_kernel k = harness_kernel(&prog, "t_bsdf_moments");
    harness_ok(lvcl_bind_t_bsdf_moments(k, &a, &st), &st, "setting arguments");
    harness_run(&dev, k, items);
    float *out = malloc(items * 8 * sizeof(float));
    harness_read(&dev, a.out, items * 8 * sizeof(float), out);

    for (size_t i = 0; i < n_cases; i++) {
        const bsdf_case *c = &cases[i];
        for (unsigned w = 0; w < n_wo; w++) {
            /* Opaque BSDFs are only ever called with wo above the surface. */
            if (!c->transmits && wos[w][2] < 0) continue;
            const float *o = &out[8 * (i * n_wo + w)];
            char name[128];
            snprintf(name, sizeof name, "bsdf %s wo%u: pdf integrates to the sampling rate", c->name, w);
            CHECK(name, fabsf(o[0] - o[1]) < 0.02f + 0.02f * o[1], "integral %.4f, rate %.4f", o[0], o[1]);
            snprintf(name, sizeof name, "bsdf %s wo%u: samples agree with eval", c->name, w);
            CHECK(name, fabsf(o[2] - o[3]) < 0.02f + 0.02f * o[3], "integral of eval %.4f, mean weight %.4f", o[2],
                  o[3]);
            snprintf(name, sizeof name, "bsdf %s wo%u: weight x pdf = eval, pdf consistent", c->name, w);
            CHECK(name, o[6] < 1e-3f && o[7] < 1e-3f, "weight error %.2g, pdf error %.2g", o[6], o[7]);
            snprintf(name, sizeof name, "bsdf %s wo%u: conserves energy", c->name, w);
            CHECK(name, o[4] <= 1.0f + 0.01f && o[4] > 0.0f, "albedo %.4f", o[4]);
            if (c->delta_only && c->type != LV_BSDF_CONDUCTOR) {
                snprintf(name, sizeof name, "bsdf %s wo%u: lossless", c->name, w);
                CHECK(name, fabsf(o[4] - 1.0f) < 1e-3f, "albedo %.5f", o[4]);
            }
            if (!c->transmits) {
                snprintf(name, sizeof name, "bsdf %s wo%u: reciprocal", c->name, w);
                CHECK(name, o[5] < 1e-3f, "relative error %.2g", o[5]);
            }
        }
    }
    /* A white Lambertian surface reflects everything, from any direction. */
    CHECK("bsdf diffuse: white albedo is 1", fabsf(out[4] - 1.0f) < 1e-6f, "albedo %.6f", out[4]);
    free(out);
    clReleaseKernel(k);
    clReleaseMemObject(a.config);
    clReleaseMemObject(a.wos);
    clReleaseMemObject(a.out);
}

int main(void)
{
    harness_open(NULL, &dev, &prog);
    test_bsdfs();
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
