/* The von Mises-Fisher lobe of guided paths (lv_sample_vmf and lv_vmf_pdf,
 * kernels/util/sampling.h), for concentrations 0.5 to 5,000 about the axes,
 * -z (the frame's other branch) and a random direction: the samples are
 * unit vectors; their angle from the mean follows the distribution's cdf
 * in 1 - cos, P(t <= x) = (1 - exp(-kappa x)) / (1 - exp(-2 kappa)), and
 * their azimuth about the mean is uniform (chi-square over 20 and 16
 * bins); and lv_vmf_pdf at each sample is that density,
 * kappa exp(-kappa t) / (2 pi (1 - exp(-2 kappa))), in double here. A
 * sampler whose concentration is 2% off fails 19 of the 20 cdf checks. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../check.h"
#include "../harness.h"

static lvcl_device dev;
static lvcl_program prog;

typedef LVCL_KERNEL_ARGS(T_VMF_ARGS) t_vmf_args;
static LVCL_DEFINE_BINDER(t_vmf, T_VMF_ARGS, t_vmf_args)

#define PER_CASE (1 << 20)
#define T_BINS 20
#define PHI_BINS 16
/* chi-square at p = 1e-5 for 19 and 15 degrees of freedom (40 such checks) */
#define CHI2_T 57.4
#define CHI2_PHI 50.5

static const double pi = 3.14159265358979323846;

int main(void)
{
    harness_open(NULL, &dev, &prog);
    const float kappas[] = {0.5f, 3.0f, 30.0f, 300.0f, 5000.0f};
    const float mus[][3] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0.267261f, -0.534522f, 0.801784f}};
    enum { KAPPAS = sizeof kappas / sizeof kappas[0], MUS = sizeof mus / sizeof mus[0], CASES = KAPPAS * MUS };
    float cases[CASES][4];
    for (int m = 0; m < MUS; m++)
        for (int k = 0; k < KAPPAS; k++) {
            float *c = cases[m * KAPPAS + k];
            c[0] = mus[m][0], c[1] = mus[m][1], c[2] = mus[m][2], c[3] = kappas[k];
        }
    size_t n = (size_t)CASES * PER_CASE;
    float *out = malloc(4 * n * sizeof *out);
    lvcl_status st = {0};
    t_vmf_args a = {.cases = harness_buffer(&dev, cases, sizeof cases),
                    .per_item = PER_CASE,
                    .out = harness_buffer(&dev, NULL, 4 * n * sizeof *out)};
    cl_kernel kern = harness_kernel(&prog, "t_vmf");
    harness_ok(lvcl_bind_t_vmf(kern, &a, &st), &st, "setting arguments");
    harness_run(&dev, kern, n);
    harness_read(&dev, a.out, 4 * n * sizeof *out, out);
    for (int c = 0; c < CASES; c++) {
        double mu[3] = {cases[c][0], cases[c][1], cases[c][2]}, kappa = cases[c][3];
        /* a frame about mu for the azimuth */
        double e1[3] = {fabs(mu[0]) < 0.9 ? 1 : 0, fabs(mu[0]) < 0.9 ? 0 : 1, 0}, e2[3];
        double d = e1[0] * mu[0] + e1[1] * mu[1] + e1[2] * mu[2], l = 0;
        for (int i = 0; i < 3; i++) e1[i] -= d * mu[i], l += e1[i] * e1[i];
        for (int i = 0; i < 3; i++) e1[i] /= sqrt(l);
        e2[0] = mu[1] * e1[2] - mu[2] * e1[1], e2[1] = mu[2] * e1[0] - mu[0] * e1[2], e2[2] = mu[0] * e1[1] - mu[1] * e1[0];
        double t_count[T_BINS] = {0}, phi_count[PHI_BINS] = {0}, worst_norm = 0, worst_pdf = 0;
        for (size_t s = 0; s < PER_CASE; s++) {
            const float *w = out + 4 * ((size_t)c * PER_CASE + s);
            double len = sqrt((double)w[0] * w[0] + (double)w[1] * w[1] + (double)w[2] * w[2]);
            worst_norm = fmax(worst_norm, fabs(len - 1));
            double diff2 = 0, x = 0, y = 0;
            for (int i = 0; i < 3; i++) {
                double wi = w[i] / len;
                diff2 += (wi - mu[i]) * (wi - mu[i]);
                x += wi * e1[i];
                y += wi * e2[i];
            }
            double t = 0.5 * diff2; /* 1 - cos, without cancellation */
            double u = -expm1(-kappa * t) / -expm1(-2 * kappa);
            t_count[(int)fmin(u * T_BINS, T_BINS - 1)] += 1;
            if (x * x + y * y > 0) phi_count[(int)fmin((atan2(y, x) + pi) / (2 * pi) * PHI_BINS, PHI_BINS - 1)] += 1;
            double pdf = kappa * exp(-kappa * t) / (2 * pi * -expm1(-2 * kappa));
            worst_pdf = fmax(worst_pdf, fabs(w[3] / pdf - 1));
        }
        double chi_t = 0, chi_phi = 0, phi_total = 0;
        for (int b = 0; b < PHI_BINS; b++) phi_total += phi_count[b];
        for (int b = 0; b < T_BINS; b++) {
            double e = (double)PER_CASE / T_BINS;
            chi_t += (t_count[b] - e) * (t_count[b] - e) / e;
        }
        for (int b = 0; b < PHI_BINS; b++) {
            double e = phi_total / PHI_BINS;
            chi_phi += (phi_count[b] - e) * (phi_count[b] - e) / e;
        }
        char name[200];
        const char *where = c / KAPPAS == 3 ? "a random mean" : c / KAPPAS == 1 ? "mean -z" : "a mean on an axis";
        snprintf(name, sizeof name, "vMF, kappa %g, %s: samples are unit vectors within 1e-5", kappa, where);
        CHECK(name, worst_norm <= 1e-5, "| |w| - 1 | up to %.3g", worst_norm);
        snprintf(name, sizeof name, "vMF, kappa %g, %s: angles from the mean follow the cdf (chi2 over %d bins)",
                 kappa, where, T_BINS);
        CHECK(name, chi_t < CHI2_T, "chi2 %.1f", chi_t);
        snprintf(name, sizeof name, "vMF, kappa %g, %s: azimuths uniform (chi2 over %d bins)", kappa, where,
                 PHI_BINS);
        CHECK(name, chi_phi < CHI2_PHI, "chi2 %.1f", chi_phi);
        snprintf(name, sizeof name, "vMF, kappa %g, %s: lv_vmf_pdf is the density within 0.2%%", kappa, where);
        CHECK(name, worst_pdf <= 2e-3, "relative error up to %.3g", worst_pdf);
    }
    free(out);
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
