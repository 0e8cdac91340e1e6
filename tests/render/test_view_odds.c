/* Light odds learned from the view (host/render/session_view.c). Two
 * rooms share a wall (harness_two_rooms), each with its lamp; the camera
 * looks into the dim one. With the packed odds the bright lamp takes most
 * particles and light samples though none of its light can reach the
 * camera; with the view's odds the dim lamp takes most of them.
 *
 * (a) Sealed rooms, bright lamp 25 and 1000 times the dim one: the dim
 *     room's noise (the relMSE between two seeds' images, which is twice a
 *     render's) with the view's odds below half that with the packed odds
 *     (measured 0.2-0.3), and its mean within 2% of the render with the
 *     bright lamp off (the estimator stays unbiased).
 * (b) A doorway 60 cm wide between the rooms, 25:1: the bright room's
 *     light reaches the camera through it, so its lamp keeps its share;
 *     the noise stays within 1.25 times the packed odds' and the two
 *     means agree within 2%.
 * (c) The odds come from integer sums: every device, and all devices at
 *     once, render the same image (relMSE below 1e-6, as test_render.c
 *     asks of every device). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/io/metrics.h"
#include "../check.h"
#include "../harness.h"

#define SIZE 32
#define SPP 16
#define PARTICLES 200000
#define DIM_LE 4.0f

static void make_rooms(float door, float ratio, lvcl_scene *s)
{
    static float tris[HARNESS_TWO_ROOMS_TRIANGLES * 9];
    size_t walls, n = harness_two_rooms(tris, 0.02f, 0, 0, door, 0, 0, &walls);
    harness_triangle_scene(tris, n, s);
    /* The two triangles after the walls light the camera's room. */
    for (size_t i = walls; i < n; i++) s->tri_material[i] = i < walls + 2 ? 1 : 2;
    lvcl_material_desc *m = harness_materials(s, 3);
    for (int k = 0; k < 3; k++) m[0].base_color[k] = 0.7f;
    harness_make_lamp(&m[1], DIM_LE);
    harness_make_lamp(&m[2], DIM_LE * ratio);
    const float eye[3] = {1.9f, 1.2f, 0.0f}, target[3] = {HARNESS_WALL_X, 1.1f, 0.0f};
    harness_look_at(s, eye, target, 70.0f);
}

/* An lv render of the rooms, or NULL after a FAIL line. */
static float *render(float door, float ratio, int view_odds, const char *device, unsigned seed)
{
    lvcl_scene scene;
    make_rooms(door, ratio, &scene);
    lvcl_render_request req = harness_request(LVCL_MODE_LV, SIZE, SPP, 16, PARTICLES);
    req.volume.view_odds = view_odds;
    lvcl_render_result r = {0};
    lvcl_status st = {0};
    if (harness_render(&scene, device, seed, &req, &r, &st)) {
        char name[160];
        snprintf(name, sizeof name, "view odds: render (door %g, %gx, device %s)", door, ratio, device);
        CHECK(name, 0, "%s", st.message);
        return NULL;
    }
    return r.rgb;
}

static double mean(const float *im)
{
    double sum = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE * 3; i++) sum += im[i];
    return sum / (SIZE * SIZE * 3);
}

/* The relMSE between two seeds' renders: twice one render's noise. */
static double noise(float door, float ratio, int view_odds, double *m)
{
    float *a = render(door, ratio, view_odds, NULL, 1), *b = render(door, ratio, view_odds, NULL, 2);
    double e = a && b ? lvcl_relmse(a, b, (size_t)SIZE * SIZE * 3) : -1;
    *m = a && b ? 0.5 * (mean(a) + mean(b)) : -1;
    free(a);
    free(b);
    return e;
}

static void test_sealed(float ratio)
{
    double m_view, m_packed, m_off;
    double view = noise(0, ratio, 1, &m_view), packed = noise(0, ratio, 0, &m_packed);
    float *off = render(0, 0, 1, NULL, 1);
    if (view < 0 || packed < 0 || !off) return free(off);
    m_off = mean(off);
    free(off);
    printf("  sealed rooms, %gx: noise %.3g with the view's odds, %.3g with the packed ones (%.2f); mean %.5g, "
           "bright lamp off %.5g\n",
           ratio, view, packed, view / packed, m_view, m_off);
    char name[160];
    snprintf(name, sizeof name, "view odds: sealed rooms at %gx, the dim room's noise below half the packed odds'",
             ratio);
    CHECK(name, view < 0.5 * packed, "%.3g against %.3g", view, packed);
    snprintf(name, sizeof name, "view odds: sealed rooms at %gx, the dim room's mean as with the bright lamp off",
             ratio);
    CHECK(name, fabs(m_view / m_off - 1) < 0.02, "%.5g against %.5g", m_view, m_off);
}

static void test_doorway(void)
{
    double m_view, m_packed;
    double view = noise(0.6f, 25, 1, &m_view), packed = noise(0.6f, 25, 0, &m_packed);
    if (view < 0 || packed < 0) return;
    printf("  doorway, 25x: noise %.3g with the view's odds, %.3g with the packed ones (%.2f); means %.5g, %.5g\n",
           view, packed, view / packed, m_view, m_packed);
    CHECK("view odds: a doorway, the noise within 1.25 times the packed odds'", view < 1.25 * packed,
          "%.3g against %.3g", view, packed);
    CHECK("view odds: a doorway, the mean as with the packed odds", fabs(m_view / m_packed - 1) < 0.02,
          "%.5g against %.5g", m_view, m_packed);
}

static void test_devices(void)
{
    int n = lvcl_device_count(0);
    if (n < 2) {
        SKIP("view odds on every device", "only one OpenCL device present");
        return;
    }
    float *first = render(0, 1000, 1, "0", 3);
    if (!first) return;
    for (int d = 1; d <= n; d++) {
        char spec[16], name[96];
        snprintf(spec, sizeof spec, d < n ? "%d" : "all", d);
        snprintf(name, sizeof name, "view odds: device %s renders what device 0 renders", spec);
        float *im = render(0, 1000, 1, spec, 3);
        if (!im) continue;
        double e = lvcl_relmse(im, first, (size_t)SIZE * SIZE * 3);
        CHECK(name, e < 1e-6, "relMSE %.3g between the devices", e);
        free(im);
    }
    free(first);
}

int main(void)
{
    /* PoCL then offers two devices, so the cross-device check has a pair. */
    setenv("POCL_DEVICES", "pthread basic", 0);
    lvcl_device_prepare_environment();
    test_sealed(25);
    test_sealed(1000);
    test_doorway();
    test_devices();
    CHECK_EXIT();
}
