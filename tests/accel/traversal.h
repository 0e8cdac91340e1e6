/* Support for the traversal tests (tests/accel/test_bvh.c, test_watertight.c,
 * test_degenerate.c, test_offset.c): vector maths in double, triangle and
 * ray lists, scenes on the test device and the ray kernels run over them,
 * and the meshes and ray sets more than one test uses. */
#ifndef LVCL_TEST_TRAVERSAL_H
#define LVCL_TEST_TRAVERSAL_H

#include <math.h>
#include <stdint.h>

#include "../harness.h"

/* LV_FAR of kernels/bvh: the tmax of a ray without a limit. */
#define NO_LIMIT 3.0e38f
#define PI 3.14159265358979323846

/* ---- random numbers: harness_uniform, so every run traces the same rays ---- */

typedef harness_rng rng;

static inline double uniform(rng *r)
{
    return harness_uniform(r);
}

static inline double range(rng *r, double lo, double hi)
{
    return lo + (hi - lo) * uniform(r);
}

/* Uniform in log scale: sizes and angles spread over decades. */
static inline double log_range(rng *r, double lo, double hi)
{
    return lo * pow(hi / lo, uniform(r));
}

/* ---- vectors, in double until a vertex or ray is stored as float ---- */

typedef struct {
    double x, y, z;
} vec3;

static inline vec3 v3(double x, double y, double z)
{
    vec3 v = {x, y, z};
    return v;
}
static inline vec3 add(vec3 a, vec3 b)
{
    return v3(a.x + b.x, a.y + b.y, a.z + b.z);
}
static inline vec3 sub(vec3 a, vec3 b)
{
    return v3(a.x - b.x, a.y - b.y, a.z - b.z);
}
static inline vec3 mul(vec3 a, double s)
{
    return v3(a.x * s, a.y * s, a.z * s);
}
static inline double dot(vec3 a, vec3 b)
{
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
static inline double length(vec3 a)
{
    return sqrt(dot(a, a));
}
static inline vec3 normalized(vec3 a)
{
    return mul(a, 1.0 / length(a));
}
static inline vec3 lerp(vec3 a, vec3 b, double s)
{
    return add(a, mul(sub(b, a), s));
}

static inline vec3 cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

static inline double *component(vec3 *a, int k)
{
    return k == 0 ? &a->x : k == 1 ? &a->y : &a->z;
}

/* The value a float stores, so that directions aim from where rays really start. */
static inline vec3 as_float(vec3 a)
{
    return v3((float)a.x, (float)a.y, (float)a.z);
}

static inline vec3 random_unit(rng *r)
{
    double z = range(r, -1, 1), phi = range(r, 0, 2 * PI), s = sqrt(1 - z * z);
    return v3(s * cos(phi), s * sin(phi), z);
}

static inline vec3 random_in_box(rng *r, double lo, double hi)
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

void add_tri_floats(tri_list *l, const float f[9]);
void add_tri(tri_list *l, vec3 a, vec3 b, vec3 c);
/* Corner k of triangle t. */
vec3 tri_vertex(const tri_list *l, size_t t, int k);
void add_ray(ray_list *l, vec3 origin, vec3 dir, float tmax);

/* ---- the test device and scenes on it ---- */

/* Opens the test device and builds the test program (harness_open). */
void traversal_open(void);
void traversal_close(void);
const lvcl_device *traversal_device(void);

typedef struct {
    lvcl_scene scene;
    lvcl_accel accel;
    lvcl_packed_scene packed;
    lvcl_device_scene ds;
} gpu_scene;

/* Builds and uploads a scene, to `on` (the test device, or a copy of it
 * that claims a smaller largest allocation). */
lvcl_error gpu_scene_prepare(const tri_list *l, const lvcl_device *on, gpu_scene *g, lvcl_status *st);
/* The same to the test device; a failure ends the test program. */
void gpu_scene_make(const tri_list *l, gpu_scene *g);
void gpu_scene_free(gpu_scene *g);

/* Runs ray kernel `kernel_name` (T_TRACE_ARGS, or T_OFFSET_RAYS_ARGS with
 * the re-shoot records reshoot4 when that is not NULL) over the rays:
 * 4 result floats per ray, to free. */
float *run_rays(const gpu_scene *g, const char *kernel_name, const ray_list *rays, const float *reshoot4);
/* run_rays with t_trace: t, prim_id or -1, any-hit, front (1) or back (-1). */
float *trace(const gpu_scene *g, const ray_list *rays);

uint32_t bits(float f);
/* Rays of `results` (t_trace's) that hit something. */
size_t count_hits(const float *results, size_t n);

/* ---- shared scenes and rays ---- */

/* About n triangles in [-1,1]^3 mixing what stresses a BVH: sizes over
 * three decades, slivers (if `slivers`), dense clusters, shared vertices,
 * flat boxes. */
void make_soup(rng *r, size_t n, int slivers, tri_list *l);

/* Rays from inside and outside the soup's bounds; some along an axis or in
 * an axis plane (zero direction components), lengths of |dir| from 0.1 to
 * 10 (t counts in |dir|), a third with a finite tmax. */
void make_soup_rays(rng *r, size_t n, ray_list *rays);

/* An icosahedron subdivided `levels` times, on the sphere of `radius`
 * about `centre`; neighbouring triangles share vertices bitwise. */
void icosphere(int levels, vec3 centre, double radius, tri_list *l);

typedef struct {
    size_t differ;   /* rays whose answers differ */
    size_t rounding; /* of those: same triangle, t at most 2 ulps apart */
    char first[400]; /* the first that differs */
} mismatches;

/* Compares the BVH's answers with brute force's (t_trace_brute_force).
 * Equal t with different triangles is a tie either may win. brute_to_bvh
 * (may be NULL) renames brute force's prim_ids. */
mismatches compare_answers(const ray_list *rays, const float *bvh, const float *brute, const int *brute_to_bvh);

#endif
