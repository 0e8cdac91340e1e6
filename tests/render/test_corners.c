/* A lamp behind an acute corner stays dark. Two faces meet at a corner
 * line at an acute angle (a partition against a wall): a red lamp lies
 * beyond the partition, a blue one inside the wedge, and the camera looks
 * into the corner from inside, so close that most pixels hit within a few
 * ray offsets of the corner line. With paths of at most three segments no
 * red light can reach the camera (the corner is closed), so the image's red
 * must be exactly 0. A hit within an offset of the corner that left along
 * its normal alone started beyond the partition, and its light sample saw
 * the red lamp (the path tracer showed it in a bowed wall's corner at
 * 1000:1); rays now leave from a step back along the way they came
 * (lv_leave_point, kernels/util/geometry.h; tests/accel/test_offset.c
 * checks the points themselves).
 *
 * Varied: the wedge's angle (20 to 80 degrees), the scene's turn and where
 * the corner lies (near the origin, where the offset is a millionth of the
 * scene, and far from it, where it grows with the coordinates), the mode
 * (pt, guided). Not lv: the wedge is open above and at its end, so red
 * light reflected by the wall beyond the partition does enter it, and the
 * volume's cells at the corner hold it (lv reads light arriving within a
 * cell; tests/volume/test_two_rooms.c checks it in closed rooms). Measured
 * with the offset along the normal alone: red in 7 to 19 of the 576 pixels
 * of each set-up, in both modes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "../harness.h"
#include "render_or_fail.h"

#define SIZE 24
#define SPP 8
#define MAX_TRIS 16

enum { WALLS, BRIGHT, DIM, MATERIALS };

typedef struct {
    float angle;      /* degrees between the faces */
    float yaw, pitch; /* the scene's turn */
    float centre[3];  /* where the corner's middle lies */
    float half_width; /* of the camera's view at the corner, metres */
} setup;

/* p (local: the wall in z = 0, the partition turned up from it about the
 * y axis by the angle) turned and moved as the set-up says. */
static void place(const setup *u, float p[3])
{
    harness_turn(p, u->yaw, u->pitch);
    for (int k = 0; k < 3; k++) p[k] += u->centre[k];
}

static size_t add_placed_quad(const setup *u, float *tris, size_t n, float a[3], float e1[3], float e2[3])
{
    float b[3], c[3];
    for (int k = 0; k < 3; k++) b[k] = a[k] + e1[k], c[k] = a[k] + e2[k];
    place(u, a), place(u, b), place(u, c);
    for (int k = 0; k < 3; k++) e1[k] = b[k] - a[k], e2[k] = c[k] - a[k];
    return harness_add_quad(tris, n, a, e1, e2);
}

static void make_scene(const setup *u, lvcl_scene *s)
{
    float tris[MAX_TRIS * 9];
    uint32_t material[MAX_TRIS];
    const float th = u->angle * 3.14159265f / 180, c = cosf(th), sn = sinf(th);
    size_t n = 0;
    /* The wall, 4 x 2 m, facing +z; the partition, 2 x 2 m, from the corner line. */
    float wa[3] = {-2, -1, 0}, wu[3] = {4, 0, 0}, wv[3] = {0, 2, 0};
    n = add_placed_quad(u, tris, n, wa, wu, wv);
    float pa[3] = {0, -1, 0}, pu[3] = {0, 2, 0}, pv[3] = {2 * c, 0, 2 * sn};
    n = add_placed_quad(u, tris, n, pa, pu, pv);
    for (size_t i = 0; i < n; i++) material[i] = WALLS;
    /* The red lamp beyond the partition, facing the corner across the
     * outer side's middle; the blue one inside the wedge, facing it too. */
    size_t from = n;
    float mid = 0.5f * (3.14159265f + th), r = 0.8f;
    float ba[3] = {r * cosf(mid) - 0.15f * sinf(mid), -0.15f, r * sinf(mid) + 0.15f * cosf(mid)};
    float bu[3] = {0, 0.3f, 0}, bv[3] = {0.3f * sinf(mid), 0, -0.3f * cosf(mid)};
    n = add_placed_quad(u, tris, n, ba, bu, bv);
    for (size_t i = from; i < n; i++) material[i] = BRIGHT;
    from = n;
    float h = 0.5f * th;
    float da[3] = {r * cosf(h) - 0.05f * sinf(h), -0.15f, r * sinf(h) + 0.05f * cosf(h)};
    float du[3] = {0, 0.3f, 0}, dv[3] = {0.1f * sinf(h), 0, -0.1f * cosf(h)};
    n = add_placed_quad(u, tris, n, da, du, dv);
    for (size_t i = from; i < n; i++) material[i] = DIM;

    harness_triangle_scene(tris, n, s);
    memcpy(s->tri_material, material, n * sizeof *material);
    lvcl_material_desc *m = harness_materials(s, MATERIALS);
    harness_make_lamp(&m[BRIGHT], 0.0f);
    harness_make_lamp(&m[DIM], 0.0f);
    m[BRIGHT].emissive[0] = 1000.0f;
    m[DIM].emissive[2] = 1.0f;
    /* The camera on the wedge's middle, 1 cm from the corner, looking at it. */
    float eye[3] = {0.01f * cosf(h), 0.002f, 0.01f * sinf(h)}, target[3] = {0, 0, 0};
    place(u, eye), place(u, target);
    harness_look_at(s, eye, target, 2 * atanf(u->half_width / 0.01f) * 180 / 3.14159265f);
}

/* Pixels with any red, and the image's mean blue. */
static void red_and_blue(const float *im, int *red_pixels, double *blue)
{
    *red_pixels = 0;
    *blue = 0;
    for (int i = 0; i < SIZE * SIZE; i++) {
        *red_pixels += im[3 * i] != 0.0f;
        *blue += im[3 * i + 2];
    }
    *blue /= SIZE * SIZE;
}

int main(void)
{
    /* The view's half-width: about 20 offsets of the corner's points. */
    const setup setups[] = {
        {20, 0, 0, {0, 0, 0}, 1e-4f},    {30, 31, 12, {0.4f, 0.2f, -0.3f}, 1e-4f}, {45, 0, 0, {0, 0, 0}, 1e-4f},
        {60, 57, -21, {0, 0, 0}, 1e-4f}, {80, 14, 40, {0.2f, -0.1f, 0.3f}, 1e-4f}, {45, 23, 9, {300, -120, 80}, 0.02f},
    };
    const lvcl_mode modes[] = {LVCL_MODE_PT, LVCL_MODE_GUIDED};
    const char *const mode_names[] = {"pt", "guided"};
    for (size_t i = 0; i < sizeof setups / sizeof setups[0]; i++)
        for (size_t k = 0; k < sizeof modes / sizeof modes[0]; k++) {
            const setup *u = &setups[i];
            lvcl_scene scene;
            make_scene(u, &scene);
            lvcl_render_request req = harness_request(modes[k], SIZE, SPP, 16, 20000);
            lvcl_session_config cfg = {.seed = 7, .max_depth = 3, .fast_math = 1};
            char what[200];
            snprintf(what, sizeof what, "corners: %g-degree wedge turned %g/%g at (%g, %g, %g), %s", u->angle, u->yaw,
                     u->pitch, u->centre[0], u->centre[1], u->centre[2], mode_names[k]);
            float *im = render_or_fail(&scene, &cfg, &req, what);
            if (!im) continue;
            int red;
            double blue;
            red_and_blue(im, &red, &blue);
            printf("  %s: %d red pixels, mean blue %.4g\n", what, red, blue);
            char name[240];
            snprintf(name, sizeof name, "%s: no light from behind the partition", what);
            CHECK(name, red == 0 && blue > 0, "%d of %d pixels red (mean blue %g)", red, SIZE * SIZE, blue);
            free(im);
        }
    CHECK_EXIT();
}
