/* Degenerate triangles: zero-area (collinear, repeated vertices) and
 * non-finite ones are left out of the BVH, and nothing else is; a scene of
 * them mixed with good ones traces as brute force over the good ones; a
 * scene of only degenerate triangles fails with a message. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "traversal.h"

/* A point of a coarse grid (multiples of 1/8 up to 8): sums of such points
 * are exact in float, so collinear triples stay exactly collinear. */
static vec3 grid_point(rng *r)
{
    return v3(floor(range(r, -64, 64)) / 8, floor(range(r, -64, 64)) / 8, floor(range(r, -64, 64)) / 8);
}

/* One triangle lvcl_bvh_build must leave out, of kind `kind` (below
 * BAD_KINDS): collinear, repeated vertices, a NaN, +Inf or -Inf. */
#define BAD_KINDS 8
static void add_bad_triangle(rng *r, int kind, tri_list *l)
{
    vec3 a = random_in_box(r, -1, 1), b = random_in_box(r, -1, 1), c = random_in_box(r, -1, 1);
    switch (kind) {
    case 0: { /* collinear, middle vertex in any position */
        vec3 p = grid_point(r), d = mul(grid_point(r), 0.25);
        vec3 q[3] = {p, add(p, d), add(p, mul(d, 2))};
        int first = (int)(3 * uniform(r));
        add_tri(l, q[first], q[(first + 1) % 3], q[(first + 2) % 3]);
        return;
    }
    case 1:
        add_tri(l, a, a, b);
        return;
    case 2:
        add_tri(l, a, b, b);
        return;
    case 3:
        add_tri(l, a, b, a);
        return;
    case 4:
        add_tri(l, a, a, a);
        return;
    default: { /* a proper triangle with one coordinate NaN, +Inf or -Inf */
        static const float bad[3] = {NAN, INFINITY, -INFINITY};
        float f[9] = {(float)a.x, (float)a.y, (float)a.z, (float)b.x, (float)b.y,
                      (float)b.z, (float)c.x, (float)c.y, (float)c.z};
        f[(int)(9 * uniform(r))] = bad[kind - 5];
        add_tri_floats(l, f);
        return;
    }
    }
}

static void test_degenerate(void)
{
    rng r = {11};
    tri_list good = {0}, mixed = {0};
    make_soup(&r, 1000, 1, &good);
    /* Interleave a bad triangle of every kind among the good ones; remember
     * which mixed index each good triangle got. */
    int *good_to_mixed = malloc(good.count * sizeof(int));
    size_t bad_count = 0;
    for (size_t t = 0; t < good.count; t++) {
        while (uniform(&r) < 0.3) {
            add_bad_triangle(&r, (int)(bad_count % BAD_KINDS), &mixed);
            bad_count++;
        }
        good_to_mixed[t] = (int)mixed.count;
        add_tri_floats(&mixed, &good.v[9 * t]);
    }
    gpu_scene gm, gg;
    gpu_scene_make(&mixed, &gm);
    gpu_scene_make(&good, &gg);
    CHECK("degenerate: the BVH leaves out exactly the zero-area and non-finite triangles",
          gm.accel.skipped == bad_count && gm.accel.triangle_count == good.count,
          "skipped %zu of %zu bad, kept %zu of %zu good", gm.accel.skipped, bad_count, gm.accel.triangle_count,
          good.count);

    ray_list rays = {0};
    make_soup_rays(&r, 50000, &rays);
    float *bvh = trace(&gm, &rays), *brute = run_rays(&gg, "t_trace_brute_force", &rays, NULL);
    mismatches m = compare_answers(&rays, bvh, brute, good_to_mixed);
    CHECK("degenerate: tracing the mixed scene equals brute force over its good triangles", m.differ == 0,
          "%zu of %zu rays differ (%zu of them only by 1-2 ulps in t on the same triangle); first: %s", m.differ,
          rays.count, m.rounding, m.first);
    free(bvh);
    free(brute);

    tri_list only_bad = {0};
    for (int i = 0; i < 5 * BAD_KINDS; i++) add_bad_triangle(&r, i % BAD_KINDS, &only_bad);
    lvcl_scene s;
    harness_triangle_scene(only_bad.v, only_bad.count, &s);
    lvcl_bvh b;
    lvcl_status st = {0};
    lvcl_error e = lvcl_bvh_build(s.positions, s.indices, s.triangle_count, &b, &st);
    CHECK("degenerate: a scene of only degenerate triangles fails with LVCL_ERR_UNSUPPORTED",
          e == LVCL_ERR_UNSUPPORTED && st.code == LVCL_ERR_UNSUPPORTED && st.message[0] != 0,
          "error %d, status %d, message \"%s\"", (int)e, (int)st.code, st.message);
    lvcl_bvh_free(&b);
    lvcl_scene_free(&s);

    gpu_scene_free(&gm);
    gpu_scene_free(&gg);
    free(good_to_mixed);
    free(good.v);
    free(mixed.v);
    free(only_bad.v);
    free(rays.v);
}

int main(void)
{
    traversal_open();
    test_degenerate();
    traversal_close();
    CHECK_EXIT();
}
