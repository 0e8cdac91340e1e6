/* The Embree 3 side of the ray-throughput benchmark: the same triangles and
 * the same rays as lvcl, traced on every CPU thread. */
#include "rays.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../host/util/timer.h"

struct bench_embree {
    RTCDevice device;
    RTCScene scene;
    uint32_t *first_triangle; /* per instance: its mesh's first glTF triangle; NULL for a flat scene */
};

/* A triangle geometry over `count` triangles from `indices`, on the one
 * vertex buffer all geometries share. */
static int attach_triangles(bench_embree *e, RTCScene to, RTCBuffer vertices, size_t vertex_count,
                            const uint32_t *indices, size_t count)
{
    RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices, 0, 3 * sizeof(float), vertex_count);
    unsigned *ix = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), count);
    if (ix) memcpy(ix, indices, count * 3 * sizeof(unsigned));
    rtcCommitGeometry(g);
    rtcAttachGeometry(to, g);
    rtcReleaseGeometry(g);
    return ix != NULL;
}

bench_embree *bench_embree_create(const lvcl_scene *s, double *build_seconds)
{
    bench_embree *e = calloc(1, sizeof *e);
    if (!e || !(e->device = rtcNewDevice(NULL))) {
        free(e);
        return NULL;
    }
    double start = lvcl_seconds();
    e->scene = rtcNewScene(e->device);
    /* Full SAH quality, like lvcl's binned-SAH build: the comparison is of
     * traversal, and a cheaper tree would handicap Embree. */
    rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_HIGH);
    /* Embree reads vertices 16 bytes at a time: the buffer has room past the last. */
    size_t bytes = s->vertex_count * 3 * sizeof(float);
    RTCBuffer vertices = rtcNewBuffer(e->device, bytes + 16);
    int ok = vertices != NULL;
    if (ok) memcpy(rtcGetBufferData(vertices), s->positions, bytes);
    if (ok && s->mesh_count == 0) {
        ok = attach_triangles(e, e->scene, vertices, s->vertex_count, s->indices, s->triangle_count);
    } else if (ok) {
        /* Two levels, as lvcl traces them: a scene per mesh, placed by instances. */
        RTCScene *mesh = calloc(s->mesh_count, sizeof *mesh);
        e->first_triangle = malloc((s->instance_count ? s->instance_count : 1) * sizeof *e->first_triangle);
        ok = mesh && e->first_triangle;
        for (size_t m = 0; ok && m < s->mesh_count; m++) {
            mesh[m] = rtcNewScene(e->device);
            rtcSetSceneBuildQuality(mesh[m], RTC_BUILD_QUALITY_HIGH);
            ok = attach_triangles(e, mesh[m], vertices, s->vertex_count, s->indices + 3 * s->meshes[m].first_triangle,
                                  s->meshes[m].triangle_count);
            rtcCommitScene(mesh[m]);
        }
        for (size_t i = 0; ok && i < s->instance_count; i++) {
            const lvcl_instance *in = &s->instances[i];
            RTCGeometry g = rtcNewGeometry(e->device, RTC_GEOMETRY_TYPE_INSTANCE);
            rtcSetGeometryInstancedScene(g, mesh[in->mesh]);
            rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT3X4_ROW_MAJOR, in->world_from_object);
            rtcCommitGeometry(g);
            rtcAttachGeometryByID(e->scene, g, (unsigned)i);
            rtcReleaseGeometry(g);
            e->first_triangle[i] = (uint32_t)s->meshes[in->mesh].first_triangle;
        }
        for (size_t m = 0; mesh && m < s->mesh_count; m++)
            if (mesh[m]) rtcReleaseScene(mesh[m]);
        free(mesh);
    }
    if (vertices) rtcReleaseBuffer(vertices);
    if (!ok) {
        bench_embree_destroy(e);
        return NULL;
    }
    rtcCommitScene(e->scene);
    *build_seconds = lvcl_seconds() - start;
    return e;
}

/* The glTF-order triangle a hit names, as lvcl's prim_id does. */
static uint32_t prim_id(const bench_embree *e, unsigned inst, unsigned prim)
{
    return e->first_triangle ? e->first_triangle[inst] + prim : prim;
}

#define PACKET 16

/* An Embree answer for ray b as the kernels write it: an occluded ray's t
 * is its tmax (Embree sets tfar to -inf), a closest hit names its prim_id. */
static void store_hit(const bench_embree *e, const bench_ray *b, int any_hit, float tfar, unsigned geom, unsigned inst,
                      unsigned prim, bench_hit *h)
{
    memset(h, 0, sizeof *h);
    if (any_hit) {
        h->t = b->tmax;
        h->prim_id = tfar < 0.0f ? 0u : BENCH_NO_HIT;
    } else {
        h->t = tfar;
        h->prim_id = geom == RTC_INVALID_GEOMETRY_ID ? BENCH_NO_HIT : prim_id(e, inst, prim);
    }
}

/* The n (at most 16) rays at `rays` as one packet (Embree's SoA layout);
 * unused lanes are masked off. */
static void trace_packet(const bench_embree *e, const bench_ray *rays, size_t n, int any_hit, bench_hit *hits)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit16 rh __attribute__((aligned(64)));
    int valid[PACKET] __attribute__((aligned(64)));
    for (size_t k = 0; k < PACKET; k++) {
        valid[k] = k < n ? -1 : 0;
        const bench_ray *b = &rays[k < n ? k : 0];
        rh.ray.org_x[k] = b->origin[0];
        rh.ray.org_y[k] = b->origin[1];
        rh.ray.org_z[k] = b->origin[2];
        rh.ray.dir_x[k] = b->dir[0];
        rh.ray.dir_y[k] = b->dir[1];
        rh.ray.dir_z[k] = b->dir[2];
        rh.ray.tnear[k] = 0.0f;
        rh.ray.tfar[k] = b->tmax;
        rh.ray.time[k] = 0.0f;
        rh.ray.mask[k] = 0xffffffffu;
        rh.ray.id[k] = 0;
        rh.ray.flags[k] = 0;
        rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
    }
    if (any_hit) rtcOccluded16(valid, e->scene, &ctx, &rh.ray);
    else rtcIntersect16(valid, e->scene, &ctx, &rh);
    for (size_t k = 0; k < n; k++)
        store_hit(e, &rays[k], any_hit, rh.ray.tfar[k], rh.hit.geomID[k], rh.hit.instID[0][k], rh.hit.primID[k],
                  &hits[k]);
}

/* One ray at a time (rtcIntersect1/rtcOccluded1), Embree's single-ray
 * API: the way a renderer that does not batch its rays calls it. */
static void trace_single(const bench_embree *e, const bench_ray *b, int any_hit, bench_hit *h)
{
    struct RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    struct RTCRayHit rh;
    rh.ray.org_x = b->origin[0];
    rh.ray.org_y = b->origin[1];
    rh.ray.org_z = b->origin[2];
    rh.ray.dir_x = b->dir[0];
    rh.ray.dir_y = b->dir[1];
    rh.ray.dir_z = b->dir[2];
    rh.ray.tnear = 0.0f;
    rh.ray.tfar = b->tmax;
    rh.ray.time = 0.0f;
    rh.ray.mask = 0xffffffffu;
    rh.ray.id = 0;
    rh.ray.flags = 0;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    if (any_hit) rtcOccluded1(e->scene, &ctx, &rh.ray);
    else rtcIntersect1(e->scene, &ctx, &rh);
    store_hit(e, b, any_hit, rh.ray.tfar, rh.hit.geomID, rh.hit.instID[0], rh.hit.primID, h);
}

/* Both ways run over all threads with OpenMP. Packets were the fastest of
 * Embree's ways on this kind of CPU (about 4x single rays on primary
 * rays, 2x on shadow rays, the same on diffuse ones; rtcIntersect1M
 * streams fell between), and they are fair, since PoCL too traces
 * neighbouring rays together, one per SIMD lane. The rays come in pixel
 * order, so a packet holds neighbouring pixels. */
void bench_embree_trace(bench_embree *e, const bench_ray *rays, size_t count, int any_hit, bench_embree_api api,
                        bench_hit *hits)
{
    if (api == BENCH_EMBREE_SINGLE) {
#pragma omp parallel for schedule(dynamic, 1024)
        for (size_t i = 0; i < count; i++) trace_single(e, &rays[i], any_hit, &hits[i]);
        return;
    }
    size_t packets = (count + PACKET - 1) / PACKET;
#pragma omp parallel for schedule(dynamic, 64)
    for (size_t p = 0; p < packets; p++) {
        size_t first = p * PACKET, n = count - first < PACKET ? count - first : PACKET;
        trace_packet(e, &rays[first], n, any_hit, &hits[first]);
    }
}

const char *bench_embree_method(void)
{
    return "rtcIntersect16/rtcOccluded16 packets (fastest) and rtcIntersect1/rtcOccluded1 (single), OpenMP over all "
           "threads";
}

void bench_embree_destroy(bench_embree *e)
{
    if (!e) return;
    if (e->scene) rtcReleaseScene(e->scene);
    free(e->first_triangle);
    if (e->device) rtcReleaseDevice(e->device);
    free(e);
}
