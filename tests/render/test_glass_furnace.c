/* A white furnace with solid glass in it: a closed room whose walls all
 * emit Le = 1 and reflect a = 1/2 diffusely holds radiance Le / (1 - a) = 2
 * everywhere, and lossless glass does not change that (inside it radiance
 * is eta^2 times as high, and the way out gives the factor back), so every
 * pixel of a camera in the room, seeing the walls through glass or not,
 * has expectation 2.
 *
 * (a) pt and guided: the image mean within 1% of 2, lv (biased) within 2%;
 * (b) pt, where the glass fills most of the room: the image's relMSE
 *     against 2 (its noise) at 64 samples below a bound. Russian roulette
 *     must measure a path against the 1/eta^2 its refractions put in its
 *     weight (kernels/integrator/scatter.h): a cube 1.6 m wide measured
 *     0.0068 (ior 2.4) and 0.0065-0.0066 (1.5) over two seeds, where
 *     roulette on the plain weight, which ends paths inside glass for
 *     nothing and returns the survivors eta^2 too bright, measured
 *     0.033-0.034 and 0.014-0.015; the bounds lie between. (The smaller
 *     cubes gain 1.3-1.5 times, too little to bound apart from the noise
 *     of the estimate.)
 * Cubes of glass 0.2 to 1.6 m wide, refractive indices 1.33, 1.5 and 2.4,
 * one set-up with two cubes. (Rough glass is left out: a single-scattering
 * microfacet model loses energy, 4.5% at roughness 0.3 here.) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"
#include "render_or_fail.h"

#define SIZE 64
#define SPP 64
#define MAX_TRIS 48

enum { WALLS, GLASS, MATERIALS };

typedef struct {
    const char *name;
    float size; /* the cube's side, metres */
    float ior;
    int cubes;         /* 1, or 2 side by side */
    double noise_most; /* bound on pt's relMSE against 2; 0: not checked */
} setup;

static void make_scene(const setup *u, lvcl_scene *s)
{
    float tris[MAX_TRIS * 9];
    uint32_t material[MAX_TRIS];
    size_t n = 0;
    const float room_lo[3] = {-1, 0, -1}, room_hi[3] = {1, 2, 1};
    n = harness_add_box(tris, n, room_lo, room_hi);
    size_t walls = n;
    for (size_t i = 0; i < walls; i++) /* the walls face in: they emit from their front */
        for (int k = 0; k < 3; k++) {
            float t = tris[9 * i + 3 + k];
            tris[9 * i + 3 + k] = tris[9 * i + 6 + k];
            tris[9 * i + 6 + k] = t;
        }
    for (int k = 0; k < u->cubes; k++) {
        float cx = u->cubes == 1 ? 0.0f : (k ? 0.35f : -0.35f), h = 0.5f * u->size;
        const float lo[3] = {cx - h, 1.0f - h, -h}, hi[3] = {cx + h, 1.0f + h, h};
        n = harness_add_box(tris, n, lo, hi);
    }
    harness_triangle_scene(tris, n, s);
    for (size_t i = 0; i < n; i++) material[i] = i < walls ? WALLS : GLASS;
    memcpy(s->tri_material, material, n * sizeof *material);
    lvcl_material_desc *m = harness_materials(s, MATERIALS);
    for (int c = 0; c < 3; c++) {
        m[WALLS].base_color[c] = 0.5f;
        m[WALLS].emissive[c] = 1.0f;
    }
    harness_make_glass(&m[GLASS], u->ior);
    const float eye[3] = {0.9f, 1.5f, 0.9f}, target[3] = {0.0f, 1.0f, 0.0f};
    harness_look_at(s, eye, target, 60.0f);
}

/* Renders u's scene in mode; returns the image (malloc'ed) or NULL after a FAIL line. */
static float *render(const setup *u, lvcl_mode mode)
{
    lvcl_scene scene;
    make_scene(u, &scene);
    lvcl_render_request req = harness_request(mode, SIZE, SPP, 16, 200000);
    lvcl_session_config cfg = {.seed = 3, .max_depth = 64, .fast_math = 1};
    char what[200];
    snprintf(what, sizeof what, "glass furnace, %s", u->name);
    return render_or_fail(&scene, &cfg, &req, what);
}

static void test_setup(const setup *u)
{
    static const struct {
        lvcl_mode mode;
        const char *name;
        double within; /* of the mean */
    } modes[] = {{LVCL_MODE_PT, "pt", 0.01}, {LVCL_MODE_GUIDED, "guided", 0.01}, {LVCL_MODE_LV, "lv", 0.02}};
    for (size_t k = 0; k < sizeof modes / sizeof modes[0]; k++) {
        float *im = render(u, modes[k].mode);
        if (!im) continue;
        double sum = 0, noise = 0;
        size_t count = (size_t)SIZE * SIZE * 3;
        for (size_t i = 0; i < count; i++) {
            sum += im[i];
            noise += (im[i] / 2.0 - 1) * (im[i] / 2.0 - 1);
        }
        double mean = sum / count;
        noise /= count;
        printf("   %s, %s: mean %.5f, relMSE against 2 %.4g\n", u->name, modes[k].name, mean, noise);
        char name[240];
        snprintf(name, sizeof name, "glass furnace, %s: %s image mean is Le/(1-a) = 2 within %.0f%%", u->name,
                 modes[k].name, 100 * modes[k].within);
        CHECK(name, fabs(mean / 2 - 1) < modes[k].within, "mean %.5f", mean);
        if (modes[k].mode == LVCL_MODE_PT && u->noise_most > 0) {
            snprintf(name, sizeof name, "glass furnace, %s: pt noise (relMSE against 2) at most %g", u->name,
                     u->noise_most);
            CHECK(name, noise <= u->noise_most, "relMSE %.4g", noise);
        }
        free(im);
    }
}

int main(void)
{
    static const setup setups[] = {
        {"cube 1.6 m, ior 2.4", 1.6f, 2.4f, 1, 0.015}, {"cube 1.6 m, ior 1.5", 1.6f, 1.5f, 1, 0.0095},
        {"cube 0.8 m, ior 1.5", 0.8f, 1.5f, 1, 0},     {"cube 1.2 m, ior 1.33", 1.2f, 1.33f, 1, 0},
        {"cube 0.2 m, ior 2.4", 0.2f, 2.4f, 1, 0},     {"two cubes 0.5 m, ior 1.5", 0.5f, 1.5f, 2, 0},
    };
    for (size_t i = 0; i < sizeof setups / sizeof setups[0]; i++) test_setup(&setups[i]);
    CHECK_EXIT();
}
