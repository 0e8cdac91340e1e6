/* Analytic checks of the device code: the direction map is measure-preserving
 * and invertible; every BSDF's pdf integrates to its sampling rate, its
 * samples agree with eval and pdf, it conserves energy and is reciprocal. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "harness.h"

static lvcl_device dev;
static lvcl_program prog;

static cl_mem buffer(size_t bytes, const void *data)
{
    cl_int err;
    cl_mem m = clCreateBuffer(dev.context, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes, (void *)data,
                              &err);
    harness_cl(err, "allocating");
    return m;
}

static cl_kernel kernel(const char *name)
{
    cl_kernel k;
    lvcl_status st = {0};
    if (lvcl_kernel_create(&prog, name, &k, &st)) {
        printf("FAIL %s: %s\n", name, st.message);
        exit(1);
    }
    return k;
}

static void test_direction_map(unsigned n)
{
    unsigned bins = 2 * n * n, per_item = 4096, items = 1024;
    unsigned *counts = calloc(bins, sizeof *counts);
    cl_mem cbuf = buffer(bins * sizeof(unsigned), counts);
    cl_kernel k = kernel("t_direction_histogram");
    clSetKernelArg(k, 0, sizeof n, &n);
    clSetKernelArg(k, 1, sizeof per_item, &per_item);
    clSetKernelArg(k, 2, sizeof cbuf, &cbuf);
    harness_run(&dev, k, items);
    clEnqueueReadBuffer(dev.queue, cbuf, CL_TRUE, 0, bins * sizeof(unsigned), counts, 0, NULL, NULL);
    /* Each bin's count is binomial; chi-square over all bins must be near
     * its degrees of freedom (within 5 standard deviations). */
    double total = (double)per_item * items, expect = total / bins, chi2 = 0.0;
    for (unsigned b = 0; b < bins; b++) chi2 += (counts[b] - expect) * (counts[b] - expect) / expect;
    double dof = bins - 1;
    char name[64];
    snprintf(name, sizeof name, "direction map n=%u is equal-area", n);
    CHECK(name, fabs(chi2 - dof) < 5.0 * sqrt(2.0 * dof), "chi2 %.1f for %.0f degrees of freedom", chi2, dof);

    unsigned misses = 0, per_bin = 256;
    cl_mem mbuf = buffer(sizeof misses, &misses);
    cl_kernel r = kernel("t_direction_roundtrip");
    clSetKernelArg(r, 0, sizeof n, &n);
    clSetKernelArg(r, 1, sizeof per_bin, &per_bin);
    clSetKernelArg(r, 2, sizeof mbuf, &mbuf);
    harness_run(&dev, r, bins);
    clEnqueueReadBuffer(dev.queue, mbuf, CL_TRUE, 0, sizeof misses, &misses, 0, NULL, NULL);
    snprintf(name, sizeof name, "direction map n=%u round trip", n);
    CHECK(name, misses == 0, "%u of %u directions came back in another bin", misses, bins * per_bin);
    clReleaseKernel(k);
    clReleaseKernel(r);
    clReleaseMemObject(cbuf);
    clReleaseMemObject(mbuf);
    free(counts);
}

typedef struct {
    const char *name;
    float type, r, g, b, alpha, ior, specular, mode;
    int delta_only;  /* no smooth lobe: pdf and eval are zero everywhere */
    int transmits;   /* reciprocity is checked for reflection only */
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
    cl_mem cbuf = buffer(sizeof config, config), wbuf = buffer(sizeof wos, wos);
    cl_mem obuf = buffer(items * 8 * sizeof(float), NULL);
    cl_kernel k = kernel("t_bsdf_moments");
    cl_uint count = (cl_uint)items;
    clSetKernelArg(k, 0, sizeof cbuf, &cbuf);
    clSetKernelArg(k, 1, sizeof count, &count);
    clSetKernelArg(k, 2, sizeof wbuf, &wbuf);
    clSetKernelArg(k, 3, sizeof n_wo, &n_wo);
    clSetKernelArg(k, 4, sizeof samples, &samples);
    clSetKernelArg(k, 5, sizeof obuf, &obuf);
    harness_run(&dev, k, items);
    float *out = malloc(items * 8 * sizeof(float));
    clEnqueueReadBuffer(dev.queue, obuf, CL_TRUE, 0, items * 8 * sizeof(float), out, 0, NULL, NULL);

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
    clReleaseMemObject(cbuf);
    clReleaseMemObject(wbuf);
    clReleaseMemObject(obuf);
}

int main(void)
{
    harness_open(NULL, &dev, &prog);
    test_direction_map(11);
    test_direction_map(4);
    test_bsdfs();
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
