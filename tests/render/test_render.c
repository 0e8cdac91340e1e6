/* Whole renders against ground truth: the white furnace against its
 * closed form, the Cornell boxes against Mitsuba 3 references (error must
 * fall as 1/spp), the same scene at millimetre and kilometre scale, and the
 * same render on every OpenCL device present. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../../host/io/image_io.h"
#include "../../host/io/metrics.h"
#include "../check.h"
#include "../harness.h"

static const char *tests_dir;

typedef struct {
    float *rgb;
    int width, height;
} image;

static int all_finite(const image *im)
{
    for (size_t i = 0; i < (size_t)im->width * im->height * 3; i++)
        if (!isfinite(im->rgb[i])) return 0;
    return 1;
}

/* Renders `scene` (consumed) with the path tracer; returns 0 and leaves
 * im->rgb NULL on failure, after a FAIL line. */
static int render_request(const char *what, lvcl_scene *scene, const char *device, unsigned seed,
                          const lvcl_render_request *req, image *im)
{
    lvcl_status st = {0};
    lvcl_render_result r;
    memset(im, 0, sizeof *im);
    if (harness_render(scene, device, seed, req, &r, &st)) {
        CHECK(what, 0, "render failed: %s", st.message);
        return 0;
    }
    im->rgb = r.rgb;
    im->width = r.width;
    im->height = r.height;
    return 1;
}

static int render(const char *what, lvcl_scene *scene, const char *device, unsigned seed, int width, int height,
                  int spp, image *im)
{
    lvcl_render_request req = {.mode = LVCL_MODE_PT, .width = width, .height = height, .pass = {.spp = spp}};
    return render_request(what, scene, device, seed, &req, im);
}

static int load(const char *name, lvcl_scene *scene)
{
    lvcl_status st = {0};
    if (lvcl_scene_load(name, scene, &st)) {
        CHECK(name, 0, "cannot load: %s", st.message);
        return 0;
    }
    return 1;
}

static int read_reference(const char *path, image *ref)
{
    lvcl_status st = {0};
    return lvcl_image_read(path, &ref->rgb, &ref->width, &ref->height, &st) == LVCL_OK;
}

/* Le / (1 - a) = 1 / (1 - 0.5) = 2 everywhere inside the closed box. */
static void test_furnace(void)
{
    lvcl_scene scene;
    image im;
    if (!load("furnace", &scene) || !render("furnace", &scene, NULL, 1, 64, 64, 256, &im)) return;
    double mean[3];
    lvcl_mean_rgb(im.rgb, (size_t)im.width * im.height, mean);
    for (int c = 0; c < 3; c++)
        CHECK(c == 0       ? "white furnace: red is Le/(1-a) = 2 within 1%"
                  : c == 1 ? "white furnace: green is 2 within 1%"
                           : "white furnace: blue is 2 within 1%",
              fabs(mean[c] - 2.0) < 0.02, "channel %d: %.5f", c, mean[c]);
    CHECK("white furnace: image finite", all_finite(&im), "NaN or Inf in the image");
    free(im.rgb);
}

/* relMSE against a Mitsuba reference at growing spp: it must fall about as
 * 1/spp (a factor of at least 6 for 16x the samples: noise dominates any
 * bias here) and reach `target` at the highest count. */
static void test_convergence(const char *label, const char *scene_name, const char *ref_path, const int *spps, int n,
                             double target)
{
    image ref;
    char name[160];
    if (!read_reference(ref_path, &ref)) {
        snprintf(name, sizeof name, "%s: reference", label);
        SKIP(name, "reference image not found (../shared is absent outside the lvcl workspace)");
        return;
    }
    double err[8] = {0};
    for (int i = 0; i < n; i++) {
        lvcl_scene scene;
        image im;
        if (!load(scene_name, &scene) || !render(label, &scene, NULL, 7, ref.width, ref.height, spps[i], &im)) break;
        err[i] = lvcl_relmse(im.rgb, ref.rgb, (size_t)ref.width * ref.height * 3);
        printf("  %s: %d spp, relMSE %.3g\n", label, spps[i], err[i]);
        snprintf(name, sizeof name, "%s: %d spp image finite", label, spps[i]);
        CHECK(name, all_finite(&im), "NaN or Inf in the image");
        free(im.rgb);
    }
    snprintf(name, sizeof name, "%s: relMSE falls about as 1/spp", label);
    double ratio = err[0] / err[n - 1], ideal = (double)spps[n - 1] / spps[0];
    CHECK(name, ratio > 0.4 * ideal, "relMSE %.3g at %d spp, %.3g at %d spp: ratio %.1f, 1/spp gives %.0f", err[0],
          spps[0], err[n - 1], spps[n - 1], ratio, ideal);
    snprintf(name, sizeof name, "%s: relMSE at %d spp <= %g", label, spps[n - 1], target);
    CHECK(name, err[n - 1] <= target, "relMSE %.4g", err[n - 1]);
    free(ref.rgb);
}

/* Adaptive sampling (host/render/adaptive_sampling.c) against uniform
 * sampling of the same pixels' streams: the path tracer's image at 64 spp
 * stays unbiased (channel means within 1% of the reference) and loses no
 * accuracy, and with at most one epoch (8 spp) it is the uniform image. */
static void test_adaptive(const char *ref_path)
{
    image ref;
    if (!read_reference(ref_path, &ref)) {
        SKIP("adaptive sampling", "tests/reference/cornell.exr not found");
        return;
    }
    image im[2][2];
    const int spps[2] = {8, 64};
    for (int k = 0; k < 2; k++)
        for (int a = 0; a < 2; a++) {
            lvcl_scene scene;
            lvcl_render_request req = {.mode = LVCL_MODE_PT,
                                       .width = ref.width,
                                       .height = ref.height,
                                       .pass = {.spp = spps[k], .adaptive = a}};
            if (!load("cornell", &scene) || !render_request("adaptive sampling", &scene, NULL, 7, &req, &im[k][a])) {
                free(ref.rgb);
                return;
            }
        }
    size_t n = (size_t)ref.width * ref.height;
    CHECK("adaptive sampling: one epoch (8 spp) is the uniform image",
          !memcmp(im[0][0].rgb, im[0][1].rgb, n * 3 * sizeof(float)), "images differ");
    double e_uniform = lvcl_relmse(im[1][0].rgb, ref.rgb, n * 3),
           e_adaptive = lvcl_relmse(im[1][1].rgb, ref.rgb, n * 3);
    printf("  cornell pt 64 spp: relMSE uniform %.4g, adaptive %.4g\n", e_uniform, e_adaptive);
    CHECK("adaptive sampling: Cornell box pt at 64 spp no less accurate than uniform", e_adaptive <= e_uniform,
          "relMSE %.4g against %.4g", e_adaptive, e_uniform);
    double mean[3], mean_ref[3];
    lvcl_mean_rgb(im[1][1].rgb, n, mean);
    lvcl_mean_rgb(ref.rgb, n, mean_ref);
    int unbiased = 1;
    for (int c = 0; c < 3; c++) unbiased &= fabs(mean[c] / mean_ref[c] - 1) < 0.01;
    CHECK("adaptive sampling: channel means within 1% of the reference", unbiased && all_finite(&im[1][1]),
          "means %.5f %.5f %.5f against %.5f %.5f %.5f", mean[0], mean[1], mean[2], mean_ref[0], mean_ref[1],
          mean_ref[2]);
    for (int k = 0; k < 2; k++)
        for (int a = 0; a < 2; a++) free(im[k][a].rgb);
    free(ref.rgb);
}

static void scale_scene(lvcl_scene *s, float k)
{
    for (size_t i = 0; i < 3 * s->vertex_count; i++) s->positions[i] *= k;
    for (int a = 0; a < 3; a++) s->camera.position[a] *= k;
}

/* The same paths at 1e-3 and 1e3 times the size: the same image, up to
 * float rounding (a different rounding can flip a Russian-roulette decision
 * here and there, so compare at a tolerance far below the noise). */
static void test_scale_invariance(void)
{
    image base;
    lvcl_scene scene;
    if (!load("cornell", &scene) || !render("scale 1", &scene, NULL, 3, 64, 64, 32, &base)) return;
    const float scales[] = {1e-3f, 1e3f};
    for (int i = 0; i < 2; i++) {
        image im;
        char name[96];
        snprintf(name, sizeof name, "cornell box scaled by %g renders the same image", scales[i]);
        if (!load("cornell", &scene)) continue;
        scale_scene(&scene, scales[i]);
        if (!render(name, &scene, NULL, 3, 64, 64, 32, &im)) continue;
        double e = lvcl_relmse(im.rgb, base.rgb, (size_t)64 * 64 * 3);
        CHECK(name, e < 1e-3 && all_finite(&im), "relMSE %.3g against scale 1", e);
        free(im.rgb);
    }
    free(base.rgb);
}

/* One render that uses the light volume (lv, lv-all or guided) of the Cornell box. */
static int render_lv(const char *what, lvcl_mode mode, const char *device, unsigned seed, image *im)
{
    lvcl_scene scene;
    if (!load("cornell", &scene)) return 0;
    lvcl_render_request req = harness_request(mode, 48, 8, 16, 100000);
    return render_request(what, &scene, device, seed, &req, im);
}

/* Every device renders what device 0 renders, for the same seed, with the
 * path tracer and with the light volume (lv, lv-all and guided). The random numbers
 * depend only on the seed and the tallies are integers, so the devices can
 * differ only where float rounding differs (fast-math builds may contract or
 * reorder differently per device): relMSE 1e-6 is far below the noise
 * (about 1e-2 here) and far above what matching images give (0 on PoCL's
 * two CPU devices). */
static void test_cross_device(void)
{
    int n = lvcl_device_count(0);
    if (n < 2) {
        SKIP("cross-device render", "only one OpenCL device present");
        return;
    }
    image first;
    lvcl_scene scene;
    if (!load("cornell", &scene) || !render("device 0", &scene, "0", 5, 64, 64, 16, &first)) return;
    enum { MODES = 3 };
    image lv_first[MODES];
    const lvcl_mode modes[MODES] = {LVCL_MODE_LV, LVCL_MODE_LV_ALL, LVCL_MODE_GUIDED};
    const char *mode_names[MODES] = {"lv", "lv-all", "guided"};
    for (int m = 0; m < MODES; m++) render_lv("device 0 (light volume)", modes[m], "0", 5, &lv_first[m]);
    for (int d = 1; d < n; d++) {
        char spec[16], name[96];
        snprintf(spec, sizeof spec, "%d", d);
        snprintf(name, sizeof name, "device %d renders what device 0 renders (pt)", d);
        image im;
        if (!load("cornell", &scene) || !render(name, &scene, spec, 5, 64, 64, 16, &im)) continue;
        double e = lvcl_relmse(im.rgb, first.rgb, (size_t)64 * 64 * 3);
        CHECK(name, e < 1e-6, "relMSE %.3g between the devices", e);
        free(im.rgb);
        for (int m = 0; m < MODES; m++) {
            snprintf(name, sizeof name, "device %d renders what device 0 renders (%s)", d, mode_names[m]);
            if (!lv_first[m].rgb || !render_lv(name, modes[m], spec, 5, &im)) continue;
            e = lvcl_relmse(im.rgb, lv_first[m].rgb, (size_t)48 * 48 * 3);
            CHECK(name, e < 1e-6 && all_finite(&im), "relMSE %.3g between the devices", e);
            free(im.rgb);
        }
    }
    /* All devices at once: particles split between them, bands of the
     * image handed out as they finish; the same image as device 0 alone. */
    for (int m = 0; m < MODES; m++) {
        char name[96];
        snprintf(name, sizeof name, "--device all renders what device 0 renders (%s)", mode_names[m]);
        image im;
        if (!lv_first[m].rgb || !render_lv(name, modes[m], "all", 5, &im)) continue;
        double e = lvcl_relmse(im.rgb, lv_first[m].rgb, (size_t)48 * 48 * 3);
        CHECK(name, e < 1e-6, "relMSE %.3g against device 0 alone", e);
        free(im.rgb);
    }
    image all;
    if (load("cornell", &scene) && render("--device all (pt)", &scene, "all", 5, 64, 64, 16, &all)) {
        double e = lvcl_relmse(all.rgb, first.rgb, (size_t)64 * 64 * 3);
        CHECK("--device all renders what device 0 renders (pt)", e < 1e-6, "relMSE %.3g against device 0 alone", e);
        free(all.rgb);
    }
    free(first.rgb);
    for (int m = 0; m < MODES; m++) free(lv_first[m].rgb);
}

int main(int argc, char **argv)
{
    tests_dir = argc > 1 ? argv[1] : "tests";
    /* PoCL then offers two devices, so the cross-device test has a pair. */
    setenv("POCL_DEVICES", "pthread basic", 0);
    lvcl_device_prepare_environment();

    test_furnace();
    char ref[4096];
    snprintf(ref, sizeof ref, "%s/reference/cornell.exr", tests_dir);
    const int cornell_spp[] = {16, 64, 256};
    test_convergence("cornell", "cornell", ref, cornell_spp, 3, 0.0015);
    test_adaptive(ref);
    snprintf(ref, sizeof ref, "%s/../../shared/reference/cornell-spheres.mitsuba.exr", tests_dir);
    char scene[4096];
    snprintf(scene, sizeof scene, "%s/../../shared/reference/cornell-spheres.glb", tests_dir);
    struct stat sb;
    if (stat(scene, &sb) == 0) {
        const int spheres_spp[] = {4, 64};
        test_convergence("cornell-spheres (mirror, glass)", scene, ref, spheres_spp, 2, 0.1);
    } else {
        SKIP("cornell-spheres", "../shared/reference is absent (it exists only in the lvcl workspace)");
    }
    test_scale_invariance();
    test_cross_device();
    CHECK_EXIT();
}
