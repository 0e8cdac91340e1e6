/* Ray traversal of the flattened BVH with watertight ray-triangle tests. */
#ifndef LV_TRAVERSE_H
#define LV_TRAVERSE_H

#include "geometry.h"
#include "scene.h"

/* The watertight test needs its edge functions evaluated exactly alike for
 * the two triangles sharing an edge; fusing a*b - c*d into an FMA breaks
 * that symmetry and lets rays slip through shared edges. */
#pragma OPENCL FP_CONTRACT OFF

/* Must be at least LVCL_BVH_MAX_DEPTH + 1 (host/bvh.h). */
#define LV_TRAVERSAL_STACK 64
#define LV_NO_HIT 0xffffffffu

typedef struct {
    float3 origin;
    float3 dir; /* need not be unit; t is in units of |dir| */
    float tmax;
    uint skip;  /* the triangle the ray leaves from, or LV_NO_HIT */
} lv_ray;

/* skip: a ray leaving a surface ignores the triangle it starts on. A flat
 * triangle cannot be met twice by a straight ray, and for thin triangles the
 * computed distance is too inexact to tell leaving from arriving. */
inline lv_ray lv_ray_make(float3 origin, float3 dir, float tmax, uint skip)
{
    lv_ray r;
    r.origin = origin;
    r.dir = dir;
    r.tmax = tmax;
    r.skip = skip;
    return r;
}

typedef struct {
    float t;
    float b1, b2; /* barycentrics of vertices 1 and 2 */
    uint tri;     /* leaf-ordered triangle index, LV_NO_HIT on a miss */
} lv_hit;

/* The ray in the shear-transformed space of Woop, Benthin and Wald (2013),
 * "Watertight ray/triangle intersection": the dominant axis becomes z, so
 * edge functions are evaluated identically for triangles sharing an edge
 * and no ray slips between them. */
typedef struct {
    uint4 perm; /* component order (kx, ky, kz, -) for shuffle() */
    float sx, sy, sz;
    float4 origin;
} lv_sheared_ray;

inline lv_sheared_ray lv_shear_ray(lv_ray r)
{
    float3 a = fabs(r.dir);
    uint kz = a.x > a.y ? (a.x > a.z ? 0u : 2u) : (a.y > a.z ? 1u : 2u);
    uint kx = kz == 2u ? 0u : kz + 1u;
    uint ky = kx == 2u ? 0u : kx + 1u;
    float4 d4 = (float4)(r.dir, 0.0f);
    float dz = kz == 0u ? r.dir.x : (kz == 1u ? r.dir.y : r.dir.z);
    if (dz < 0.0f) { /* keep the winding of the permuted frame */
        uint t = kx;
        kx = ky;
        ky = t;
    }
    lv_sheared_ray s;
    s.perm = (uint4)(kx, ky, kz, 3u);
    float4 d = shuffle(d4, s.perm);
    s.sx = d.x / d.z;
    s.sy = d.y / d.z;
    s.sz = 1.0f / d.z;
    s.origin = (float4)(r.origin, 0.0f);
    return s;
}

/* Tests one triangle; on a hit closer than *tmax updates *tmax and the
 * barycentrics and returns 1. */
inline int lv_intersect_triangle(const lv_sheared_ray *s, float4 v0, float4 v1, float4 v2,
                                 float *tmax, float *b1, float *b2)
{
    float4 a = shuffle(v0 - s->origin, s->perm);
    float4 b = shuffle(v1 - s->origin, s->perm);
    float4 c = shuffle(v2 - s->origin, s->perm);
    float ax = a.x - s->sx * a.z, ay = a.y - s->sy * a.z;
    float bx = b.x - s->sx * b.z, by = b.y - s->sy * b.z;
    float cx = c.x - s->sx * c.z, cy = c.y - s->sy * c.z;
    float u = cx * by - cy * bx;
    float v = ax * cy - ay * cx;
    float w = bx * ay - by * ax;
    if ((u < 0.0f || v < 0.0f || w < 0.0f) && (u > 0.0f || v > 0.0f || w > 0.0f)) return 0;
    float det = u + v + w;
    if (det == 0.0f) return 0;
    float t = u * (s->sz * a.z) + v * (s->sz * b.z) + w * (s->sz * c.z);
    if (det > 0.0f ? (t <= 0.0f || t >= *tmax * det) : (t >= 0.0f || t <= *tmax * det)) return 0;
    float inv = 1.0f / det;
    *tmax = t * inv;
    *b1 = v * inv;
    *b2 = w * inv;
    return 1;
}

/* Compared with, never computed: fast-math builds may assume no infinities. */
#define LV_FAR 3.0e38f

/* Entry distance of the ray into a node's box, or LV_FAR if it misses
 * within [0, tmax]. The far distance is widened by a few ulps so that
 * rounding never culls a box the ray grazes (Ize 2013). */
inline float lv_box_entry(__global const lv_bvh_node *node, float3 origin, float3 inv_dir, float tmax)
{
    float3 lo = (LV_F3(node->bmin) - origin) * inv_dir;
    float3 hi = (LV_F3(node->bmax) - origin) * inv_dir;
    float3 tn = fmin(lo, hi), tf = fmax(lo, hi);
    float t0 = fmax(fmax(tn.x, tn.y), fmax(tn.z, 0.0f));
    float t1 = fmin(fmin(tf.x, tf.y), fmin(tf.z, tmax)) * 1.0000004f;
    return t0 <= t1 ? t0 : LV_FAR;
}

inline float3 lv_safe_inverse(float3 d)
{
    const float tiny = 1e-30f;
    float3 safe = select(d, copysign((float3)(tiny), d), fabs(d) < tiny);
    return 1.0f / safe;
}

/* Closest hit if any_hit is 0; any hit (for shadow rays) otherwise. */
inline lv_hit lv_trace(const lv_scene *sc, lv_ray r, int any_hit)
{
    lv_hit hit;
    hit.t = r.tmax;
    hit.tri = LV_NO_HIT;
    hit.b1 = hit.b2 = 0.0f;
    lv_sheared_ray s = lv_shear_ray(r);
    float3 inv_dir = lv_safe_inverse(r.dir);

    int stack[LV_TRAVERSAL_STACK];
    int top = 0;
    int node = 0;
    if (lv_box_entry(&sc->nodes[0], r.origin, inv_dir, hit.t) == LV_FAR) return hit;
    for (;;) {
        __global const lv_bvh_node *n = &sc->nodes[node];
        if (n->count > 0) {
            for (int i = n->index; i < n->index + n->count; i++) {
                if ((uint)i == r.skip) continue;
                __global const float4 *v = &sc->tri_vertices[3 * i];
                if (lv_intersect_triangle(&s, v[0], v[1], v[2], &hit.t, &hit.b1, &hit.b2)) {
                    hit.tri = (uint)i;
                    if (any_hit) return hit;
                }
            }
        } else {
            int first = node + 1, second = n->index;
            float t_first = lv_box_entry(&sc->nodes[first], r.origin, inv_dir, hit.t);
            float t_second = lv_box_entry(&sc->nodes[second], r.origin, inv_dir, hit.t);
            if (t_second < t_first) {
                int tn = first;
                first = second;
                second = tn;
                float tt = t_first;
                t_first = t_second;
                t_second = tt;
            }
            if (t_first != LV_FAR) {
                if (t_second != LV_FAR) stack[top++] = second;
                node = first;
                continue;
            }
        }
        if (top == 0) break;
        node = stack[--top];
    }
    return hit;
}

inline int lv_occluded(const lv_scene *sc, float3 origin, float3 dir, float tmax, uint skip)
{
    return lv_trace(sc, lv_ray_make(origin, dir, tmax, skip), 1).tri != LV_NO_HIT;
}

#endif
