#include "traversal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static lvcl_device dev;
static lvcl_program prog;

/* ---- triangle and ray lists ---- */

static void *grow(void *p, size_t *cap, size_t need, size_t item_bytes)
{
    if (need <= *cap) return p;
    *cap = need > 2 * *cap ? need : 2 * *cap;
    p = realloc(p, *cap * item_bytes);
    if (!p) {
        printf("FAIL traversal support: out of memory\n");
        exit(1);
    }
    return p;
}

void add_tri_floats(tri_list *l, const float f[9])
{
    l->v = grow(l->v, &l->cap, l->count + 1, 9 * sizeof(float));
    memcpy(&l->v[9 * l->count++], f, 9 * sizeof(float));
}

void add_tri(tri_list *l, vec3 a, vec3 b, vec3 c)
{
    float f[9] = {(float)a.x, (float)a.y, (float)a.z, (float)b.x, (float)b.y,
                  (float)b.z, (float)c.x, (float)c.y, (float)c.z};
    add_tri_floats(l, f);
}

vec3 tri_vertex(const tri_list *l, size_t t, int k)
{
    const float *f = &l->v[9 * t + 3 * k];
    return v3(f[0], f[1], f[2]);
}

void add_ray(ray_list *l, vec3 origin, vec3 dir, float tmax)
{
    l->v = grow(l->v, &l->cap, l->count + 1, 8 * sizeof(float));
    float *q = &l->v[8 * l->count++];
    q[0] = (float)origin.x, q[1] = (float)origin.y, q[2] = (float)origin.z, q[3] = tmax;
    q[4] = (float)dir.x, q[5] = (float)dir.y, q[6] = (float)dir.z, q[7] = 0.0f;
}

/* ---- the test device and scenes on it ---- */

void traversal_open(void)
{
    harness_open(NULL, &dev, &prog);
}

void traversal_close(void)
{
    harness_close(&dev, &prog);
}

const lvcl_device *traversal_device(void)
{
    return &dev;
}

lvcl_error gpu_scene_prepare(const tri_list *l, const lvcl_device *on, gpu_scene *g, lvcl_status *st)
{
    harness_triangle_scene(l->v, l->count, &g->scene);
    memset(&g->accel, 0, sizeof g->accel);
    memset(&g->packed, 0, sizeof g->packed);
    memset(&g->ds, 0, sizeof g->ds);
    lvcl_error e = lvcl_accel_build(&g->scene, &g->accel, st);
    if (!e) e = lvcl_pack_scene(&g->scene, &g->accel, 0, 8, &g->packed, st);
    if (!e) e = lvcl_device_scene_upload(on, &g->scene, &g->packed, &g->ds, st);
    return e;
}

void gpu_scene_make(const tri_list *l, gpu_scene *g)
{
    lvcl_status st = {0};
    if (gpu_scene_prepare(l, &dev, g, &st)) {
        printf("FAIL traversal: preparing a scene of %zu triangles: %s\n", l->count, st.message);
        exit(1);
    }
}

void gpu_scene_free(gpu_scene *g)
{
    lvcl_device_scene_release(&g->ds);
    lvcl_packed_scene_free(&g->packed);
    lvcl_accel_free(&g->accel);
    lvcl_scene_free(&g->scene);
}

float *run_rays(const gpu_scene *g, const char *kernel_name, const ray_list *rays, const float *reshoot4)
{
    lvcl_status st = {0};
    cl_kernel k = harness_kernel(&prog, kernel_name);
    size_t n = rays->count;
    float *results = malloc(4 * n * sizeof(float));
    if (!results) {
        printf("FAIL traversal: out of memory for %zu results\n", n);
        exit(1);
    }
    cl_mem rbuf = harness_buffer(&dev, rays->v, 8 * n * sizeof(float));
    cl_mem obuf = harness_buffer(&dev, NULL, 4 * n * sizeof(float));
    cl_mem ebuf = NULL;
    lvcl_error e;
    if (reshoot4) {
        ebuf = harness_buffer(&dev, reshoot4, 4 * n * sizeof(float));
        t_offset_rays_args a = {
            .scene = &g->ds.buffers, .rays = rbuf, .count = (cl_uint)n, .reshoot = ebuf, .results = obuf};
        e = lvcl_bind_t_offset_rays(k, &a, &st);
    } else {
        t_trace_args a = {.scene = &g->ds.buffers, .rays = rbuf, .count = (cl_uint)n, .results = obuf};
        e = lvcl_bind_t_trace(k, &a, &st);
    }
    harness_ok(e, &st, kernel_name);
    harness_run(&dev, k, n);
    harness_read(&dev, obuf, 4 * n * sizeof(float), results);
    clReleaseMemObject(rbuf);
    if (ebuf) clReleaseMemObject(ebuf);
    clReleaseMemObject(obuf);
    clReleaseKernel(k);
    return results;
}

float *trace(const gpu_scene *g, const ray_list *rays)
{
    return run_rays(g, "t_trace", rays, NULL);
}

uint32_t bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* ---- shared scenes and rays ---- */

static void add_random_triangle(rng *r, tri_list *l, vec3 centre, double size)
{
    add_tri(l, add(centre, mul(random_unit(r), size * range(r, 0.3, 1))),
            add(centre, mul(random_unit(r), size * range(r, 0.3, 1))),
            add(centre, mul(random_unit(r), size * range(r, 0.3, 1))));
}

/* Long and thin: a long edge and a third vertex very close to it. */
static void add_sliver(rng *r, tri_list *l)
{
    vec3 a = random_in_box(r, -1, 1), u = random_unit(r);
    vec3 b = add(a, mul(u, range(r, 0.5, 2)));
    vec3 side = normalized(cross(u, random_unit(r)));
    add_tri(l, a, b, add(lerp(a, b, uniform(r)), mul(side, log_range(r, 1e-5, 1e-3))));
}

/* A bumpy k x k grid whose triangles share vertices bitwise. */
static void add_patch(rng *r, tri_list *l)
{
    enum { K = 4 };
    vec3 o = random_in_box(r, -1, 1), e1 = random_unit(r);
    vec3 e2 = normalized(cross(e1, random_unit(r))), n = cross(e1, e2);
    double h = log_range(r, 0.005, 0.1);
    vec3 g[K + 1][K + 1];
    for (int i = 0; i <= K; i++)
        for (int j = 0; j <= K; j++)
            g[i][j] = add(o, add(mul(e1, i * h), add(mul(e2, j * h), mul(n, range(r, -0.3, 0.3) * h))));
    for (int i = 0; i < K; i++)
        for (int j = 0; j < K; j++) {
            add_tri(l, g[i][j], g[i + 1][j], g[i + 1][j + 1]);
            add_tri(l, g[i][j], g[i + 1][j + 1], g[i][j + 1]);
        }
}

/* In a plane x, y or z = const, so its bounding box is flat. */
static void add_axis_aligned(rng *r, tri_list *l)
{
    int axis = (int)(3 * uniform(r));
    vec3 c = random_in_box(r, -1, 1), p[3];
    double size = log_range(r, 0.02, 0.3);
    for (int k = 0; k < 3; k++) {
        p[k] = add(c, mul(random_in_box(r, -1, 1), size));
        *component(&p[k], axis) = *component(&c, axis);
    }
    add_tri(l, p[0], p[1], p[2]);
}

void make_soup(rng *r, size_t n, int slivers, tri_list *l)
{
    vec3 clusters[8];
    for (int i = 0; i < 8; i++) clusters[i] = random_in_box(r, -0.9, 0.9);
    while (l->count < n) {
        double kind = uniform(r);
        if (kind < 0.30) add_random_triangle(r, l, random_in_box(r, -1, 1), log_range(r, 1e-3, 0.1));
        else if (kind < 0.38) add_random_triangle(r, l, random_in_box(r, -1, 1), range(r, 0.3, 1.5));
        else if (kind < 0.53 && slivers) add_sliver(r, l);
        else if (kind < 0.73)
            add_random_triangle(r, l, add(clusters[(int)(8 * uniform(r))], mul(random_unit(r), 0.01)),
                                log_range(r, 1e-4, 5e-3));
        else if (kind < 0.76) add_patch(r, l); /* 32 triangles at once */
        else add_axis_aligned(r, l);
    }
}

void make_soup_rays(rng *r, size_t n, ray_list *rays)
{
    for (size_t i = 0; i < n; i++) {
        vec3 o, d;
        if (uniform(r) < 0.5) {
            o = random_in_box(r, -1.1, 1.1);
            d = random_unit(r);
        } else {
            o = mul(random_unit(r), 4);
            d = sub(random_in_box(r, -1, 1), o);
        }
        double special = uniform(r);
        if (special < 0.05) {
            d = v3(0, 0, 0);
            *component(&d, (int)(3 * uniform(r))) = uniform(r) < 0.5 ? -1 : 1;
        } else if (special < 0.12) {
            *component(&d, (int)(3 * uniform(r))) = 0;
        }
        d = mul(normalized(d), log_range(r, 0.1, 10));
        float tmax = uniform(r) < 0.33 ? (float)(range(r, 0.05, 3) / length(d)) : NO_LIMIT;
        add_ray(rays, o, d, tmax);
    }
}

/* Distance in ulps between two finite floats of the same sign. */
static uint32_t ulps_apart(float a, float b)
{
    uint32_t x = bits(a), y = bits(b);
    return x > y ? x - y : y - x;
}

mismatches compare_answers(const ray_list *rays, const float *bvh, const float *brute, const int *brute_to_bvh)
{
    mismatches m = {0};
    for (size_t i = 0; i < rays->count; i++) {
        const float *q = &rays->v[8 * i], *a = &bvh[4 * i], *b = &brute[4 * i];
        int pa = (int)a[1], pb = (int)b[1];
        if (pb >= 0 && brute_to_bvh) pb = brute_to_bvh[pb];
        int same_t = bits(a[0]) == bits(b[0]);
        int any_ok = (a[2] != 0.0f) == (b[0] < q[3]);
        if (same_t && any_ok && (pa == pb || (pa >= 0 && pb >= 0))) continue;
        m.rounding += any_ok && pa == pb && ulps_apart(a[0], b[0]) <= 2;
        if (m.differ++ == 0)
            snprintf(m.first, sizeof m.first,
                     "ray %zu (origin %.9g %.9g %.9g, dir %.9g %.9g %.9g, tmax %g): BVH t %.9g prim %d any-hit %g, "
                     "brute force t %.9g prim %d",
                     i, q[0], q[1], q[2], q[4], q[5], q[6], q[3], a[0], pa, a[2], b[0], pb);
    }
    return m;
}

size_t count_hits(const float *results, size_t n)
{
    size_t hits = 0;
    for (size_t i = 0; i < n; i++) hits += results[4 * i + 1] >= 0;
    return hits;
}

/* The 20 faces of the icosahedron with vertices (0, +-1, +-phi) and cyclic
 * permutations: the triples whose vertices are pairwise an edge apart. Each
 * level splits every triangle in four; a midpoint is computed from its two
 * endpoints symmetrically, so neighbours share it bitwise. */
static void icosphere_face(tri_list *l, vec3 a, vec3 b, vec3 c, int levels, vec3 centre, double radius)
{
    if (levels == 0) {
        add_tri(l, add(centre, mul(a, radius)), add(centre, mul(b, radius)), add(centre, mul(c, radius)));
        return;
    }
    vec3 ab = normalized(add(a, b)), bc = normalized(add(b, c)), ca = normalized(add(c, a));
    icosphere_face(l, a, ab, ca, levels - 1, centre, radius);
    icosphere_face(l, ab, b, bc, levels - 1, centre, radius);
    icosphere_face(l, ca, bc, c, levels - 1, centre, radius);
    icosphere_face(l, ab, bc, ca, levels - 1, centre, radius);
}

void icosphere(int levels, vec3 centre, double radius, tri_list *l)
{
    const double phi = (1 + sqrt(5.0)) / 2;
    vec3 v[12];
    for (int i = 0; i < 12; i++) {
        double p[3] = {0, (i & 1) ? -1 : 1, (i & 2) ? -phi : phi};
        int rot = i / 4; /* cyclic permutation of the axes */
        v[i] = normalized(v3(p[rot % 3], p[(rot + 1) % 3], p[(rot + 2) % 3]));
    }
    const double edge = 2 / sqrt(1 + phi * phi); /* after normalising */
    for (int i = 0; i < 12; i++)
        for (int j = i + 1; j < 12; j++)
            for (int k = j + 1; k < 12; k++) {
                if (fabs(length(sub(v[i], v[j])) - edge) > 1e-9 || fabs(length(sub(v[j], v[k])) - edge) > 1e-9 ||
                    fabs(length(sub(v[k], v[i])) - edge) > 1e-9)
                    continue;
                int outward = dot(cross(sub(v[j], v[i]), sub(v[k], v[i])), v[i]) > 0;
                icosphere_face(l, v[i], outward ? v[j] : v[k], outward ? v[k] : v[j], levels, centre, radius);
            }
}
