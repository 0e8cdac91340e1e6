/* Glass tinted by its base colour (glTF's KHR_materials_transmission):
 * light passing through is multiplied by the base colour at each crossing
 * of a surface, light reflected off it is not (kernels/closure/dielectric.h,
 * thin_dielectric.h).
 *
 * A closed grey room, a white lamp on its ceiling and a pane across the
 * whole room at 1 m, so that no light reaches the lower half but through
 * it; the camera, below the pane, sees the floor and walls. With paths of
 * the fewest segments that reach the lamp through the pane (3 for a thin
 * pane, 4 for a slab: its two faces) every contribution crosses the pane
 * once, so each pixel's red and blue are exactly its green times the
 * tint's red and blue (green 1), once for a thin pane and squared for a
 * slab, whichever way the light is found (a light sample seen through the
 * glass, a path reaching the lamp, or the guided mixture). Before the tint
 * was applied the ratios were 1. Set-ups: thin and 2 cm panes, smooth and
 * rough slabs, tints of several colours, light samples through glass on
 * and off, pt and guided. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"
#include "render_or_fail.h"

#define SIZE 24
#define MAX_TRIS 32

enum { WALLS, LAMP, PANE, MATERIALS };

typedef struct {
    const char *name;
    float thickness; /* 0: one polygon of thin glass */
    float roughness;
    float tint[3]; /* green 1 */
    lvcl_mode mode;
    int see_through;
} setup;

static void make_scene(const setup *u, lvcl_scene *s)
{
    float tris[MAX_TRIS * 9];
    uint32_t material[MAX_TRIS];
    const float room_lo[3] = {-1, 0, -1}, room_hi[3] = {1, 2, 1};
    size_t n = harness_add_box(tris, 0, room_lo, room_hi), from;
    for (size_t i = 0; i < n; i++) material[i] = WALLS;
    const float lamp[3] = {-0.3f, 1.999f, -0.3f}, lu[3] = {0.6f, 0, 0}, lv[3] = {0, 0, 0.6f};
    from = n;
    n = harness_add_quad(tris, n, lamp, lu, lv);
    for (size_t i = from; i < n; i++) material[i] = LAMP;
    from = n;
    if (u->thickness > 0) {
        const float lo[3] = {-1, 1.0f - u->thickness, -1}, hi[3] = {1, 1.0f, 1};
        n = harness_add_box(tris, n, lo, hi);
    } else {
        const float a[3] = {-1, 1.0f, -1}, e1[3] = {0, 0, 2}, e2[3] = {2, 0, 0};
        n = harness_add_quad(tris, n, a, e1, e2);
    }
    for (size_t i = from; i < n; i++) material[i] = PANE;
    harness_triangle_scene(tris, n, s);
    memcpy(s->tri_material, material, n * sizeof *material);
    lvcl_material_desc *m = harness_materials(s, MATERIALS);
    for (int c = 0; c < 3; c++) m[WALLS].base_color[c] = 0.6f;
    harness_make_lamp(&m[LAMP], 5.0f);
    harness_make_glass(&m[PANE], 1.5f);
    m[PANE].has_volume = u->thickness > 0;
    m[PANE].roughness = u->roughness;
    for (int c = 0; c < 3; c++) m[PANE].base_color[c] = u->tint[c];
    const float eye[3] = {0.8f, 0.7f, 0.8f}, target[3] = {-0.2f, 0.0f, -0.2f};
    harness_look_at(s, eye, target, 60.0f);
}

static void test_setup(const setup *u)
{
    lvcl_scene scene;
    make_scene(u, &scene);
    int crossings = u->thickness > 0 ? 2 : 1;
    lvcl_render_request req = harness_request(u->mode, SIZE, 64, 16, 200000);
    req.see_through = u->see_through;
    lvcl_session_config cfg = {.seed = 3, .max_depth = 2 + crossings, .fast_math = 1};
    char name[240];
    snprintf(name, sizeof name, "glass tint, %s", u->name);
    float *rgb = render_or_fail(&scene, &cfg, &req, name);
    if (!rgb) return;
    double want[2] = {pow(u->tint[0], crossings), pow(u->tint[2], crossings)}, worst = 0, green = 0;
    int lit = 0;
    for (int i = 0; i < SIZE * SIZE; i++) {
        const float *p = &rgb[3 * i];
        if (!(p[1] > 0)) continue;
        lit++;
        green += p[1];
        worst = fmax(worst, fabs(p[0] / p[1] - want[0]) / want[0]);
        worst = fmax(worst, fabs(p[2] / p[1] - want[1]) / want[1]);
    }
    printf("  %s: %d lit pixels, mean green %.4f, red and blue over green off by at most %.2g\n", u->name, lit,
           green / (lit ? lit : 1), worst);
    snprintf(name, sizeof name,
             "glass tint, %s: every pixel's red and blue are its green times the tint, to the power of the "
             "crossings (%d)",
             u->name, crossings);
    CHECK(name, lit >= SIZE * SIZE / 2 && worst < 1e-4, "%d of %d pixels lit; worst relative error %.3g", lit,
          SIZE * SIZE, worst);
    free(rgb);
}

int main(void)
{
    lvcl_device_prepare_environment();
    const setup setups[] = {
        {"thin pane, pt", 0, 0, {0.5f, 1, 0.25f}, LVCL_MODE_PT, 1},
        {"thin pane, pt, light samples stop at glass", 0, 0, {0.7f, 1, 0.9f}, LVCL_MODE_PT, 0},
        {"2 cm slab, pt", 0.02f, 0, {0.5f, 1, 0.25f}, LVCL_MODE_PT, 1},
        {"2 cm slab, pt, light samples stop at glass", 0.02f, 0, {0.8f, 1, 0.3f}, LVCL_MODE_PT, 0},
        {"rough 2 cm slab, pt", 0.02f, 0.3f, {0.6f, 1, 0.4f}, LVCL_MODE_PT, 1},
        {"2 cm slab, guided", 0.02f, 0, {0.5f, 1, 0.25f}, LVCL_MODE_GUIDED, 1},
    };
    for (size_t i = 0; i < sizeof setups / sizeof *setups; i++) test_setup(&setups[i]);
    CHECK_EXIT();
}
