/* Ray traversal of the flattened BVH with watertight ray-triangle tests. */
#ifndef LV_TRAVERSE_H
#define LV_TRAVERSE_H

#include "../util/geometry.h"
#include "../scene_buffers.h"

/* Floating-point contraction is off from the end of util/geometry.h on:
 * the watertight test needs its edge functions evaluated exactly alike for
 * the two triangles sharing an edge, and fusing a*b - c*d into an FMA
 * breaks that symmetry and lets rays slip through shared edges. */

/* The top-level tree and one mesh tree under it, each at most
 * LVCL_BVH_MAX_DEPTH deep (host/accel/bvh.h), plus the marker between them. */
#define LV_TRAVERSAL_STACK 128
#define LV_NO_HIT 0xffffffffu

typedef struct {
    float3 origin;
    float3 dir; /* need not be unit; t is in units of |dir| */
    float tmax;
    uint skip;      /* the triangle the ray leaves from, or LV_NO_HIT */
    uint skip_inst; /* and its instance */
} lv_ray;

/* A ray leaving a surface ignores the triangle (of the instance) it starts
 * on: a flat triangle cannot be met twice by a straight ray, and for thin
 * triangles the computed distance is too inexact to tell leaving from
 * arriving. Pass LV_NO_HIT for rays that leave no surface. */
inline lv_ray lv_ray_make(float3 origin, float3 dir, float tmax, uint skip_inst, uint skip)
{
    lv_ray r;
    r.origin = origin;
    r.dir = dir;
    r.tmax = tmax;
    r.skip = skip;
    r.skip_inst = skip_inst;
    return r;
}

typedef struct {
    float t;
    float b1, b2; /* barycentrics of vertices 1 and 2 */
    uint tri;     /* leaf-ordered triangle index, LV_NO_HIT on a miss */
    uint inst;    /* the instance it belongs to */
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
inline int lv_intersect_triangle(const lv_sheared_ray *s, float4 v0, float4 v1, float4 v2, float *tmax, float *b1,
                                 float *b2)
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
 * rounding never culls a box the ray grazes (Ize 2013). min and max, not
 * fmin and fmax: no operand is NaN (lv_safe_inverse keeps inv_dir finite),
 * and PoCL builds fmin and fmax with NaN handling, which cost a quarter of
 * the diffuse-ray throughput (bench/RAYS.md workloads, same hits). */
inline float lv_box_entry(__global const lv_bvh_node *node, float3 origin, float3 inv_dir, float tmax)
{
    float3 lo = (LV_F3(node->bmin) - origin) * inv_dir;
    float3 hi = (LV_F3(node->bmax) - origin) * inv_dir;
    float3 tn = min(lo, hi), tf = max(lo, hi);
    float t0 = max(max(tn.x, tn.y), max(tn.z, 0.0f));
    float t1 = min(min(tf.x, tf.y), min(tf.z, tmax)) * 1.0000004f;
    return t0 <= t1 ? t0 : LV_FAR;
}

inline float3 lv_safe_inverse(float3 d)
{
    const float tiny = 1e-30f;
    float3 safe = select(d, copysign((float3)(tiny), d), fabs(d) < tiny);
    return 1.0f / safe;
}

/* p transformed by a 3 x 4 row-major matrix; w = 0 leaves out the translation. */
inline float3 lv_transform(__global const float *m, float3 p, float w)
{
    return (float3)(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3] * w, m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7] * w,
                    m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11] * w);
}

/* Marks, on the traversal stack, where a mesh's tree ends and the top-level
 * tree resumes. */
#define LV_LEAVE_INSTANCE (-1)

/* Closest hit if any_hit is 0; any hit (for shadow rays) otherwise. One
 * stack walks the top-level tree of instances and, inside a leaf's
 * instance, that mesh's tree with the ray in object space (its direction
 * is not renormalised, so t means the same in both spaces). */
inline lv_hit lv_trace(const lv_scene *sc, lv_ray r, int any_hit)
{
    lv_hit hit;
    hit.t = r.tmax;
    hit.tri = LV_NO_HIT;
    hit.inst = 0u;
    hit.b1 = hit.b2 = 0.0f;
    float3 origin = r.origin, dir = r.dir;
    lv_sheared_ray s = lv_shear_ray(r);
    float3 inv_dir = lv_safe_inverse(dir);

    int stack[LV_TRAVERSAL_STACK];
    int top = 0;
    if (lv_box_entry(lv_node(sc, 0u), origin, inv_dir, hit.t) == LV_FAR) return hit;
    /* A flat scene's one instance is the identity: start in its mesh. */
    uint inst = 0u;
    int in_mesh = sc->info.flat != 0u;
    int node = in_mesh ? (int)sc->instances[0].root : 0;
    for (;;) {
        __global const lv_bvh_node *n = lv_node(sc, (uint)node);
        if (n->count > 0 && !in_mesh) {
            /* A top-level leaf holds one instance: enter its mesh. */
            inst = (uint)n->index;
            __global const lv_instance *placed = &sc->instances[inst];
            lv_ray object_ray =
                lv_ray_make(lv_transform(placed->object_from_world, r.origin, 1.0f),
                            lv_transform(placed->object_from_world, r.dir, 0.0f), hit.t, LV_NO_HIT, LV_NO_HIT);
            origin = object_ray.origin;
            dir = object_ray.dir;
            s = lv_shear_ray(object_ray);
            inv_dir = lv_safe_inverse(dir);
            stack[top++] = LV_LEAVE_INSTANCE;
            node = (int)placed->root;
            in_mesh = 1;
            continue;
        }
        if (n->count > 0) {
            for (int i = n->index; i < n->index + n->count; i++) {
                if ((uint)i == r.skip && inst == r.skip_inst) continue;
                __global const float4 *v = lv_tri_corners(sc, (uint)i);
                if (lv_intersect_triangle(&s, v[0], v[1], v[2], &hit.t, &hit.b1, &hit.b2)) {
                    hit.tri = (uint)i;
                    hit.inst = inst;
                    if (any_hit) return hit;
                }
            }
        } else {
            int first = node + 1, second = n->index;
            float t_first = lv_box_entry(lv_node(sc, (uint)first), origin, inv_dir, hit.t);
            float t_second = lv_box_entry(lv_node(sc, (uint)second), origin, inv_dir, hit.t);
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
        if (node == LV_LEAVE_INSTANCE) {
            /* Back to the top level and the world-space ray. */
            origin = r.origin;
            dir = r.dir;
            s = lv_shear_ray(r);
            inv_dir = lv_safe_inverse(dir);
            in_mesh = 0;
            if (top == 0) break;
            node = stack[--top];
        }
    }
    return hit;
}

inline int lv_occluded(const lv_scene *sc, float3 origin, float3 dir, float tmax, uint skip_inst, uint skip)
{
    return lv_trace(sc, lv_ray_make(origin, dir, tmax, skip_inst, skip), 1).tri != LV_NO_HIT;
}

#endif
