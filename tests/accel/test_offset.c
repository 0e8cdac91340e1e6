/* The self-intersection offset: rays re-shot from lv_offset_origin never
 * hit their own triangle, at any scene scale and far from the origin, and
 * step off the surface by a small fraction of the scene; on a closed needle
 * of sliver faces, rays skipping the face they leave go where they should;
 * rays that leave a hit near the corner of an acute wedge (lv_leave_point)
 * start inside it. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "traversal.h"

/* The point of triangle t of l at barycentric coordinates (b1, b2). */
static vec3 tri_point(const tri_list *l, size_t t, double b1, double b2)
{
    vec3 v0 = tri_vertex(l, t, 0);
    return add(v0, add(mul(sub(tri_vertex(l, t, 1), v0), b1), mul(sub(tri_vertex(l, t, 2), v0), b2)));
}

/* A random point on a random triangle of l. */
static vec3 point_on(rng *r, const tri_list *l)
{
    size_t t = (size_t)(uniform(r) * l->count);
    double b1 = uniform(r), b2 = uniform(r);
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    return tri_point(l, t, b1, b2);
}

/* A re-shoot record for t_offset_rays: a direction about the normal, a third
 * of them grazing (down to 1e-4 rad), and w = +mode (back to the side the
 * ray came from) or -mode (through) at even odds; mode 2 also skips the
 * triangle left. */
static void random_reshoot(rng *r, float mode, float e[4])
{
    double z = uniform(r) < 0.33 ? log_range(r, 1e-4, 1e-2) : range(r, 1e-4, 1);
    double s = sqrt(1 - z * z), phi = range(r, 0, 2 * PI);
    e[0] = (float)(s * cos(phi)), e[1] = (float)(s * sin(phi)), e[2] = (float)z;
    e[3] = uniform(r) < 0.5 ? mode : -mode;
}

/* Up to `cap` rays, each with its re-shoot record. */
typedef struct {
    ray_list rays;
    float *reshoot; /* 4 floats per ray */
    size_t cap;
} reshot_rays;

static reshot_rays reshot_rays_make(size_t cap)
{
    reshot_rays l = {.reshoot = malloc(4 * cap * sizeof(float)), .cap = cap};
    if (!l.reshoot) {
        printf("FAIL offset: out of memory\n");
        exit(1);
    }
    return l;
}

/* A ray without a limit, and a random re-shoot record of `mode` for it. */
static void add_reshot_ray(rng *r, vec3 origin, vec3 dir, float mode, reshot_rays *l)
{
    if (l->rays.count == l->cap) {
        printf("FAIL offset: more than %zu re-shot rays\n", l->cap);
        exit(1);
    }
    random_reshoot(r, mode, &l->reshoot[4 * l->rays.count]);
    add_ray(&l->rays, origin, dir, NO_LIMIT);
}

static void reshot_rays_free(reshot_rays *l)
{
    free(l->rays.v);
    free(l->reshoot);
}

/* Shoots rays at `unit` (a scene in about [-1,1]^3) scaled by `scale` and
 * moved to `centre`, re-shoots every hit with t_offset_rays and checks that
 * no re-shot ray hits its own triangle and that the step off the surface
 * stays small. */
static void check_offset(const char *what, const tri_list *unit, double scale, vec3 centre, uint64_t seed)
{
    rng r = {seed};
    tri_list scene = {0};
    for (size_t t = 0; t < unit->count; t++)
        add_tri(&scene, add(centre, mul(tri_vertex(unit, t, 0), scale)),
                add(centre, mul(tri_vertex(unit, t, 1), scale)), add(centre, mul(tri_vertex(unit, t, 2), scale)));
    gpu_scene g;
    gpu_scene_make(&scene, &g);

    /* Rays from outside and inside at points on the triangles; each hit is
     * re-shot half the time back to the side it came from, half the time
     * through, a third of those at grazing angles down to 1e-4 rad. */
    size_t n = 40000;
    reshot_rays l = reshot_rays_make(n);
    for (size_t i = 0; i < n; i++) {
        vec3 o = uniform(&r) < 0.5 ? mul(random_unit(&r), 4) : random_in_box(&r, -1, 1);
        vec3 d = sub(point_on(&r, unit), o);
        add_reshot_ray(&r, add(centre, mul(o, scale)), d, 1.0f, &l);
    }
    float *res = run_rays(&g, "t_offset_rays", &l.rays, l.reshoot);

    /* The offset is 2^-18 of the point's coordinates along the normal plus
     * 2^-20 of the scene's size: well under 1e-4 of the scene's reach. */
    double reach = fmax(g.packed.info.scene_scale, fmax(fabs(centre.x), fmax(fabs(centre.y), fabs(centre.z))) + scale);
    size_t hits = 0, own = 0, far = 0, first_own = 0;
    double largest_step = 0;
    for (size_t i = 0; i < n; i++) {
        const float *o = &res[4 * i];
        if (o[0] < 0) continue;
        hits++;
        if (o[1] == o[0] && own++ == 0) first_own = i;
        largest_step = fmax(largest_step, o[3]);
        far += o[3] > 1e-4 * reach;
    }
    char name[160];
    snprintf(name, sizeof name, "offset: %s, %zu re-shot rays never hit their own triangle", what, hits);
    const float *q = &l.rays.v[8 * first_own], *e = &l.reshoot[4 * first_own], *o = &res[4 * first_own];
    CHECK(name, own == 0 && hits > n / 2,
          "%zu of %zu hit their own triangle (scene_scale %g); first: ray %zu origin %.9g %.9g %.9g dir %.9g %.9g "
          "%.9g, prim %g, re-shot %s at local direction %g %g %g, own hit at t %.9g, offset %.3g",
          own, hits, g.packed.info.scene_scale, first_own, q[0], q[1], q[2], q[4], q[5], q[6], o[0],
          e[3] > 0 ? "back" : "through", e[0], e[1], e[2], o[2], o[3]);
    snprintf(name, sizeof name, "offset: %s, the step off the surface is under 1e-4 of the scene's reach", what);
    CHECK(name, far == 0, "%zu steps too long, largest %.3g for reach %.3g", far, largest_step, reach);

    free(res);
    reshot_rays_free(&l);
    gpu_scene_free(&g);
    free(scene.v);
}

/* Long thin triangles: the distance at which a ray leaving one seems to
 * meet it again comes from edge functions only good to about eps R^2 / area,
 * so the offset alone cannot keep rays off their own sliver; the renderer's
 * rays skip the triangle they leave. On a closed convex needle of sliver
 * faces, a ray re-shot outward must then meet nothing, and one re-shot
 * inward must meet another face. Rays aim at least 5% of a face's extent
 * away from its edges: nearer the tips the needle is thinner than any
 * offset, and leaving it "outward" is not well defined there. */
static void check_needle(void)
{
    rng r = {25};
    tri_list needle = {0};
    const double w = 1e-3;
    vec3 a = v3(-1, 0, 0), b = v3(1, 0, 0), c = v3(0, w, 0), d = v3(0, w / 2, w);
    add_tri(&needle, a, b, c);
    add_tri(&needle, a, d, b);
    add_tri(&needle, b, d, c);
    add_tri(&needle, a, c, d);
    size_t n = 40000;
    reshot_rays l = reshot_rays_make(n);
    for (size_t i = 0; i < n; i++) {
        vec3 o = mul(random_unit(&r), 3);
        size_t t = (size_t)(uniform(&r) * needle.count);
        double b1, b2;
        do {
            b1 = uniform(&r), b2 = uniform(&r);
        } while (b1 < 0.05 || b2 < 0.05 || b1 + b2 > 0.95);
        add_reshot_ray(&r, o, sub(tri_point(&needle, t, b1, b2), o), 2.0f, &l);
    }
    gpu_scene g;
    gpu_scene_make(&needle, &g);
    float *res = run_rays(&g, "t_offset_rays", &l.rays, l.reshoot);
    size_t hits = 0, out_hit = 0, in_missed = 0;
    for (size_t i = 0; i < n; i++) {
        const float *o = &res[4 * i];
        if (o[0] < 0) continue;
        hits++;
        if (l.reshoot[4 * i + 3] > 0) out_hit += o[1] >= 0;
        else in_missed += o[1] < 0 || o[1] == o[0];
    }
    /* Known limit (docs/design.md): a few grazing rays inside a body 1e-3 of
     * its length thin still go astray, about 1 in 1,000 when measured; the
     * bound catches any regression of the offset or of the skip. */
    printf("  sliver needle: %zu of %zu outward rays hit it again, %zu inward rays found no other face\n", out_hit,
           hits, in_missed);
    CHECK("offset: sliver needle, rays re-shot outward meet nothing (all but 1 in 5,000)",
          out_hit * 5000 <= hits && hits > n / 4, "%zu of %zu outward rays hit the needle again", out_hit, hits);
    CHECK("offset: sliver needle, rays re-shot inward meet another face (all but 1 in 500)",
          in_missed * 500 <= hits && hits > n / 4, "%zu of %zu inward rays found no other face", in_missed, hits);
    free(res);
    reshot_rays_free(&l);
    gpu_scene_free(&g);
    free(needle.v);
}

/* Two faces meeting at a corner line at `angle` degrees (A in its plane
 * z = 0, B turned up from it about the y axis; both 2 x 2 squares), the
 * whole turned and moved. Rays from inside the wedge at 10 degrees or more
 * from both faces hit one face within four offsets of the corner line, so
 * that an offset along its normal alone would leave them behind the other
 * face where the wedge is acute; each hit is re-shot from lv_leave_point
 * towards the other face (at 6 degrees or more from both), which it must
 * then hit: it starts inside the wedge. Returns how many missed. */
static size_t check_wedge(double angle, double scale, vec3 centre, uint64_t seed, size_t *hits_out)
{
    rng r = {seed};
    double th = angle * PI / 180;
    /* A frame turned at random: the faces face no axis. */
    vec3 ex = random_unit(&r), ey = normalized(cross(ex, random_unit(&r))), ez = cross(ex, ey);
#define WEDGE_AT(x, y, z) add(centre, mul(add(add(mul(ex, x), mul(ey, y)), mul(ez, z)), scale))
    vec3 ub = v3(cos(th), 0, sin(th));
    tri_list scene = {0};
    add_tri(&scene, WEDGE_AT(-2, -1, 0), WEDGE_AT(2, -1, 0), WEDGE_AT(2, 1, 0));
    add_tri(&scene, WEDGE_AT(-2, -1, 0), WEDGE_AT(2, 1, 0), WEDGE_AT(-2, 1, 0));
    add_tri(&scene, WEDGE_AT(0, -1, 0), WEDGE_AT(2 * ub.x, -1, 2 * ub.z), WEDGE_AT(2 * ub.x, 1, 2 * ub.z));
    add_tri(&scene, WEDGE_AT(0, -1, 0), WEDGE_AT(2 * ub.x, 1, 2 * ub.z), WEDGE_AT(0, 1, 0));
    gpu_scene g;
    gpu_scene_make(&scene, &g);

    /* Local normals into the wedge: A's is +z, B's (sin, 0, -cos). */
    vec3 na = v3(0, 0, 1), nb = v3(sin(th), 0, -cos(th));
    size_t n = 4000;
    reshot_rays l = reshot_rays_make(n);
    int *on_b = malloc(n * sizeof *on_b);
    for (size_t i = 0; i < n; i++) {
        int b = uniform(&r) < 0.5;
        /* The target: on face A (or B) at distance d from the corner line. */
        vec3 along = b ? ub : v3(1, 0, 0);
        double y = range(&r, -0.5, 0.5);
        vec3 p = WEDGE_AT(0, y, 0), nl = b ? nb : na;
        vec3 nw = add(add(mul(ex, nl.x), mul(ey, nl.y)), mul(ez, nl.z));
        /* The offset's length there (lv_offset_step). */
        double eps =
            0x1p-18 * (fabs(nw.x * p.x) + fabs(nw.y * p.y) + fabs(nw.z * p.z)) + 0x1p-20 * g.packed.info.scene_scale;
        double d = range(&r, 0, 4) * eps / scale;
        vec3 target = add(mul(along, d), v3(0, y, 0));
        /* The ray's origin: half a unit back, at 10 degrees or more from both faces and tilted along y. */
        double a = range(&r, 10, angle - 10) * PI / 180, tilt = range(&r, -30, 30) * PI / 180;
        vec3 back = v3(cos(a) * cos(tilt), sin(tilt), sin(a) * cos(tilt));
        vec3 o = add(target, mul(back, 0.5));
        /* The re-shoot: towards the other face, 6 degrees or more from both. */
        vec3 nh = b ? nb : na, no = b ? na : nb, e;
        do e = random_unit(&r);
        while (dot(e, nh) < 0.1 || dot(e, no) > -0.1);
        vec3 ew = add(add(mul(ex, e.x), mul(ey, e.y)), mul(ez, e.z));
        add_ray(&l.rays, WEDGE_AT(o.x, o.y, o.z), sub(WEDGE_AT(target.x, target.y, target.z), WEDGE_AT(o.x, o.y, o.z)),
                NO_LIMIT);
        float *rec = &l.reshoot[4 * l.rays.count - 4];
        rec[0] = (float)ew.x, rec[1] = (float)ew.y, rec[2] = (float)ew.z, rec[3] = 3.0f;
        on_b[i] = b;
    }
#undef WEDGE_AT
    float *res = run_rays(&g, "t_offset_rays", &l.rays, l.reshoot);
    size_t hits = 0, missed = 0;
    for (size_t i = 0; i < n; i++) {
        const float *o = &res[4 * i];
        /* A ray that met the other face first (it passed the corner
         * within a rounding error) is not counted. */
        if (o[0] < 0 || (o[0] >= 2) != on_b[i]) continue;
        hits++;
        int other = o[1] >= 0 && ((o[1] >= 2) != on_b[i]);
        missed += !other;
    }
    *hits_out = hits;
    free(on_b);
    free(res);
    reshot_rays_free(&l);
    gpu_scene_free(&g);
    free(scene.v);
    return missed;
}

static void test_wedges(void)
{
    const double angles[] = {30, 45, 60, 80, 100, 135};
    const double scales[] = {1e-3, 1, 1e3};
    uint64_t seed = 40;
    for (size_t i = 0; i < sizeof angles / sizeof *angles; i++)
        for (size_t k = 0; k < sizeof scales / sizeof *scales; k++)
            for (int far = 0; far < 2; far++) {
                vec3 centre = far ? mul(v3(1000, -700, 300), scales[k]) : v3(0, 0, 0);
                size_t hits, missed = check_wedge(angles[i], scales[k], centre, seed++, &hits);
                char name[160];
                snprintf(name, sizeof name,
                         "offset: rays leaving a hit near the corner of a %g-degree wedge (scale %g%s) start inside it",
                         angles[i], scales[k], far ? ", far from the origin" : "");
                CHECK(name, missed == 0 && hits > 3900, "%zu of %zu re-shot rays missed the other face", missed, hits);
            }
}

static void test_offset(void)
{
    /* A closed sphere and a soup through it, at three scales and far from
     * the origin, where the offset is counted in ulps. */
    rng r = {20};
    tri_list unit = {0}, slanted = {0};
    icosphere(3, v3(0, 0, 0), 1, &unit);
    make_soup(&r, unit.count + 3000, 0, &unit);
    check_offset("sphere and soup at scale 1e-3", &unit, 1e-3, v3(0, 0, 0), 21);
    check_offset("sphere and soup at scale 1", &unit, 1, v3(0, 0, 0), 22);
    check_offset("sphere and soup at scale 1e3", &unit, 1e3, v3(0, 0, 0), 23);
    check_offset("sphere and soup at scale 1, at (1000, -700, 300)", &unit, 1, v3(1000, -700, 300), 24);
    check_needle();
    /* One coordinate much larger than the others: a triangle whose normal
     * leans 0.003 towards x, 5 cm wide, 10^4 from the origin along x. Its
     * hit points are off by ulps of 10^4 in x, which moves them 0.003 of
     * that off the plane; the step must cover it. */
    add_tri(&slanted, v3(-1, -0.003, -1), v3(1, 0.003, -1), v3(0, 0, 1));
    check_offset("slanted triangle, 5e-2 wide, at (1e4, 0, 0)", &slanted, 2.5e-2, v3(1e4, 0, 0), 26);
    free(unit.v);
    free(slanted.v);
}

int main(void)
{
    traversal_open();
    test_offset();
    test_wedges();
    traversal_close();
    CHECK_EXIT();
}
