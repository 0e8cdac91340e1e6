/* Ray traversal against ground truth and at the edges of floating point:
 *   1. the BVH finds exactly what testing every triangle finds;
 *   2. closed meshes do not leak at shared edges and vertices;
 *   3. grazing and in-plane rays give the plane's distance or a clean miss;
 *   4. zero-area and non-finite triangles are left out, and nothing else;
 *   5. rays re-shot from lv_offset_origin never hit their own triangle, at
 *      any scene scale. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "harness.h"

static lvcl_device dev;
static lvcl_program prog;

/* LV_FAR of kernels/traverse.h: the tmax of a ray without a limit. */
#define NO_LIMIT 3.0e38f
#define PI 3.14159265358979323846

/* ---- random numbers: harness_uniform, so every run traces the same rays ---- */

typedef harness_rng rng;

static double uniform(rng *r)
{
    return harness_uniform(r);
}

static double range(rng *r, double lo, double hi)
{
    return lo + (hi - lo) * uniform(r);
}

/* Uniform in log scale: sizes and angles spread over decades. */
static double log_range(rng *r, double lo, double hi)
{
    return lo * pow(hi / lo, uniform(r));
}

/* ---- vectors, in double until a vertex or ray is stored as float ---- */

typedef struct {
    double x, y, z;
} vec3;

static vec3 v3(double x, double y, double z)
{
    vec3 v = {x, y, z};
    return v;
}
static vec3 add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static vec3 sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static vec3 mul(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static double dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double length(vec3 a) { return sqrt(dot(a, a)); }
static vec3 normalized(vec3 a) { return mul(a, 1.0 / length(a)); }
static vec3 lerp(vec3 a, vec3 b, double s) { return add(a, mul(sub(b, a), s)); }

static vec3 cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

static double *component(vec3 *a, int k)
{
    return k == 0 ? &a->x : k == 1 ? &a->y : &a->z;
}

/* The value a float stores, so that directions aim from where rays really start. */
static vec3 as_float(vec3 a)
{
    return v3((float)a.x, (float)a.y, (float)a.z);
}

static vec3 random_unit(rng *r)
{
    double z = range(r, -1, 1), phi = range(r, 0, 2 * PI), s = sqrt(1 - z * z);
    return v3(s * cos(phi), s * sin(phi), z);
}

static vec3 random_in_box(rng *r, double lo, double hi)
{
    return v3(range(r, lo, hi), range(r, lo, hi), range(r, lo, hi));
}

/* ---- triangle and ray lists ---- */

typedef struct {
    float *v; /* 9 floats per triangle */
    size_t count, cap;
} tri_list;

typedef struct {
    float *v; /* 8 floats per ray: origin, tmax, direction, unused */
    size_t count, cap;
} ray_list;

static void *grow(void *p, size_t *cap, size_t need, size_t item_bytes)
{
    if (need <= *cap) return p;
    *cap = need > 2 * *cap ? need : 2 * *cap;
    p = realloc(p, *cap * item_bytes);
    if (!p) {
        printf("FAIL traversal: out of memory\n");
        exit(1);
    }
    return p;
}

static void add_tri_floats(tri_list *l, const float f[9])
{
    l->v = grow(l->v, &l->cap, l->count + 1, 9 * sizeof(float));
    memcpy(&l->v[9 * l->count++], f, 9 * sizeof(float));
}

static void add_tri(tri_list *l, vec3 a, vec3 b, vec3 c)
{
    float f[9] = {(float)a.x, (float)a.y, (float)a.z, (float)b.x, (float)b.y,
                  (float)b.z, (float)c.x, (float)c.y, (float)c.z};
    add_tri_floats(l, f);
}

static vec3 tri_vertex(const tri_list *l, size_t t, int k)
{
    const float *f = &l->v[9 * t + 3 * k];
    return v3(f[0], f[1], f[2]);
}

static void add_ray(ray_list *l, vec3 origin, vec3 dir, float tmax)
{
    l->v = grow(l->v, &l->cap, l->count + 1, 8 * sizeof(float));
    float *q = &l->v[8 * l->count++];
    q[0] = (float)origin.x, q[1] = (float)origin.y, q[2] = (float)origin.z, q[3] = tmax;
    q[4] = (float)dir.x, q[5] = (float)dir.y, q[6] = (float)dir.z, q[7] = 0.0f;
}

/* ---- scenes on the device ---- */

typedef struct {
    lvcl_scene scene;
    lvcl_accel accel;
    lvcl_packed_scene packed;
    lvcl_device_scene ds;
} gpu_scene;

/* Builds and uploads a scene, to `on` (the test device, or a copy of it
 * that claims a smaller largest allocation). */
static lvcl_error gpu_scene_prepare(const tri_list *l, const lvcl_device *on, gpu_scene *g, lvcl_status *st)
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

static void gpu_scene_make(const tri_list *l, gpu_scene *g)
{
    lvcl_status st = {0};
    if (gpu_scene_prepare(l, &dev, g, &st)) {
        printf("FAIL traversal: preparing a scene of %zu triangles: %s\n", l->count, st.message);
        exit(1);
    }
}

static void gpu_scene_free(gpu_scene *g)
{
    lvcl_device_scene_release(&g->ds);
    lvcl_packed_scene_free(&g->packed);
    lvcl_accel_free(&g->accel);
    lvcl_scene_free(&g->scene);
}

static cl_mem buffer(const void *data, size_t bytes)
{
    cl_int err;
    cl_mem m = clCreateBuffer(dev.context, CL_MEM_READ_WRITE | (data ? CL_MEM_COPY_HOST_PTR : 0), bytes,
                              (void *)data, &err);
    harness_cl(err, "allocating");
    return m;
}

/* Runs kernel(scene, rays, count, [extra,] results): 4 result floats per ray. */
static float *run_rays(const gpu_scene *g, const char *kernel_name, const ray_list *rays, const float *extra4)
{
    lvcl_status st = {0};
    cl_kernel k;
    if (lvcl_kernel_create(&prog, kernel_name, &k, &st)) {
        printf("FAIL traversal: kernel %s: %s\n", kernel_name, st.message);
        exit(1);
    }
    size_t n = rays->count;
    float *results = malloc(4 * n * sizeof(float));
    cl_mem rbuf = buffer(rays->v, 8 * n * sizeof(float));
    cl_mem ebuf = extra4 ? buffer(extra4, 4 * n * sizeof(float)) : NULL;
    cl_mem obuf = buffer(NULL, 4 * n * sizeof(float));
    cl_uint count = (cl_uint)n;
    if (lvcl_device_scene_bind(&g->ds, k, 0, &st) || !results) {
        printf("FAIL traversal: setting up kernel %s: %s\n", kernel_name, st.message);
        exit(1);
    }
    harness_cl(clSetKernelArg(k, T_TRACE_ARG_RAYS, sizeof rbuf, &rbuf), "arg");
    harness_cl(clSetKernelArg(k, T_TRACE_ARG_COUNT, sizeof count, &count), "arg");
    if (ebuf) harness_cl(clSetKernelArg(k, T_OFFSET_ARG_RESHOOT, sizeof ebuf, &ebuf), "arg");
    harness_cl(clSetKernelArg(k, ebuf ? T_OFFSET_ARG_RESULTS : T_TRACE_ARG_RESULTS, sizeof obuf, &obuf), "arg");
    harness_run(&dev, k, n);
    harness_cl(clEnqueueReadBuffer(dev.queue, obuf, CL_TRUE, 0, 4 * n * sizeof(float), results, 0, NULL, NULL),
               "reading results");
    clReleaseMemObject(rbuf);
    if (ebuf) clReleaseMemObject(ebuf);
    clReleaseMemObject(obuf);
    clReleaseKernel(k);
    return results;
}

static float *trace(const gpu_scene *g, const ray_list *rays)
{
    return run_rays(g, "t_trace", rays, NULL);
}

static uint32_t bits(float f)
{
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* ---- 1. BVH against brute force ---- */

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

/* About n triangles in [-1,1]^3 mixing what stresses a BVH: sizes over
 * three decades, slivers (if `slivers`), dense clusters, shared vertices,
 * flat boxes. */
static void make_soup(rng *r, size_t n, int slivers, tri_list *l)
{
    vec3 clusters[8];
    for (int i = 0; i < 8; i++) clusters[i] = random_in_box(r, -0.9, 0.9);
    while (l->count < n) {
        double kind = uniform(r);
        if (kind < 0.30)
            add_random_triangle(r, l, random_in_box(r, -1, 1), log_range(r, 1e-3, 0.1));
        else if (kind < 0.38)
            add_random_triangle(r, l, random_in_box(r, -1, 1), range(r, 0.3, 1.5));
        else if (kind < 0.53 && slivers)
            add_sliver(r, l);
        else if (kind < 0.73)
            add_random_triangle(r, l, add(clusters[(int)(8 * uniform(r))], mul(random_unit(r), 0.01)),
                                log_range(r, 1e-4, 5e-3));
        else if (kind < 0.76)
            add_patch(r, l); /* 32 triangles at once */
        else
            add_axis_aligned(r, l);
    }
}

/* Rays from inside and outside the soup's bounds; some along an axis or in
 * an axis plane (zero direction components), lengths of |dir| from 0.1 to
 * 10 (t counts in |dir|), a third with a finite tmax. */
static void make_soup_rays(rng *r, size_t n, ray_list *rays)
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

typedef struct {
    size_t differ;  /* rays whose answers differ */
    size_t rounding; /* of those: same triangle, t at most 2 ulps apart */
    char first[400]; /* the first that differs */
} mismatches;

/* Compares the BVH's answers with brute force's. Equal t with different
 * triangles is a tie either may win. brute_to_bvh (may be NULL) renames
 * brute force's prim_ids. */
static mismatches compare_answers(const ray_list *rays, const float *bvh, const float *brute,
                                  const int *brute_to_bvh)
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

static size_t count_hits(const float *results, size_t n)
{
    size_t hits = 0;
    for (size_t i = 0; i < n; i++) hits += results[4 * i + 1] >= 0;
    return hits;
}

static void test_random_soups(void)
{
    static const struct {
        uint64_t seed;
        size_t triangles;
    } cases[] = {{1, 2000}, {2, 4000}, {3, 10000}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        rng r = {cases[c].seed};
        tri_list soup = {0};
        ray_list rays = {0};
        make_soup(&r, cases[c].triangles, 1, &soup);
        make_soup_rays(&r, 50000, &rays);
        gpu_scene g;
        gpu_scene_make(&soup, &g);
        float *bvh = trace(&g, &rays), *brute = run_rays(&g, "t_trace_brute_force", &rays, NULL);
        char name[128];
        mismatches m = compare_answers(&rays, bvh, brute, NULL);
        size_t hits = count_hits(brute, rays.count);
        snprintf(name, sizeof name, "bvh equals brute force: soup seed %llu, %zu triangles, %zu rays",
                 (unsigned long long)cases[c].seed, soup.count, rays.count);
        /* Mostly misses would make the comparison vacuous. */
        CHECK(name, m.differ == 0 && hits > rays.count / 4,
              "%zu rays differ (%zu of them only by 1-2 ulps in t on the same triangle), %zu of %zu hit; first: %s",
              m.differ, m.rounding, hits, rays.count, m.first);
        snprintf(name, sizeof name, "bvh depth within LVCL_BVH_MAX_DEPTH: soup seed %llu",
                 (unsigned long long)cases[c].seed);
        CHECK(name, g.accel.mesh_bvh[0].depth <= LVCL_BVH_MAX_DEPTH, "depth %d > %d", g.accel.mesh_bvh[0].depth, LVCL_BVH_MAX_DEPTH);
        free(bvh);
        free(brute);
        gpu_scene_free(&g);
        free(soup.v);
        free(rays.v);
    }
}

/* ---- 1b. tables split over several buffers ---- */

/* Gives every vertex of g a random normal and uv, re-uploaded to `on`. */
static void random_attributes(const lvcl_device *on, uint64_t seed, gpu_scene *g, lvcl_status *st)
{
    rng r = {seed};
    lvcl_scene *s = &g->scene;
    for (size_t v = 0; v < s->vertex_count; v++) {
        vec3 n = random_unit(&r);
        s->normals[3 * v] = (float)n.x, s->normals[3 * v + 1] = (float)n.y, s->normals[3 * v + 2] = (float)n.z;
        s->uvs[2 * v] = (float)uniform(&r), s->uvs[2 * v + 1] = (float)uniform(&r);
    }
    for (size_t t = 0; t < s->triangle_count; t++) s->tri_flags[t] |= LV_TRI_HAS_NORMALS | LV_TRI_HAS_UVS;
    lvcl_packed_scene_free(&g->packed);
    lvcl_device_scene_release(&g->ds);
    if (lvcl_pack_scene(s, &g->accel, 0, 8, &g->packed, st) ||
        lvcl_device_scene_upload(on, s, &g->packed, &g->ds, st)) {
        printf("FAIL traversal: re-uploading with attributes: %s\n", st->message);
        exit(1);
    }
}

static void test_split_tables(void)
{
    rng r = {7};
    tri_list soup = {0};
    ray_list rays = {0};
    make_soup(&r, 10000, 1, &soup);
    make_soup_rays(&r, 20000, &rays);
    lvcl_status st = {0};
    gpu_scene whole, split;
    if (gpu_scene_prepare(&soup, &dev, &whole, &st)) {
        printf("FAIL traversal: preparing the split-table scene: %s\n", st.message);
        exit(1);
    }
    /* A device whose largest allocation holds a third of the triangle
     * corners: every large table needs two to four buffers. */
    lvcl_device small = dev;
    small.max_alloc = 10000 * 48 / 3 + 1000;
    if (gpu_scene_prepare(&soup, &small, &split, &st)) {
        CHECK("split tables: a scene over the largest allocation uploads in parts", 0, "%s", st.message);
        gpu_scene_free(&split);
        gpu_scene_free(&whole);
        return;
    }
    random_attributes(&dev, 11, &whole, &st);
    random_attributes(&small, 11, &split, &st);
    const lv_scene_info *in = &split.ds.buffers.info;
    CHECK("split tables: nodes, triangles and vertices each take several buffers",
          split.ds.split_tables == 5 && whole.ds.split_tables == 0 && in->triangles_per_part < 10000 &&
              in->vertices_per_part < 30000 && in->nodes_per_part < split.packed.node_count,
          "%d tables split (one buffer: %d); per part: %u nodes of %zu, %u triangles, %u vertices", split.ds.split_tables,
          whole.ds.split_tables, in->nodes_per_part, split.packed.node_count, in->triangles_per_part,
          in->vertices_per_part);

    float *hits_whole = trace(&whole, &rays), *hits_split = trace(&split, &rays);
    float *surf_whole = run_rays(&whole, "t_surface", &rays, NULL), *surf_split = run_rays(&split, "t_surface", &rays, NULL);
    size_t n = 4 * rays.count * sizeof(float);
    size_t hits = count_hits(hits_whole, rays.count);
    CHECK("split tables: hits and surfaces (normals, uvs) equal one buffer's bit for bit",
          !memcmp(hits_whole, hits_split, n) && !memcmp(surf_whole, surf_split, n) && hits > rays.count / 4,
          "hits %s, surfaces %s, %zu of %zu rays hit", memcmp(hits_whole, hits_split, n) ? "differ" : "equal",
          memcmp(surf_whole, surf_split, n) ? "differ" : "equal", hits, rays.count);
    free(hits_whole);
    free(hits_split);
    free(surf_whole);
    free(surf_split);
    gpu_scene_free(&split);

    /* Over four buffers' worth, the upload fails and says what and why. */
    small.max_alloc = 10000 * 48 / 5;
    lvcl_error e = gpu_scene_prepare(&soup, &small, &split, &st);
    CHECK("split tables: more than four buffers' worth fails, naming the table and sizes",
          e == LVCL_ERR_TOO_LARGE && strstr(st.message, "the scene's ") && strstr(st.message, "MiB") &&
              strstr(st.message, "4 buffers at most"),
          "error %d: %s", e, st.message);
    gpu_scene_free(&split);
    gpu_scene_free(&whole);
    free(soup.v);
    free(rays.v);
}

/* ---- 2. watertightness ---- */

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

static void icosphere(int levels, vec3 centre, double radius, tri_list *l)
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
    vec3 rot[3] = {
        v3(t * axis.x * axis.x + c, t * axis.x * axis.y - s * axis.z, t * axis.x * axis.z + s * axis.y),
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
        if (meshes[m].cube)
            grid_cube(meshes[m].detail, centre, meshes[m].size, &mesh);
        else
            icosphere(meshes[m].detail, centre, meshes[m].size, &mesh);
        check_closed_mesh(meshes[m].name, &mesh, centre, meshes[m].size, 100 + m);
        free(mesh.v);
    }
}

/* ---- 3. grazing rays ---- */

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
    snprintf(why, size, "ray %zu (origin %.9g %.9g %.9g, dir %.9g %.9g %.9g): t %.9g prim %g, plane at t %.9g", i,
             q[0], q[1], q[2], q[4], q[5], q[6], res[0], res[1], -(double)q[2] / q[6]);
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
          "%zu of %zu rays missed or were off by more than 16 eps (t + R/|d|), worst %.3g; first: %s", bad,
          above.count, worst, why);
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

/* ---- 4. degenerate triangles ---- */

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
    case 1: add_tri(l, a, a, b); return;
    case 2: add_tri(l, a, b, b); return;
    case 3: add_tri(l, a, b, a); return;
    case 4: add_tri(l, a, a, a); return;
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

/* ---- 5. self-intersection offset ---- */

/* A random point on a random triangle of l. */
static vec3 point_on(rng *r, const tri_list *l)
{
    size_t t = (size_t)(uniform(r) * l->count);
    double b1 = uniform(r), b2 = uniform(r);
    if (b1 + b2 > 1) b1 = 1 - b1, b2 = 1 - b2;
    vec3 v0 = tri_vertex(l, t, 0);
    return add(v0, add(mul(sub(tri_vertex(l, t, 1), v0), b1), mul(sub(tri_vertex(l, t, 2), v0), b2)));
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
    ray_list rays = {0};
    float *reshoot = malloc(4 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        vec3 o = uniform(&r) < 0.5 ? mul(random_unit(&r), 4) : random_in_box(&r, -1, 1);
        vec3 d = sub(point_on(&r, unit), o);
        add_ray(&rays, add(centre, mul(o, scale)), d, NO_LIMIT);
        random_reshoot(&r, 1.0f, &reshoot[4 * i]);
    }
    float *res = run_rays(&g, "t_offset_rays", &rays, reshoot);

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
    const float *q = &rays.v[8 * first_own], *e = &reshoot[4 * first_own], *o = &res[4 * first_own];
    CHECK(name, own == 0 && hits > n / 2,
          "%zu of %zu hit their own triangle (scene_scale %g); first: ray %zu origin %.9g %.9g %.9g dir %.9g %.9g "
          "%.9g, prim %g, re-shot %s at local direction %g %g %g, own hit at t %.9g, offset %.3g",
          own, hits, g.packed.info.scene_scale, first_own, q[0], q[1], q[2], q[4], q[5], q[6], o[0],
          e[3] > 0 ? "back" : "through", e[0], e[1], e[2], o[2], o[3]);
    snprintf(name, sizeof name, "offset: %s, the step off the surface is under 1e-4 of the scene's reach", what);
    CHECK(name, far == 0, "%zu steps too long, largest %.3g for reach %.3g", far, largest_step, reach);

    free(res);
    free(reshoot);
    free(rays.v);
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
    gpu_scene g;
    gpu_scene_make(&needle, &g);
    size_t n = 40000;
    ray_list rays = {0};
    float *reshoot = malloc(4 * n * sizeof(float));
    for (size_t i = 0; i < n; i++) {
        vec3 o = mul(random_unit(&r), 3);
        size_t t = (size_t)(uniform(&r) * needle.count);
        double b1, b2;
        do {
            b1 = uniform(&r), b2 = uniform(&r);
        } while (b1 < 0.05 || b2 < 0.05 || b1 + b2 > 0.95);
        vec3 v0 = tri_vertex(&needle, t, 0);
        vec3 target = add(v0, add(mul(sub(tri_vertex(&needle, t, 1), v0), b1), mul(sub(tri_vertex(&needle, t, 2), v0), b2)));
        add_ray(&rays, o, sub(target, o), NO_LIMIT);
        random_reshoot(&r, 2.0f, &reshoot[4 * i]);
    }
    float *res = run_rays(&g, "t_offset_rays", &rays, reshoot);
    size_t hits = 0, out_hit = 0, in_missed = 0;
    for (size_t i = 0; i < n; i++) {
        const float *o = &res[4 * i];
        if (o[0] < 0) continue;
        hits++;
        if (reshoot[4 * i + 3] > 0) out_hit += o[1] >= 0;
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
    free(reshoot);
    free(rays.v);
    gpu_scene_free(&g);
    free(needle.v);
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

int main(int argc, char **argv)
{
    (void)argc;
    (void)argv;
    harness_open(NULL, &dev, &prog);
    test_random_soups();
    test_split_tables();
    test_watertight();
    test_grazing();
    test_degenerate();
    test_offset();
    harness_close(&dev, &prog);
    CHECK_EXIT();
}
