/* Ray and hit records of the ray-throughput benchmark, as bench/kernels/rays.cl
 * writes them, and the small interface to the Embree comparison
 * (bench/embree_compare.c, built only where Embree 3 is installed). */
#ifndef LVCL_BENCH_RAYS_H
#define LVCL_BENCH_RAYS_H

#include <stddef.h>
#include <stdint.h>

#include "../host/scene/scene.h"

#define BENCH_NO_HIT 0xffffffffu

/* Two float4 on the device: (origin, tmax), (dir, 0); dir is unit length. */
typedef struct {
    float origin[3], tmax;
    float dir[3], pad;
} bench_ray;

/* One uint4 on the device. prim_id is the glTF-order triangle index (any
 * occluder for occlusion queries), BENCH_NO_HIT on a miss. */
typedef struct {
    float t;
    uint32_t prim_id;
    uint32_t leaf; /* lvcl's leaf-ordered triangle; unused by Embree */
    uint32_t pad;
} bench_hit;

typedef struct bench_embree bench_embree;

/* Which of Embree's APIs traces: packets of 16, or one ray per call. */
typedef enum { BENCH_EMBREE_PACKETS, BENCH_EMBREE_SINGLE } bench_embree_api;

#ifdef LVCL_HAVE_EMBREE
/* Builds Embree's BVHs over the scene's triangles in glTF order, a scene
 * per mesh under instances where the scene has them, so that hits name
 * the prim_ids of the checksums. NULL if unavailable. */
bench_embree *bench_embree_create(const lvcl_scene *scene, double *build_seconds);

/* Traces `count` rays with every thread: closest hits, or occlusion only if
 * any_hit. Fills hits like the kernels do (t of an occluded ray: its tmax). */
void bench_embree_trace(bench_embree *e, const bench_ray *rays, size_t count, int any_hit, bench_embree_api api,
                        bench_hit *hits);

/* A short description of how bench_embree_trace traces, for the JSON. */
const char *bench_embree_method(void);

void bench_embree_destroy(bench_embree *e);
#else
/* Without Embree the comparison is simply absent. */
static inline bench_embree *bench_embree_create(const lvcl_scene *scene, double *build_seconds)
{
    (void)scene, (void)build_seconds;
    return NULL;
}
static inline void bench_embree_trace(bench_embree *e, const bench_ray *rays, size_t count, int any_hit,
                                      bench_embree_api api, bench_hit *hits)
{
    (void)e, (void)rays, (void)count, (void)any_hit, (void)api, (void)hits;
}
static inline const char *bench_embree_method(void)
{
    return "";
}
static inline void bench_embree_destroy(bench_embree *e)
{
    (void)e;
}
#endif

#endif
