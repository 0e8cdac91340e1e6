/* Guided path tracing (--mode guided) is unbiased whatever its guide holds:
 * the white furnace gives Le/(1-a) under guides of a few trusted spikes;
 * the Cornell box converges to its Mitsuba reference with guides from many
 * particles, from very few, and from deliberately wrong volumes (every
 * cell's bins reversed, so the guide points away from the light; one bin
 * in 16 kept and scaled up, spikes the guide trusts), and each stays within
 * the bound on its error against the path tracer's at the same samples; a
 * volume that holds no light gives the path tracer's image. On the glass
 * table, whose floor is lit through glass, aiming at the lamp keeps the
 * image unbiased and lowers the error well below the path tracer's. In a
 * room lit by its lamp's image in a mirror ball, the lobes of
 * concentrated light keep the image unbiased and lower the error below the
 * path tracer's, and reversed lobes keep it unbiased and within the bound.
 * In a room lit through a doorway, roulette by the volume's light keeps
 * the image the path tracer's and its noise per sample well below. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/io/image_io.h"
#include "../../host/io/metrics.h"
#include "../../host/render/light_volume_internal.h"
#include "../../host/render/session_internal.h"
#include "../check.h"
#include "../harness.h"

#define SIZE 64

/* What is done to the volume between its trace and the guided pass
 * (reversed: the bins in the opposite order and the lobes turned round). */
typedef enum { GUIDE_AS_TRACED, GUIDE_REVERSED, GUIDE_SPIKY, GUIDE_EMPTY } guide_change;

static const char *tests_dir;

/* The scene name render() makes with make_mirror_ball. */
#define MIRROR_BALL "mirror ball"

/* A closed grey room (2 x 2 x 2 m) with a small lamp on its ceiling and a
 * mirror ball (radius 0.3 m, 24 x 12 facets) on its floor, which throws
 * the lamp's image over the ceiling and walls: light that only paths which
 * hit the ball and then the lamp find, as in a caustic. */
static void make_mirror_ball(lvcl_scene *s)
{
    enum { SEGS = 24, RINGS = 12, TRIS = 12 + 2 + 2 * SEGS * RINGS };
    static float tris[TRIS * 9];
    uint32_t material[TRIS];
    size_t n = 0;
    const float lo[3] = {-1, 0, -1}, hi[3] = {1, 2, 1};
    n = harness_add_box(tris, n, lo, hi);
    const float lamp[3] = {-0.075f, 1.999f, -0.075f}, lu[3] = {0.15f, 0, 0}, lv[3] = {0, 0, 0.15f};
    size_t lamp_at = n;
    n = harness_add_quad(tris, n, lamp, lu, lv); /* faces down */
    size_t ball_at = n;
    const double pi = 3.14159265358979323846, r = 0.3, c[3] = {0.2, 0.3, 0.1};
    for (int j = 0; j < RINGS; j++)
        for (int i = 0; i < SEGS; i++) {
            float p[4][3];
            for (int k = 0; k < 4; k++) {
                double th = pi * (j + (k >> 1)) / RINGS, ph = 2 * pi * (i + ((k ^ (k >> 1)) & 1)) / SEGS;
                p[k][0] = (float)(c[0] + r * sin(th) * cos(ph));
                p[k][1] = (float)(c[1] + r * cos(th));
                p[k][2] = (float)(c[2] + r * sin(th) * sin(ph));
            }
            /* The poles' quads are triangles. */
            const int order[6] = {0, 1, 2, 0, 2, 3};
            for (int t = j == 0 ? 3 : 0; t < (j == RINGS - 1 ? 3 : 6); t++)
                memcpy(tris + 9 * n + 3 * (t % 3), p[order[t]], sizeof p[0]), n += t % 3 == 2;
        }
    harness_triangle_scene(tris, n, s);
    for (size_t i = 0; i < n; i++) material[i] = i < lamp_at ? 0 : i < ball_at ? 1 : 2;
    memcpy(s->tri_material, material, n * sizeof *material);
    lvcl_material_desc *m = harness_materials(s, 3);
    for (int k = 0; k < 3; k++) {
        m[0].base_color[k] = 0.6f;
        m[2].base_color[k] = 0.95f;
    }
    harness_make_lamp(&m[1], 80.0f);
    m[2].metallic = 1.0f;
    m[2].roughness = 0.0f;
    const float eye[3] = {0.9f, 0.6f, 0.9f}, target[3] = {-0.3f, 1.1f, -0.3f};
    harness_look_at(s, eye, target, 80.0f);
}

/* The scene name render() makes with make_door_ajar. */
#define DOOR_AJAR "door ajar"

/* Two grey rooms (harness_two_rooms) split by a wall 10 cm thick with a
 * doorway 10 cm wide and 2 m tall; the lamp lights one room (the other's
 * is grey), the camera looks into the other, lit only through the
 * doorway: most of its light arrives after several bounces, which plain
 * roulette ends early. */
static void make_door_ajar(lvcl_scene *s)
{
    static float tris[HARNESS_TWO_ROOMS_TRIANGLES * 9];
    size_t walls, n = harness_two_rooms(tris, 0.1f, 0, 0, 0.1f, 0, 0, &walls);
    harness_triangle_scene(tris, n, s);
    /* The camera's room's lamp (the two triangles after the walls) is off. */
    for (size_t i = 0; i < n; i++) s->tri_material[i] = i < walls + 2 ? 0 : 1;
    lvcl_material_desc *m = harness_materials(s, 2);
    for (int k = 0; k < 3; k++) m[0].base_color[k] = 0.7f;
    harness_make_lamp(&m[1], 100.0f);
    const float eye[3] = {1.9f, 1.2f, 0.8f}, target[3] = {0.6f, 0.8f, -0.5f};
    harness_look_at(s, eye, target, 70.0f);
}

/* Renders `scene_name` (consumed) at SIZE x SIZE, spp samples: the path
 * tracer (particles 0) or guided with a volume of `particles`, changed as
 * asked; light samples see lamps through glass or not (see_through).
 * Returns the image (malloc'ed) or NULL after a FAIL line. */
static float *render_seed(const char *what, const char *scene_name, int spp, uint64_t particles,
                          guide_change change, int see_through, unsigned seed)
{
    lvcl_status st = {0};
    lvcl_scene scene;
    lvcl_session *s = NULL;
    lvcl_session_config cfg = {.seed = seed, .max_depth = 64, .fast_math = 1};
    lvcl_render_request req = harness_request(particles ? LVCL_MODE_GUIDED : LVCL_MODE_PT, SIZE, spp, 16, particles);
    req.see_through = see_through;
    lvcl_render_result r = {0};
    lvcl_error e = LVCL_OK;
    if (!strcmp(scene_name, MIRROR_BALL)) make_mirror_ball(&scene);
    else if (!strcmp(scene_name, DOOR_AJAR)) make_door_ajar(&scene);
    else e = lvcl_scene_load(scene_name, &scene, &st);
    if (!e) e = lvcl_session_open(&scene, &cfg, &s, &st);
    if (!e && !particles) e = lvcl_session_render(s, &req, &r, &st);
    if (!e && particles) {
        /* The guided render's steps, with the change in between. */
        session_device *sd = &s->devices[0];
        e = lvcl_session_trace_volume(s, &req.volume, &st);
        int64_t *tallies = NULL;
        if (!e && change != GUIDE_AS_TRACED) e = lvcl_volume_read(sd->volume, &tallies, NULL, &st);
        if (!e && change != GUIDE_AS_TRACED) {
            const lv_grid_info *g = lvcl_volume_grid(sd->volume);
            for (size_t set = 0; set < g->tally_sets; set++) {
                int64_t *t = tallies + set * LV_SET_LONGS(g->bins);
                /* One bin in 16 keeps its light, a thousandfold: spikes
                 * the guide trusts (its share is near the most). */
                if (change == GUIDE_SPIKY)
                    for (unsigned b = 0; b < g->bins; b++)
                        for (int c = 0; c < 3; c++) t[3 * b + c] = b % 16 ? 0 : 1000 * t[3 * b + c];
                for (unsigned b = 0; b < g->bins / 2 && change != GUIDE_SPIKY; b++)
                    for (int c = 0; c < 3; c++) {
                        int64_t x = t[3 * b + c];
                        t[3 * b + c] = change == GUIDE_EMPTY ? 0 : t[3 * (g->bins - 1 - b) + c];
                        t[3 * (g->bins - 1 - b) + c] = change == GUIDE_EMPTY ? 0 : x;
                    }
                int64_t *lobe = t + 3 * (size_t)g->bins + LV_AXES;
                for (int c = 0; c < LV_LOBE_LONGS && change != GUIDE_SPIKY; c++)
                    lobe[c] = change == GUIDE_EMPTY ? 0 : c < 3 ? -lobe[c] : lobe[c];
            }
            e = lvcl_volume_write(sd->volume, tallies, NULL, "changing the volume", &st);
        }
        free(tallies);
        if (!e) e = lvcl_volume_fill_guide(sd->volume, &sd->program, &st);
        if (!e) e = lvcl_session_camera_pass(s, &req, SIZE, SIZE, &req.pass, &r, &st);
    }
    lvcl_session_close(s);
    if (e) {
        CHECK(what, 0, "render failed: %s", st.message);
        return NULL;
    }
    return r.rgb;
}

/* render_seed with seed 3. */
static float *render(const char *what, const char *scene_name, int spp, uint64_t particles, guide_change change,
                     int see_through)
{
    return render_seed(what, scene_name, spp, particles, change, see_through, 3);
}

static void test_furnace(void)
{
    /* The furnace's light is even, which gets no guide; with one bin in 16
     * kept and scaled up, every cell's guide is a few trusted spikes. */
    float *im = render("guided white furnace", "furnace", 64, 100000, GUIDE_SPIKY, 1);
    if (!im) return;
    double mean[3];
    lvcl_mean_rgb(im, SIZE * SIZE, mean);
    CHECK("guided white furnace, spiky guides: Le/(1-a) = 2 within 1%",
          fabs(mean[0] - 2.0) < 0.02 && fabs(mean[1] - 2.0) < 0.02 && fabs(mean[2] - 2.0) < 0.02, "mean %.5f %.5f %.5f",
          mean[0], mean[1], mean[2]);
    free(im);
}

/* The reference tests/reference/NAME.exr as SIZE x SIZE block means
 * (malloc'ed), or NULL after a FAIL line. */
static float *reference(const char *name)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/reference/%s.exr", tests_dir, name);
    lvcl_status st = {0};
    float *ref;
    int rw, rh;
    if (lvcl_image_read(path, &ref, &rw, &rh, &st)) {
        CHECK(name, 0, "%s", st.message);
        return NULL;
    }
    float *small = calloc((size_t)SIZE * SIZE * 3, sizeof *small);
    for (int y = 0; y < rh; y++)
        for (int x = 0; x < rw; x++)
            for (int c = 0; c < 3; c++)
                small[((y * SIZE / rh) * SIZE + x * SIZE / rw) * 3 + c] +=
                    ref[((size_t)y * rw + x) * 3 + c] * (float)(SIZE * SIZE) / (float)(rw * rh);
    free(ref);
    return small;
}

static void test_cornell(void)
{
    float *small = reference("cornell");
    if (!small) return;
    double ref_mean[3];
    lvcl_mean_rgb(small, SIZE * SIZE, ref_mean);
    size_t n = (size_t)SIZE * SIZE * 3;

    float *pt = render("Cornell box pt", "cornell", 64, 0, GUIDE_AS_TRACED, 1);
    if (!pt) return;
    double pt_error = lvcl_relmse(pt, small, n);
    struct {
        const char *name;
        uint64_t particles;
        guide_change change;
    } guides[] = {{"a guide of 2e5 particles", 200000, GUIDE_AS_TRACED},
                  {"a guide of 300 particles", 300, GUIDE_AS_TRACED},
                  {"a reversed guide", 200000, GUIDE_REVERSED},
                  {"a guide of trusted spikes", 200000, GUIDE_SPIKY}};
    for (int g = 0; g < 4; g++) {
        char name[160];
        float *low = render(guides[g].name, "cornell", 16, guides[g].particles, guides[g].change, 1);
        float *high = render(guides[g].name, "cornell", 64, guides[g].particles, guides[g].change, 1);
        if (!low || !high) {
            free(low);
            free(high);
            continue;
        }
        double mean[3], e16 = lvcl_relmse(low, small, n), e64 = lvcl_relmse(high, small, n);
        lvcl_mean_rgb(high, SIZE * SIZE, mean);
        snprintf(name, sizeof name, "guided Cornell box, %s: channel means within 1%% of the reference",
                 guides[g].name);
        int close = 1;
        for (int c = 0; c < 3; c++) close = close && fabs(mean[c] / ref_mean[c] - 1.0) < 0.01;
        CHECK(name, close, "means %.5f %.5f %.5f against %.5f %.5f %.5f", mean[0], mean[1], mean[2], ref_mean[0],
              ref_mean[1], ref_mean[2]);
        /* 4x the samples: error falls by about 4 (at least 2.5: noise
         * dominates any bias here). */
        snprintf(name, sizeof name, "guided Cornell box, %s: error falls as 1/spp", guides[g].name);
        CHECK(name, e16 / e64 > 2.5, "relMSE %.3g at 16 spp, %.3g at 64", e16, e64);
        /* With at least half the samples from the BSDF, a useless guide can
         * at most double a scattering step's second moment, and a path has
         * two guided steps (docs/guided.md). */
        snprintf(name, sizeof name, "guided Cornell box, %s: error within 4x the path tracer's", guides[g].name);
        CHECK(name, e64 < 4.0 * pt_error, "relMSE %.3g against pt's %.3g at 64 spp", e64, pt_error);
        /* Else the checks above would test the path tracer: some cells of
         * the good and the reversed guide must be guided. */
        if (guides[g].particles > 1000) {
            snprintf(name, sizeof name, "guided Cornell box, %s: the guide is used", guides[g].name);
            double d = lvcl_relmse(high, pt, n);
            CHECK(name, d > 1e-6, "relMSE %.3g against pt's image of the same seed", d);
        }
        free(low);
        free(high);
    }
    float *empty = render("an empty guide", "cornell", 64, 200000, GUIDE_EMPTY, 1);
    if (empty) {
        double e = lvcl_relmse(empty, pt, n);
        CHECK("guided Cornell box: a volume holding no light gives the path tracer's image", e < 1e-10,
              "relMSE %.3g against pt", e);
        free(empty);
    }
    free(pt);
    free(small);
}

/* The glass table's floor is lit by its lamp through the glass top. With
 * light samples that stop at glass (--see-through off), the guide aims at
 * the lamp (kernels/light/light_directions.h): unbiased, and it must lower
 * the error well below the path tracer's at the same samples, at this size
 * 0.69 of it, where the bins alone give 0.97. With light samples that see
 * through glass (the default), the image stays unbiased. */
static void test_glass_table(void)
{
    float *small = reference("glass-table");
    if (!small) return;
    size_t n = (size_t)SIZE * SIZE * 3;
    char scene[4096];
    snprintf(scene, sizeof scene, "%s/../scenes/glass-table.gltf", tests_dir);
    float *pt = render("glass table pt", scene, 64, 0, GUIDE_AS_TRACED, 0);
    float *guided = render("glass table guided", scene, 64, 200000, GUIDE_AS_TRACED, 0);
    float *seeing = render("glass table guided, seeing through glass", scene, 64, 200000, GUIDE_AS_TRACED, 1);
    if (pt && guided && seeing) {
        double mean[3], ref_mean[3], e_pt = lvcl_relmse(pt, small, n), e = lvcl_relmse(guided, small, n);
        lvcl_mean_rgb(guided, SIZE * SIZE, mean);
        lvcl_mean_rgb(small, SIZE * SIZE, ref_mean);
        int close = 1;
        for (int c = 0; c < 3; c++) close = close && fabs(mean[c] / ref_mean[c] - 1.0) < 0.01;
        CHECK("guided glass table: channel means within 1% of the reference", close,
              "means %.5f %.5f %.5f against %.5f %.5f %.5f", mean[0], mean[1], mean[2], ref_mean[0], ref_mean[1],
              ref_mean[2]);
        CHECK("guided glass table, light samples stopping at glass: aiming at the lamp through the glass, "
              "error below 0.8 of the path tracer's",
              e < 0.8 * e_pt, "relMSE %.3g against pt's %.3g at 64 spp", e, e_pt);
        lvcl_mean_rgb(seeing, SIZE * SIZE, mean);
        close = 1;
        for (int c = 0; c < 3; c++) close = close && fabs(mean[c] / ref_mean[c] - 1.0) < 0.01;
        CHECK("guided glass table, light samples seeing through glass: channel means within 1% of the reference",
              close, "means %.5f %.5f %.5f against %.5f %.5f %.5f", mean[0], mean[1], mean[2], ref_mean[0],
              ref_mean[1], ref_mean[2]);
    }
    free(pt);
    free(guided);
    free(seeing);
    free(small);
}

static int means_close(const float *im, const float *ref, double within, double *mean, double *ref_mean)
{
    lvcl_mean_rgb(im, SIZE * SIZE, mean);
    lvcl_mean_rgb(ref, SIZE * SIZE, ref_mean);
    int close = 1;
    for (int c = 0; c < 3; c++) close = close && fabs(mean[c] / ref_mean[c] - 1.0) < within;
    return close;
}

static void test_mirror_ball(void)
{
    size_t n = (size_t)SIZE * SIZE * 3;
    float *ref = render_seed("mirror ball reference", MIRROR_BALL, 4096, 0, GUIDE_AS_TRACED, 1, 11);
    float *pt = render("mirror ball pt", MIRROR_BALL, 256, 0, GUIDE_AS_TRACED, 1);
    float *guided = render("mirror ball guided", MIRROR_BALL, 256, 200000, GUIDE_AS_TRACED, 1);
    float *reversed = render("mirror ball guided, reversed", MIRROR_BALL, 256, 200000, GUIDE_REVERSED, 1);
    if (ref && pt && guided && reversed) {
        double mean[3], ref_mean[3], e_pt = lvcl_relmse(pt, ref, n), e = lvcl_relmse(guided, ref, n);
        double e_rev = lvcl_relmse(reversed, ref, n);
        printf("   mirror ball at 256 spp: relMSE pt %.4g, guided %.4g, reversed lobes %.4g\n", e_pt, e, e_rev);
        int close = means_close(guided, ref, 0.01, mean, ref_mean);
        CHECK("guided mirror ball: channel means within 1% of the path tracer's at 4,096 spp", close,
              "means %.5f %.5f %.5f against %.5f %.5f %.5f", mean[0], mean[1], mean[2], ref_mean[0], ref_mean[1],
              ref_mean[2]);
        /* Measured 0.60-0.73 of it over seeds 3 to 5 (the path tracer's
         * error moves by half between seeds: fireflies). */
        CHECK("guided mirror ball: lobes toward the lamp's image, error below 0.8 of the path tracer's",
              e < 0.8 * e_pt, "relMSE %.3g against pt's %.3g at 256 spp", e, e_pt);
        close = means_close(reversed, ref, 0.01, mean, ref_mean);
        CHECK("guided mirror ball, reversed guide: channel means within 1% of the path tracer's at 4,096 spp",
              close, "means %.5f %.5f %.5f against %.5f %.5f %.5f", mean[0], mean[1], mean[2], ref_mean[0],
              ref_mean[1], ref_mean[2]);
        CHECK("guided mirror ball, reversed guide: error within 4x the path tracer's", e_rev < 4.0 * e_pt,
              "relMSE %.3g against pt's %.3g at 256 spp", e_rev, e_pt);
    }
    free(ref);
    free(pt);
    free(guided);
    free(reversed);
}

/* Roulette by the volume's light (guide.h): in a room lit through a
 * doorway, guided paths that reach the lit side live on, so the noise per
 * sample falls well below the path tracer's while the image stays the
 * path tracer's. Two seeds each, the noise measured between them. */
static void test_door_ajar(void)
{
    size_t n = (size_t)SIZE * SIZE * 3;
    float *im[3][2] = {{0}};
    const char *what[3] = {"door ajar pt", "guided door ajar", "guided door ajar, reversed guide"};
    for (int k = 0; k < 3; k++)
        for (int seed = 0; seed < 2; seed++)
            im[k][seed] = render_seed(what[k], DOOR_AJAR, 64, k ? 200000 : 0, k == 2 ? GUIDE_REVERSED : GUIDE_AS_TRACED,
                                      1, 3 + seed);
    int ok = 1;
    for (int k = 0; k < 3; k++) ok = ok && im[k][0] && im[k][1];
    if (ok) {
        /* Each pair's noise per pixel, (a - b)^2 / 2, weighed as relMSE
         * weighs it, against the plain and guided renders' mean over 3 x 3
         * pixels (as the time budget's pilots are: a pixel's own mean would
         * shrink its fireflies' weight). */
        lvcl_render_result pooled[4];
        for (int k = 0; k < 4; k++)
            pooled[k] = (lvcl_render_result){.rgb = im[k / 2][k % 2], .width = SIZE, .height = SIZE};
        float *den = lvcl_pilot_denominators(pooled, 4), *mean = malloc(n * sizeof *mean);
        for (size_t i = 0; i < n; i++) mean[i] = 0.5f * (im[0][0][i] + im[0][1][i]);
        double noise[3];
        for (int k = 0; k < 3; k++) noise[k] = 0.5 * lvcl_weighted_difference(im[k][0], im[k][1], den, n, NULL);
        printf("   door ajar at 64 spp: noise per pixel pt %.4g, guided %.4g, reversed guide %.4g\n", noise[0],
               noise[1], noise[2]);
        for (int k = 1; k < 3; k++) {
            double m[3], ref_m[3];
            float *both = malloc(n * sizeof *both);
            for (size_t i = 0; i < n; i++) both[i] = 0.5f * (im[k][0][i] + im[k][1][i]);
            int close = means_close(both, mean, 0.02, m, ref_m);
            char name[160];
            snprintf(name, sizeof name, "%s: channel means within 2%% of the path tracer's", what[k]);
            CHECK(name, close, "means %.5f %.5f %.5f against %.5f %.5f %.5f", m[0], m[1], m[2], ref_m[0], ref_m[1],
                  ref_m[2]);
            free(both);
        }
        /* Measured 0.39 of it; 0.88 without the roulette (2026-12-06). */
        CHECK("guided door ajar: noise per sample below 0.6 of the path tracer's", noise[1] < 0.6 * noise[0],
              "%.4g against pt's %.4g", noise[1], noise[0]);
        CHECK("guided door ajar, reversed guide: noise within 4x the path tracer's", noise[2] < 4.0 * noise[0],
              "%.4g against pt's %.4g", noise[2], noise[0]);
        free(den);
        free(mean);
    }
    for (int k = 0; k < 3; k++)
        for (int seed = 0; seed < 2; seed++) free(im[k][seed]);
}

int main(int argc, char **argv)
{
    tests_dir = argc > 1 ? argv[1] : "tests";
    lvcl_device_prepare_environment();
    test_furnace();
    test_cornell();
    test_glass_table();
    test_mirror_ball();
    test_door_ajar();
    CHECK_EXIT();
}
