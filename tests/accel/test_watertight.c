/* Traversal at the edges of floating point: closed meshes do not leak at
 * shared edges and vertices, from inside or outside, near the origin or far
 * from it; grazing and in-plane rays give the plane's distance or a clean
 * miss, never NaN or t <= 0. */
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "traversal.h"

/* ---- closed meshes ---- */

/* Grid coordinate i of n in [-1, 1], unevenly spaced so that grid lines
 * are not at round numbers. */
static double cube_coord(int i, int n)
{
    return -1 + 2 * pow((double)i / n, 1.3);
}

/* A point of the cube's grid, rotated and moved. One function of the grid
 * indices computes every vertex, so faces share edges and corners bitwise. */
static vec3 cube_point(const int ijk[3], int n, const vec3 rot[3], vec3 centre, double half)
{
    vec3 p = v3(cube_coord(ijk[0], n), cube_coord(ijk[1], n), cube_coord(ijk[2], n));
    return add(centre, mul(v3(dot(rot[0], p), dot(rot[1], p), dot(rot[2], p)), half));
}

/* A closed cube whose six faces are n x n grids of quads, turned by a
 * fixed rotation so that no face is axis-aligned. */
static void grid_cube(int n, vec3 centre, double half, tri_list *l)
{
    vec3 axis = normalized(v3(1, 2, 3));
    double c = cos(0.7), s = sin(0.7), t = 1 - c;
    vec3 rot[3] = {v3(t * axis.x * axis.x + c, t * axis.x * axis.y - s * axis.z, t * axis.x * axis.z + s * axis.y),
                   v3(t * axis.x * axis.y + s * axis.z, t * axis.y * axis.y + c, t * axis.y * axis.z - s * axis.x),
                   v3(t * axis.x * axis.z - s * axis.y, t * axis.y * axis.z + s * axis.x, t * axis.z * axis.z + c)};
    for (int a = 0; a < 3; a++)
        for (int side = 0; side <= n; side += n)
            for (int u = 0; u < n; u++)
                for (int v = 0; v < n; v++) {
                    int corner[4][3];
                    for (int q = 0; q < 4; q++) {
                        corner[q][a] = side;
                        corner[q][(a + 1) % 3] = u + (q == 1 || q == 2);
                        corner[q][(a + 2) % 3] = v + (q >= 2);
                    }
                    vec3 p[4];
                    for (int q = 0; q < 4; q++) p[q] = cube_point(corner[q], n, rot, centre, half);
                    add_tri(l, p[0], p[1], p[2]);
                    add_tri(l, p[0], p[2], p[3]);
                }
}

/* Aim points on a mesh: every triangle's corners, edge midpoints and a
 * random point on each edge (shared ones come up once per triangle). */
static size_t aim_points(rng *r, const tri_list *mesh, vec3 **out)
{
    size_t n = 0;
    *out = malloc(9 * mesh->count * sizeof(vec3));
    for (size_t t = 0; t < mesh->count; t++)
        for (int k = 0; k < 3; k++) {
            vec3 a = tri_vertex(mesh, t, k), b = tri_vertex(mesh, t, (k + 1) % 3);
            (*out)[n++] = a;
            (*out)[n++] = as_float(lerp(a, b, 0.5));
            (*out)[n++] = as_float(lerp(a, b, uniform(r)));
        }
    return n;
}

/* Rays from the centre and from random interior points (within
 * inner_radius) at every aim point, plus random directions. From the
 * centre of an origin-centred mesh the direction is the aim point itself,
 * so the ray passes exactly through each vertex. */
static void rays_from_inside(rng *r, const tri_list *mesh, vec3 centre, double inner_radius, ray_list *rays)
{
    vec3 *aims;
    size_t n = aim_points(r, mesh, &aims);
    for (int o = 0; o < 4; o++) {
        vec3 origin = as_float(o == 0 ? centre : add(centre, mul(random_unit(r), inner_radius * uniform(r))));
        for (size_t i = 0; i < n; i++) add_ray(rays, origin, sub(aims[i], origin), NO_LIMIT);
        for (int i = 0; i < 2000; i++) add_ray(rays, origin, random_unit(r), NO_LIMIT);
    }
    free(aims);
}

/* Rays from outside a convex mesh at its aim points, arriving within about
 * 12 degrees of the direction away from the centre: each enters the mesh at
 * its aim point, at t = 1. */
static void rays_from_outside(rng *r, const tri_list *mesh, vec3 centre, double size, ray_list *rays)
{
    vec3 *aims;
    size_t n = aim_points(r, mesh, &aims);
    for (size_t i = 0; i < n; i++) {
        vec3 away = normalized(add(normalized(sub(aims[i], centre)), mul(random_unit(r), 0.2)));
        vec3 origin = as_float(add(aims[i], mul(away, size * range(r, 0.5, 3))));
        add_ray(rays, origin, sub(aims[i], origin), NO_LIMIT);
    }
    free(aims);
}

/* Misses, or hits not at t = 1 when `at_one` (rays aimed from outside). */
static size_t count_leaks(const ray_list *rays, const float *res, int at_one, char *why, size_t why_size)
{
    size_t bad = 0;
    for (size_t i = 0; i < rays->count; i++) {
        float t = res[4 * i];
        int ok = res[4 * i + 1] >= 0 && t > 0 && (!at_one || fabsf(t - 1) < 1e-3f);
        if (ok) continue;
        const float *q = &rays->v[8 * i];
        if (bad++ == 0)
            snprintf(why, why_size, "ray %zu (origin %.9g %.9g %.9g, dir %.9g %.9g %.9g): t %.9g prim %g", i, q[0],
                     q[1], q[2], q[4], q[5], q[6], t, res[4 * i + 1]);
    }
    return bad;
}

static void check_closed_mesh(const char *what, const tri_list *mesh, vec3 centre, double size, uint64_t seed)
{
    rng r = {seed};
    ray_list inside = {0}, outside = {0};
    rays_from_inside(&r, mesh, centre, 0.5 * size, &inside);
    rays_from_outside(&r, mesh, centre, size, &outside);
    gpu_scene g;
    gpu_scene_make(mesh, &g);
    float *in = trace(&g, &inside), *out = trace(&g, &outside);
    char why[512] = "", name[160];
    size_t bad = count_leaks(&inside, in, 0, why, sizeof why);
    snprintf(name, sizeof name, "watertight: %s, %zu rays from inside at vertices, edges, anywhere", what,
             inside.count);
    CHECK(name, bad == 0, "%zu rays escaped; first: %s", bad, why);
    bad = count_leaks(&outside, out, 1, why, sizeof why);
    snprintf(name, sizeof name, "watertight: %s, %zu rays from outside at vertices and edges", what, outside.count);
    CHECK(name, bad == 0, "%zu rays missed or hit away from their aim point; first: %s", bad, why);
    free(in);
    free(out);
    gpu_scene_free(&g);
    free(inside.v);
    free(outside.v);
}

static void test_watertight(void)
{
    static const struct {
        const char *name;
        int cube; /* else an icosphere */
        int detail;
        double x, y, z, size;
    } meshes[] = {
        {"icosphere (5120 triangles)", 0, 4, 0, 0, 0, 1},
        {"rotated 16x16 grid cube", 1, 16, 0, 0, 0, 1},
        {"icosphere at (1000.3, -1200.7, 1500.1)", 0, 3, 1000.3, -1200.7, 1500.1, 2},
        {"rotated 8x8 grid cube at (-3000.5, 2500.25, 1000.1)", 1, 8, -3000.5, 2500.25, 1000.1, 3},
    };
    for (size_t m = 0; m < sizeof meshes / sizeof meshes[0]; m++) {
        tri_list mesh = {0};
        vec3 centre = v3(meshes[m].x, meshes[m].y, meshes[m].z);
        if (meshes[m].cube) grid_cube(meshes[m].detail, centre, meshes[m].size, &mesh);
        else icosphere(meshes[m].detail, centre, meshes[m].size, &mesh);
        check_closed_mesh(meshes[m].name, &mesh, centre, meshes[m].size, 100 + m);
        free(mesh.v);
    }
}

/* ---- grazing rays ---- */

/* The quad [-100,100]^2 in the plane z = 0, split along the diagonal y = x. */
static void plane_quad(tri_list *l)
{
    vec3 p0 = v3(-100, -100, 0), p1 = v3(100, -100, 0), p2 = v3(100, 100, 0), p3 = v3(-100, 100, 0);
    add_tri(l, p0, p1, p2);
    add_tri(l, p0, p2, p3);
}

/* Largest distance from o to a corner of the quad. */
static double quad_reach(const float *o)
{
    double x = 100 + fabs(o[0]), y = 100 + fabs(o[1]);
    return sqrt(x * x + y * y + (double)o[2] * o[2]);
}

/* How far a hit on the plane z = 0 is from the exact intersection of the
 * ray as stored (t = -oz / dz, in double from the floats), in units of
 * eps (t + R / |d|); infinite for a miss. Error model: the kernel subtracts
 * the origin from the vertices and shears; the plane's coordinate (0 - oz)
 * is exact, the other roundings are of quantities up to R = |vertex -
 * origin|, so t is off by a few eps R / |d| in absolute terms plus a few
 * eps relative. The checks allow 16 of these units. */
static double grazing_error(const float *q, const float *res)
{
    if (res[1] < 0) return INFINITY;
    double d = sqrt((double)q[4] * q[4] + (double)q[5] * q[5] + (double)q[6] * q[6]);
    double exact = -(double)q[2] / q[6];
    return fabs(res[0] - exact) / (FLT_EPSILON * (exact + quad_reach(q) / d));
}

/* A ray that may miss but must not give NaN or t <= 0: t is tmax on a miss. */
static int sane(const float *q, const float *res)
{
    float t = res[0];
    return !isnan(t) && t > 0 && (res[1] >= 0 ? t < q[3] : bits(t) == bits(q[3]));
}

static void describe(char *why, size_t size, size_t i, const float *q, const float *res)
{
    snprintf(why, size, "ray %zu (origin %.9g %.9g %.9g, dir %.9g %.9g %.9g): t %.9g prim %g, plane at t %.9g", i, q[0],
             q[1], q[2], q[4], q[5], q[6], res[0], res[1], -(double)q[2] / q[6]);
}

/* Unit direction at `angle` below the horizontal, heading `heading`. */
static vec3 grazing_dir(double angle, double heading)
{
    return v3(cos(angle) * cos(heading), cos(angle) * sin(heading), -sin(angle));
}

static void test_grazing(void)
{
    rng r = {7};
    tri_list quad = {0};
    plane_quad(&quad);
    gpu_scene g;
    gpu_scene_make(&quad, &g);

    /* From above at 1e-3..1e-6 rad, meeting the plane 5 to 60 units away
     * (inside the quad); heights of 1e-7 and up must hit. */
    ray_list above = {0}, low = {0}, in_plane = {0}, diagonal = {0};
    for (int i = 0; i < 20000; i++) {
        double angle = log_range(&r, 1e-6, 1e-3), heading = range(&r, 0, 2 * PI);
        vec3 d = grazing_dir(angle, heading);
        double travel = range(&r, 5, 60);
        vec3 o = v3(range(&r, -30, 30) - travel * d.x, range(&r, -30, 30) - travel * d.y, travel * tan(angle));
        if (o.z < 1e-7) continue;
        add_ray(&above, o, d, NO_LIMIT);
    }
    /* Starting within 1e-7 of the plane (or on it), down or level. */
    for (int i = 0; i < 5000; i++) {
        double angle = uniform(&r) < 0.2 ? 0 : log_range(&r, 1e-7, 1e-1);
        double height = uniform(&r) < 0.2 ? 0 : log_range(&r, 1e-30, 1e-7);
        add_ray(&low, v3(range(&r, -120, 120), range(&r, -120, 120), height), grazing_dir(angle, range(&r, 0, 7)),
                NO_LIMIT);
    }
    /* Exactly in the plane: on the quad, beside it towards it, along an axis. */
    for (int i = 0; i < 5000; i++) {
        vec3 o = i % 2 ? v3(range(&r, -99, 99), range(&r, -99, 99), 0) : v3(range(&r, 150, 300), range(&r, -50, 50), 0);
        vec3 d = i % 5 == 0 ? v3(-1, 0, 0) : grazing_dir(0, range(&r, 0.8 * PI, 1.2 * PI));
        add_ray(&in_plane, o, d, NO_LIMIT);
    }
    /* Along the shared diagonal: from above it, in its vertical plane (equal
     * x and y), down to the edge; and lying on the edge itself. */
    for (int i = 0; i < 2000; i++) {
        double angle = log_range(&r, 1e-6, 1e-1), travel = range(&r, 5, 60), x = range(&r, -30, 30);
        vec3 d = v3(cos(angle) * sqrt(0.5), cos(angle) * sqrt(0.5), -sin(angle));
        if (i % 2) d.x = -d.x, d.y = -d.y;
        double h = travel * sin(angle);
        if (h >= 1e-7) add_ray(&diagonal, v3(x - travel * d.x, x - travel * d.x, h), d, NO_LIMIT);
    }
    ray_list on_edge = {0};
    for (int i = 0; i < 200; i++) {
        double x = range(&r, -150, 150), sign = i % 2 ? 1 : -1;
        add_ray(&on_edge, v3(x, x, 0), v3(sign, sign, 0), NO_LIMIT);
    }

    char why[512] = "";
    float *res = trace(&g, &above);
    size_t bad = 0;
    double worst = 0;
    for (size_t i = 0; i < above.count; i++) {
        double err = grazing_error(&above.v[8 * i], &res[4 * i]);
        worst = fmax(worst, err);
        if (err > 16 && bad++ == 0) describe(why, sizeof why, i, &above.v[8 * i], &res[4 * i]);
    }
    CHECK("grazing: rays at 1e-3..1e-6 rad hit the plane at its distance", bad == 0,
          "%zu of %zu rays missed or were off by more than 16 eps (t + R/|d|), worst %.3g; first: %s", bad, above.count,
          worst, why);
    free(res);

    const struct {
        const char *name;
        ray_list *rays;
    } sanity[] = {{"grazing: rays starting below 1e-7 give no NaN and no t <= 0", &low},
                  {"grazing: rays in the plane give no NaN and no t <= 0", &in_plane},
                  {"grazing: rays lying on the shared diagonal give no NaN and no t <= 0", &on_edge}};
    for (size_t s = 0; s < 3; s++) {
        res = trace(&g, sanity[s].rays);
        bad = 0;
        for (size_t i = 0; i < sanity[s].rays->count; i++)
            if (!sane(&sanity[s].rays->v[8 * i], &res[4 * i]) && bad++ == 0)
                describe(why, sizeof why, i, &sanity[s].rays->v[8 * i], &res[4 * i]);
        CHECK(sanity[s].name, bad == 0, "%zu of %zu rays; first: %s", bad, sanity[s].rays->count, why);
        free(res);
    }

    res = trace(&g, &diagonal);
    bad = 0;
    for (size_t i = 0; i < diagonal.count; i++)
        if (grazing_error(&diagonal.v[8 * i], &res[4 * i]) > 16 && bad++ == 0)
            describe(why, sizeof why, i, &diagonal.v[8 * i], &res[4 * i]);
    CHECK("grazing: rays down onto the shared diagonal hit it at the plane's distance", bad == 0,
          "%zu of %zu rays missed or were off; first: %s", bad, diagonal.count, why);
    free(res);

    gpu_scene_free(&g);
    free(quad.v);
    free(above.v);
    free(low.v);
    free(in_plane.v);
    free(diagonal.v);
    free(on_edge.v);
}

int main(void)
{
    traversal_open();
    test_watertight();
    test_grazing();
    traversal_close();
    CHECK_EXIT();
}
