/* lv at the line where a glossy wall meets a diffuse ceiling or floor
 * reads what the path tracer reads. The wall is too smooth for the volume
 * to answer at (GGX alpha below 0.1: plastic or metal), so a camera ray
 * that meets it goes on as a path, and its next rough surface, the ceiling
 * right at the corner, gathers. Half of that point's near hits land on the
 * wall within a ray offset. They read the volume until 2026-12-07, as for
 * a mirror: its light averaged over the cell in front, which at the corner
 * line is brighter than the wall's light there (lv / pt 1.11 to 1.17 at
 * 24 cells in bench/leak_sweep.py's set-ups, 1.05 at 96 cells); now a near
 * hit on a surface without a delta lobe goes on as a path, as on a rough
 * one (kernels/integrator/gather.h).
 *
 * The two closed rooms of tests/harness.c, the bright one dark, the dim
 * room lit by its ceiling lamp; the shared wall (2 or 10 cm, or one
 * polygon) is glossy, the rest grey and diffuse. The camera's view is
 * 10^-4 degrees wide, so every pixel sees the corner line itself. Varied:
 * the wall's finish (plastic of GGX alpha 0.04 and 0.09, metal of
 * 0.0625), the line (ceiling, floor), cells (16 to 32), grid offset,
 * subcells (2 to 4) and the scene's turn about y. Bound: the two means
 * within 6% (measured 0.975-1.041 over seeds 5 to 7; with the near hits
 * read from the volume the four plastic walls at the ceiling read
 * 1.21-1.32, the metal one and the floor lines 1.003-1.017). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"
#include "render_or_fail.h"

#define SIZE 16
#define LV_SPP 16
#define PT_SPP 256
#define BOUND 0.06

enum { GREY, DIM, BRIGHT, GLOSSY, MATERIALS };

typedef struct {
    float thickness; /* the shared wall's, metres (0: one polygon) */
    float metallic, roughness;
    int floor; /* the line where the wall meets the floor, else the ceiling */
    int cells, subcells;
    float offset, yaw;
} setup;

static void make_scene(const setup *u, lvcl_scene *s)
{
    float tris[HARNESS_TWO_ROOMS_TRIANGLES * 9];
    size_t walls, n = harness_two_rooms(tris, u->thickness, 0, 0, 0, u->yaw, 0, &walls);
    harness_triangle_scene(tris, n, s);
    /* The rooms' box first (12 triangles), then the shared wall, then the
     * dim lamp's two triangles and the bright one's. */
    for (size_t i = 0; i < n; i++)
        s->tri_material[i] = i < 12 ? GREY : i < walls ? GLOSSY : i < walls + 2 ? DIM : BRIGHT;
    lvcl_material_desc *m = harness_materials(s, MATERIALS);
    harness_make_lamp(&m[DIM], 4.0f);
    harness_make_lamp(&m[BRIGHT], 0.0f);
    m[GLOSSY].metallic = u->metallic;
    m[GLOSSY].roughness = u->roughness;
    m[GLOSSY].specular = 1.0f;
    for (int k = 0; k < 3; k++) m[GLOSSY].base_color[k] = u->metallic > 0 ? 0.9f : 0.6f;
    float eye[3] = {1.9f, 1.2f, 0.3f},
          target[3] = {HARNESS_WALL_X + u->thickness / 2, u->floor ? 0.0f : HARNESS_ROOMS_Y, -0.2f};
    harness_turn(eye, u->yaw, 0);
    harness_turn(target, u->yaw, 0);
    harness_look_at(s, eye, target, 1e-4f);
}

static double mean_of(const float *im)
{
    double sum = 0;
    for (int i = 0; i < 3 * SIZE * SIZE; i++) sum += im[i];
    return sum / (3 * SIZE * SIZE);
}

int main(void)
{
    const setup setups[] = {
        {0.1f, 0, 0.3f, 0, 24, 2, 0.27f, 0},   {0.1f, 0, 0.3f, 0, 24, 2, 0.27f, 19.6f},
        {0.1f, 0, 0.2f, 0, 16, 4, 0.5f, 0},    {0.0f, 0, 0.3f, 0, 32, 4, 0.0f, 0},
        {0.1f, 1, 0.25f, 0, 20, 3, 0.61f, 0},  {0.1f, 0, 0.3f, 1, 24, 4, 0.37f, 0},
        {0.02f, 1, 0.25f, 1, 28, 2, 0.1f, 33},
    };
    for (size_t i = 0; i < sizeof setups / sizeof *setups; i++) {
        const setup *u = &setups[i];
        char what[240];
        snprintf(what, sizeof what,
                 "glossy corners: %s wall %.2f m (alpha %.4f) meets the %s, %d cells, %d subcells, offset %.2f, "
                 "turned %g deg",
                 u->metallic > 0 ? "metal" : "plastic", u->thickness, u->roughness * u->roughness,
                 u->floor ? "floor" : "ceiling", u->cells, u->subcells, u->offset, u->yaw);
        lvcl_session_config cfg = {.seed = 5, .max_depth = 64, .fast_math = 1};
        lvcl_scene scene;
        make_scene(u, &scene);
        lvcl_render_request req = harness_request(LVCL_MODE_LV, SIZE, LV_SPP, u->cells, 400000);
        req.volume.subcells = u->subcells;
        req.volume.offset = u->offset;
        float *lv = render_or_fail(&scene, &cfg, &req, what);
        make_scene(u, &scene);
        req = harness_request(LVCL_MODE_PT, SIZE, PT_SPP, u->cells, 1);
        float *pt = render_or_fail(&scene, &cfg, &req, what);
        if (lv && pt) {
            double ratio = mean_of(lv) / mean_of(pt);
            printf("  %s: lv / pt %.4f\n", what, ratio);
            char name[300];
            snprintf(name, sizeof name, "%s: lv reads the path tracer's light", what);
            CHECK(name, fabs(ratio - 1) < BOUND, "lv / pt %.4f (bound %g)", ratio, BOUND);
        }
        free(lv);
        free(pt);
    }
    CHECK_EXIT();
}
