/* Lamps seen through glass (kernels/integrator/see_through.h). In lv mode
 * the particle trace leaves out light that crossed only glass and kept its
 * direction, and the gather's shadow rays, blocked by glass, go on through
 * it to find that light: each piece of light must be counted once, by one
 * side. In pt and guided mode a blocked light sample goes on through the
 * glass too, and a path that reaches the lamp through it shares the light
 * with that sample by MIS: the image must stay unbiased.
 *
 * A closed grey room, a lamp on its ceiling, a glass slab under the lamp
 * with an opaque block on it; the camera, below the slab, sees the floor
 * lit through the glass and the block's shadow. The reference is the path
 * tracer with the feature off (light through glass found only by paths
 * that hit the lamp) at 2,048 samples. Slabs of several thicknesses (one
 * polygon of thin glass to 15 cm, more than a cell), refractive indices,
 * tilts, two slabs stacked (four interfaces), rough glass (which stays in
 * the volume), grid offsets, cell counts and subcell settings:
 *
 * (a) smooth glass, lv: the image mean within 2% of the reference's;
 *     measured 0.2-0.9%, where lv with --see-through off is 1.4-3.1%
 *     bright. Light counted twice or not at all would move it by a third:
 *     without the gather's part the image is 31-35% dark;
 * (b) smooth glass, lv: 8 x 8 blocks, the RMS of their relative error
 *     against the reference at most 0.75 of lv's with --see-through off
 *     (the volume blurs the block's shadow over a cell); measured 0.35-0.62;
 * (c) rough glass, which the volume keeps and light samples do not see
 *     through: lv and pt render as with the feature off, bit for bit;
 * (d) smooth glass, pt and guided at 256 samples (other random numbers
 *     than the reference's): the image mean within 1% of the reference's;
 *     measured within 0.4%. A path that finds the lamp through glass
 *     weighted 1 instead of by MIS makes it 47-57% bright; a light sample
 *     through glass without its MIS weight, guided 1.2-2.4% bright;
 * (e) smooth glass, pt at 256 samples: the blocks' RMS relative error
 *     against the reference at most 0.75 of pt's with the feature off;
 *     measured 0.44-0.61.
 * One set-up makes the block a mirror: light it turns stays in the volume,
 * and only paths find it. One makes the room glossy. One limits paths to 5
 * segments, so a light sample on the floor may see through 3 scatters and
 * the two slabs take 4: without that cap pt is 2.5 times too bright (lv
 * counts depth otherwise and is not checked there). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../host/io/metrics.h"
#include "../check.h"
#include "../harness.h"
#include "render_or_fail.h"

#define SIZE 64
#define BLOCK 8
/* The reference's samples. It is the path tracer with the feature off,
 * whose paths find the light through glass only by hitting the lamp: its
 * noise, an eighth of the 256-sample images' with the feature off, adds
 * to what the blocks' checks measure: the ratios (b) and (e) measured
 * 0.31-0.63 and 0.32-0.58 with 4,096 samples, 0.35-0.62 and 0.44-0.61
 * with this count, against a bound of 0.75. */
#define REFERENCE_SPP 2048
#define MAX_TRIS 64

/* Room [-1, 1] x [0, 2] x [-1, 1] metres. */
enum { WALLS, LAMP, GLASS, BLOCKER, MATERIALS };

typedef struct {
    const char *name;
    float thickness; /* 0: one polygon of thin glass */
    float ior, tilt_deg;
    int slabs;       /* 1 or 2, stacked 10 cm apart */
    float roughness; /* of the glass */
    float offset;    /* grid offset, in cells */
    int cells, subcells;
    int mirror;        /* the block on the slab a smooth mirror */
    float walls_gloss; /* 0: matte walls; else their roughness (glossy plastic) */
    int max_depth;     /* segments per path; 0: 64 */
} setup;

/* Turns triangles [from, n) by deg degrees about the z axis through (0, cy, 0). */
static void tilt(float *t, size_t from, size_t n, float deg, float cy)
{
    float c = cosf(deg * 3.14159265f / 180.0f), s = sinf(deg * 3.14159265f / 180.0f);
    for (size_t i = 9 * from; i < 9 * n; i += 3) {
        float x = t[i], y = t[i + 1] - cy;
        t[i] = c * x - s * y;
        t[i + 1] = s * x + c * y + cy;
    }
}

static void make_scene(const setup *u, lvcl_scene *s)
{
    float tris[MAX_TRIS * 9];
    uint32_t material[MAX_TRIS];
    size_t n = 0, from;
    const float room_lo[3] = {-1, 0, -1}, room_hi[3] = {1, 2, 1};
    n = harness_add_box(tris, n, room_lo, room_hi); /* double-sided: its faces' winding does not matter */
    for (size_t i = 0; i < n; i++) material[i] = WALLS;
    /* The lamp, 0.8 m square, just under the ceiling, facing down. */
    const float lamp[3] = {-0.4f, 1.999f, -0.4f}, lu[3] = {0.8f, 0, 0}, lv[3] = {0, 0, 0.8f};
    from = n;
    n = harness_add_quad(tris, n, lamp, lu, lv);
    for (size_t i = from; i < n; i++) material[i] = LAMP;
    /* The slabs, 1.4 m square, the first's top at 1.1 m. */
    from = n;
    for (int k = 0; k < u->slabs; k++) {
        float top = 1.1f - 0.1f * (float)k;
        if (u->thickness > 0) {
            const float lo[3] = {-0.7f, top - u->thickness, -0.7f}, hi[3] = {0.7f, top, 0.7f};
            n = harness_add_box(tris, n, lo, hi);
        } else {
            const float a[3] = {-0.7f, top, -0.7f}, e1[3] = {0, 0, 1.4f}, e2[3] = {1.4f, 0, 0};
            n = harness_add_quad(tris, n, a, e1, e2);
        }
    }
    for (size_t i = from; i < n; i++) material[i] = GLASS;
    /* An opaque block on the top slab. */
    size_t glass_end = n;
    const float blo[3] = {-0.15f, 1.1f, -0.1f}, bhi[3] = {0.05f, 1.3f, 0.1f};
    n = harness_add_box(tris, n, blo, bhi);
    for (size_t i = glass_end; i < n; i++) material[i] = BLOCKER;
    tilt(tris, from, n, u->tilt_deg, 1.1f);

    harness_triangle_scene(tris, n, s);
    memcpy(s->tri_material, material, n * sizeof *material);
    lvcl_material_desc *m = harness_materials(s, MATERIALS);
    for (int c = 0; c < 3; c++) {
        m[WALLS].base_color[c] = 0.6f;
        m[BLOCKER].base_color[c] = 0.3f;
    }
    harness_make_lamp(&m[LAMP], 5.0f);
    harness_make_glass(&m[GLASS], u->ior);
    if (u->walls_gloss > 0) {
        m[WALLS].specular = 1.0f;
        m[WALLS].roughness = u->walls_gloss;
    }
    if (u->mirror) {
        m[BLOCKER].metallic = 1.0f;
        m[BLOCKER].roughness = 0.0f;
        for (int c = 0; c < 3; c++) m[BLOCKER].base_color[c] = 0.9f;
    }
    m[GLASS].roughness = u->roughness;
    m[GLASS].has_volume = u->thickness > 0;

    const float eye[3] = {0.95f, 0.55f, 0.95f}, target[3] = {-0.1f, 0.0f, -0.1f};
    harness_look_at(s, eye, target, 70.0f);
}

/* Renders u's scene in mode at spp, with see_through on or off and the
 * random numbers of seed. Returns the image (malloc'ed) or NULL after a
 * FAIL line. */
static float *render(const setup *u, lvcl_mode mode, int spp, int see_through, unsigned seed)
{
    lvcl_scene scene;
    make_scene(u, &scene);
    lvcl_render_request req = harness_request(mode, SIZE, spp, u->cells, 300000);
    req.volume.subcells = u->subcells;
    req.volume.offset = u->offset;
    req.see_through = see_through;
    lvcl_session_config cfg = {.seed = seed, .max_depth = u->max_depth ? u->max_depth : 64, .fast_math = 1};
    char what[200];
    snprintf(what, sizeof what, "see-through, %s", u->name);
    return render_or_fail(&scene, &cfg, &req, what);
}

static double mean_of(const float *im)
{
    double sum = 0;
    for (size_t i = 0; i < (size_t)SIZE * SIZE * 3; i++) sum += im[i];
    return sum / (SIZE * SIZE * 3);
}

/* The RMS over BLOCK x BLOCK blocks of their mean's relative error against ref. */
static double block_error(const float *im, const float *ref)
{
    double sum = 0;
    int count = 0;
    for (int by = 0; by < SIZE; by += BLOCK)
        for (int bx = 0; bx < SIZE; bx += BLOCK) {
            double a = 0, b = 0;
            for (int y = by; y < by + BLOCK; y++)
                for (int x = bx; x < bx + BLOCK; x++)
                    for (int c = 0; c < 3; c++) {
                        a += im[((size_t)y * SIZE + x) * 3 + c];
                        b += ref[((size_t)y * SIZE + x) * 3 + c];
                    }
            if (b <= 0) continue;
            sum += (a / b - 1) * (a / b - 1);
            count++;
        }
    return count ? sqrt(sum / count) : 0;
}

static void check_lv(const setup *u, const float *ref, const float *on, const float *off)
{
    char name[240];
    double m_ref = mean_of(ref), m_on = mean_of(on), m_off = mean_of(off);
    double e_on = block_error(on, ref), e_off = block_error(off, ref);
    printf("   %s, lv: mean %.5f, off %.5f, reference %.5f; block error %.4f, off %.4f\n", u->name, m_on, m_off, m_ref,
           e_on, e_off);
    snprintf(name, sizeof name, "see-through, %s: lv image mean within 2%% of the reference's", u->name);
    CHECK(name, fabs(m_on / m_ref - 1) < 0.02, "lv %.5f (see-through off %.5f), reference %.5f", m_on, m_off, m_ref);
    snprintf(name, sizeof name, "see-through, %s: lv 8x8 blocks closer to the reference than with it off", u->name);
    CHECK(name, e_on < 0.75 * e_off, "RMS relative block error %.4f, off %.4f", e_on, e_off);
}

static void check_paths(const setup *u, const float *ref, const float *pt, const float *pt_off, const float *guided)
{
    char name[240];
    double m_ref = mean_of(ref), m_pt = mean_of(pt), m_guided = mean_of(guided);
    double e_pt = block_error(pt, ref), e_off = block_error(pt_off, ref);
    printf("   %s, paths: mean pt %.5f, guided %.5f, reference %.5f; pt block error %.4f, off %.4f\n", u->name, m_pt,
           m_guided, m_ref, e_pt, e_off);
    snprintf(name, sizeof name, "see-through, %s: pt image mean within 1%% of the reference's", u->name);
    CHECK(name, fabs(m_pt / m_ref - 1) < 0.01, "pt %.5f, reference %.5f", m_pt, m_ref);
    snprintf(name, sizeof name, "see-through, %s: guided image mean within 1%% of the reference's", u->name);
    CHECK(name, fabs(m_guided / m_ref - 1) < 0.01, "guided %.5f, reference %.5f", m_guided, m_ref);
    snprintf(name, sizeof name, "see-through, %s: pt 8x8 blocks closer to the reference than with it off", u->name);
    CHECK(name, e_pt < 0.75 * e_off, "RMS relative block error %.4f, off %.4f", e_pt, e_off);
}

static void test_setup(const setup *u)
{
    char name[240];
    float *ref = render(u, LVCL_MODE_PT, REFERENCE_SPP, 0, 7);
    float *lv = u->max_depth ? NULL : render(u, LVCL_MODE_LV, 32, 1, 7);
    float *lv_off = u->max_depth ? NULL : render(u, LVCL_MODE_LV, 32, 0, 7);
    float *pt = render(u, LVCL_MODE_PT, 256, 1, 11), *pt_off = render(u, LVCL_MODE_PT, 256, 0, 11);
    float *guided = u->roughness == 0 ? render(u, LVCL_MODE_GUIDED, 256, 1, 11) : NULL;
    if (ref && (u->max_depth || (lv && lv_off)) && pt && pt_off && u->roughness == 0 && guided) {
        /* lv's depth counts the particle's segments and the gather's
         * apart, so only a full depth compares with a path tracer. */
        if (!u->max_depth) check_lv(u, ref, lv, lv_off);
        check_paths(u, ref, pt, pt_off, guided);
    } else if (lv && lv_off && pt && pt_off && u->roughness > 0) {
        double d_lv = lvcl_relmse(lv, lv_off, (size_t)SIZE * SIZE * 3);
        double d_pt = lvcl_relmse(pt, pt_off, (size_t)SIZE * SIZE * 3);
        snprintf(name, sizeof name, "see-through, %s: rough glass is left to the volume and to paths", u->name);
        CHECK(name, d_lv == 0 && d_pt == 0, "relMSE between on and off: lv %.3g, pt %.3g", d_lv, d_pt);
    }
    free(ref);
    free(lv);
    free(lv_off);
    free(pt);
    free(pt_off);
    free(guided);
}

int main(int argc, char **argv)
{
    const setup setups[] = {
        {"2 cm slab", 0.02f, 1.5f, 0, 1, 0, 0, 16, 4},
        {"thin glass polygon, offset 0.37", 0, 1.5f, 0, 1, 0, 0.37f, 16, 4},
        {"15 cm slab, ior 1.5, offset 0.5, subcells 2", 0.15f, 1.5f, 0, 1, 0, 0.5f, 16, 2},
        {"3 cm slab, ior 2.2, tilted 20 degrees, 24 cells", 0.03f, 2.2f, 20, 1, 0, 0.25f, 24, 4},
        {"two 2 cm slabs, subcells 0", 0.02f, 1.5f, 0, 2, 0, 0, 16, 0},
        {"rough 2 cm slab", 0.02f, 1.5f, 0, 1, 0.5f, 0, 16, 4},
        {"2 cm slab with a mirror block, tilted 30 degrees", 0.02f, 1.5f, 30, 1, 0, 0.6f, 16, 4, 1},
        {"2 cm slab, glossy room", 0.02f, 1.5f, 0, 1, 0, 0, 16, 4, 0, 0.35f},
        /* The floor under both slabs: a light sample there may see the
         * lamp through 3 scatters, and the slabs take 4. */
        {"two 2 cm slabs, paths of at most 5 segments", 0.02f, 1.5f, 0, 2, 0, 0, 16, 4, 0, 0, 5},
    };
    /* argv[1] is the tests folder (tests/run.sh); a second argument picks
     * the set-ups whose names contain it. */
    int ran = 0;
    for (size_t i = 0; i < sizeof setups / sizeof *setups; i++)
        if (argc < 3 || strstr(setups[i].name, argv[2])) {
            test_setup(&setups[i]);
            ran++;
        }
    CHECK("see-through: some set-up ran", ran > 0, "no set-up's name contains '%s'", argc > 2 ? argv[2] : "");
    CHECK_EXIT();
}
