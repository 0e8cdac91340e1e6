/* Ray traversal of the flattened BVH with watertight ray-triangle tests. */
#ifndef LV_TRAVERSE_H
#define LV_TRAVERSE_H

#include "../util/geometry.h"
#include "../scene_buffers.h"

/* Floating-point contraction is off from the end of util/geometry.h on:
 * the watertight test needs its edge functions evaluated exactly alike for
 * the two triangles sharing an edge, and fusing a*b - c*d into an FMA
 * breaks that symmetry and lets rays slip through shared edges. */

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
 * and no ray slips between them. The axes are offsets into a triangle
 * group (one float4 per axis), so the permutation costs no shuffle. */
typedef struct {
    int kx, ky, kz; /* component order */
    float sx, sy, sz;
    float ox, oy, oz; /* the origin's components in that order */
} lv_sheared_ray;

inline float lv_component(float3 v, int k)
{
    return k == 0 ? v.x : (k == 1 ? v.y : v.z);
}

inline lv_sheared_ray lv_shear_ray(lv_ray r)
{
    float3 a = fabs(r.dir);
    int kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    float dz = lv_component(r.dir, kz);
    if (dz < 0.0f) { /* keep the winding of the permuted frame */
        int t = kx;
        kx = ky;
        ky = t;
    }
    lv_sheared_ray s;
    s.kx = kx;
    s.ky = ky;
    s.kz = kz;
    s.sx = lv_component(r.dir, kx) / dz;
    s.sy = lv_component(r.dir, ky) / dz;
    s.sz = 1.0f / dz;
    s.ox = lv_component(r.origin, kx);
    s.oy = lv_component(r.origin, ky);
    s.oz = lv_component(r.origin, kz);
    return s;
}

/* One lane's depth test, with t and det not yet divided: on a hit closer
 * than *tmax it updates *tmax and the barycentrics. */
#define LV_LANE_HIT(sk, lane)                                                                     \
    if (live.sk) {                                                                                \
        float d_ = det.sk, t_ = t.sk;                                                             \
        if (!(d_ > 0.0f ? (t_ <= 0.0f || t_ >= *tmax * d_) : (t_ >= 0.0f || t_ <= *tmax * d_))) { \
            float inv_ = 1.0f / d_;                                                               \
            *tmax = t_ * inv_;                                                                    \
            *b1 = v.sk * inv_;                                                                    \
            *b2 = w.sk * inv_;                                                                    \
            found = (lane);                                                                       \
            if (any_hit) return found;                                                            \
        }                                                                                         \
    }

/* Tests the triangles of group g that lie in [first, end) and are not
 * `skip`, in triangle order, four edge tests at once; each hit closer than
 * *tmax updates it and the barycentrics. Returns the lane of the last
 * triangle hit (the first with any_hit), or -1. */
inline int lv_intersect_group(const lv_sheared_ray *s, __global const float4 *corners, uint g, uint first, uint end,
                              uint skip, int any_hit, float *tmax, float *b1, float *b2)
{
    /* Fast math lets the compiler reassociate, and it then evaluated the
     * four lanes' edge functions so that two triangles sharing an edge no
     * longer agreed on it: rays slipped between them far from the origin
     * (tests/accel/test_watertight.c). Clang 12 and later (PoCL, Intel's
     * runtime) take this pragma; others must not reassociate here. */
#if LV_HAS_FP_REASSOCIATE_PRAGMA
#pragma clang fp reassociate(off)
#endif
    float4 az = corners[s->kz] - s->oz;
    float4 bz = corners[3 + s->kz] - s->oz;
    float4 cz = corners[6 + s->kz] - s->oz;
    float4 ax = (corners[s->kx] - s->ox) - s->sx * az, ay = (corners[s->ky] - s->oy) - s->sy * az;
    float4 bx = (corners[3 + s->kx] - s->ox) - s->sx * bz, by = (corners[3 + s->ky] - s->oy) - s->sy * bz;
    float4 cx = (corners[6 + s->kx] - s->ox) - s->sx * cz, cy = (corners[6 + s->ky] - s->oy) - s->sy * cz;
    float4 u = cx * by - cy * bx;
    float4 v = ax * cy - ay * cx;
    float4 w = bx * ay - by * ax;
    float4 det = u + v + w;
    uint4 tri = (uint4)(LV_TRI_GROUP * g) + (uint4)(0u, 1u, 2u, 3u);
    int4 live = ((u >= 0.0f & v >= 0.0f & w >= 0.0f) | (u <= 0.0f & v <= 0.0f & w <= 0.0f)) & (det != 0.0f) &
        tri >= first & tri < end & tri != skip;
    if (!any(live)) return -1;
    float4 t = u * (s->sz * az) + v * (s->sz * bz) + w * (s->sz * cz);
    int found = -1;
    LV_LANE_HIT(s0, 0)
    LV_LANE_HIT(s1, 1)
    LV_LANE_HIT(s2, 2)
    LV_LANE_HIT(s3, 3)
    return found;
}

/* Compared with, never computed: fast-math builds may assume no infinities. */
#define LV_FAR 3.0e38f

inline float3 lv_safe_inverse(float3 d)
{
    const float tiny = 1e-30f;
    float3 safe = select(d, copysign((float3)(tiny), d), fabs(d) < tiny);
    return 1.0f / safe;
}

/* The ray as the slab test reads it: per axis, the offset (in floats from
 * lv_wide_node.lo) of the bound it meets first, so near and far need no
 * min or max. */
typedef struct {
    float3 origin, inv_dir;
    int near_x, near_y, near_z;
} lv_box_ray;

inline lv_box_ray lv_box_ray_make(float3 origin, float3 dir)
{
    lv_box_ray b;
    b.origin = origin;
    b.inv_dir = lv_safe_inverse(dir); /* never 0: its sign is dir's */
    b.near_x = b.inv_dir.x < 0.0f ? 3 * LV_BVH_WIDTH : 0;
    b.near_y = (b.inv_dir.y < 0.0f ? 3 * LV_BVH_WIDTH : 0) + LV_BVH_WIDTH;
    b.near_z = (b.inv_dir.z < 0.0f ? 3 * LV_BVH_WIDTH : 0) + 2 * LV_BVH_WIDTH;
    return b;
}

/* The offset of the bound opposite `near` on the same axis. */
#define LV_FAR_BOUND(near) ((near) < 3 * LV_BVH_WIDTH ? (near) + 3 * LV_BVH_WIDTH : (near)-3 * LV_BVH_WIDTH)

/* Entry distances of the ray into a node's four child boxes, all at once,
 * or LV_FAR for a child it misses within [0, tmax] and an empty one. The
 * far distance is widened by a few ulps so that rounding never culls a box
 * the ray grazes (Ize 2013). min and max, not fmin and fmax: no operand is
 * NaN (lv_safe_inverse keeps inv_dir finite), and PoCL builds fmin and
 * fmax with NaN handling, which cost a quarter of the diffuse-ray
 * throughput (bench/RAYS.md workloads, same hits). */
inline float4 lv_child_entries(__global const lv_wide_node *n, const lv_box_ray *b, float tmax)
{
    __global const float *bounds = &n->lo[0][0];
    float4 tnx = (vload4(0, bounds + b->near_x) - b->origin.x) * b->inv_dir.x;
    float4 tny = (vload4(0, bounds + b->near_y) - b->origin.y) * b->inv_dir.y;
    float4 tnz = (vload4(0, bounds + b->near_z) - b->origin.z) * b->inv_dir.z;
    float4 tfx = (vload4(0, bounds + LV_FAR_BOUND(b->near_x)) - b->origin.x) * b->inv_dir.x;
    float4 tfy = (vload4(0, bounds + LV_FAR_BOUND(b->near_y)) - b->origin.y) * b->inv_dir.y;
    float4 tfz = (vload4(0, bounds + LV_FAR_BOUND(b->near_z)) - b->origin.z) * b->inv_dir.z;
    float4 t0 = max(max(tnx, tny), max(tnz, 0.0f));
    float4 t1 = min(min(tfx, tfy), min(tfz, tmax)) * 1.0000004f;
    int4 live = vload4(0, n->count) != (int4)(LV_EMPTY_CHILD);
    return select((float4)(LV_FAR), t0, (t0 <= t1) & live);
}

/* p transformed by a 3 x 4 row-major matrix; w = 0 leaves out the translation. */
inline float3 lv_transform(__global const float *m, float3 p, float w)
{
    return (float3)(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3] * w, m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7] * w,
                    m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11] * w);
}

/* What the traversal stack holds: a node (>= 0), a leaf as the lane of
 * the node that lists it (LV_LEAF_REF), or the mark where a mesh's tree
 * ends and the top-level tree resumes. */
#define LV_LEAVE_INSTANCE (-1)
#define LV_LEAF_REF(node, lane) (-2 - (int)(LV_BVH_WIDTH * (node) + (lane)))
#define LV_LEAF_NODE(ref) ((uint)(-2 - (ref)) / LV_BVH_WIDTH)
#define LV_LEAF_LANE(ref) ((uint)(-2 - (ref)) % LV_BVH_WIDTH)

/* Pushes child `lane` of node `node` (read through `n`) if the ray enters
 * it (at t), for lv_trace, whose stack and locals it uses. A closest-hit
 * traversal keeps the children it pushes from one node sorted, nearest on
 * top (`from` is where they start); any-hit leaves them in lane order.
 * (Plain branches: a branch-free sorting network measured slower on PoCL,
 * docs/performance.md.) */
#define LV_PUSH_CHILD(t, lane)                                                    \
    if ((t) != LV_FAR) {                                                          \
        int ref_ = n->count[lane] > 0 ? LV_LEAF_REF(node, lane) : n->index[lane]; \
        int j_ = top++;                                                           \
        if (!any_hit)                                                             \
            for (; j_ > from && stack_t[j_ - 1] < (t); j_--) {                    \
                stack_node[j_] = stack_node[j_ - 1];                              \
                stack_t[j_] = stack_t[j_ - 1];                                    \
            }                                                                     \
        stack_node[j_] = ref_;                                                    \
        stack_t[j_] = (t);                                                        \
    }

/* Closest hit if any_hit is 0; any hit (for shadow and visibility rays)
 * otherwise, which neither sorts children nor skips far ones, and stops
 * at the first hit. One stack walks the top-level tree of instances and,
 * inside a leaf's instance, that mesh's tree with the ray in object space
 * (its direction is not renormalised, so t means the same in both
 * spaces). An entry's distance lets a closest-hit traversal skip nodes
 * beyond the hit found since it was pushed. */
inline lv_hit lv_trace(const lv_scene *sc, lv_ray r, int any_hit)
{
    lv_hit hit;
    hit.t = r.tmax;
    hit.tri = LV_NO_HIT;
    hit.inst = 0u;
    hit.b1 = hit.b2 = 0.0f;
    lv_sheared_ray s = lv_shear_ray(r);
    lv_box_ray b = lv_box_ray_make(r.origin, r.dir);

    int stack_node[LV_TRAVERSAL_STACK];
    float stack_t[LV_TRAVERSAL_STACK];
    int top = 0;
    /* A flat scene's one instance is the identity: start in its mesh. */
    uint inst = 0u;
    int in_mesh = sc->info.flat != 0u;
    int node = in_mesh ? (int)sc->instances[0].root : 0;
    for (;;) {
        if (node >= 0) {
            __global const lv_wide_node *n = lv_node(sc, (uint)node);
            float4 t = lv_child_entries(n, &b, hit.t);
            int from = top;
            LV_PUSH_CHILD(t.s0, 0)
            LV_PUSH_CHILD(t.s1, 1)
            LV_PUSH_CHILD(t.s2, 2)
            LV_PUSH_CHILD(t.s3, 3)
            if (top > from) {
                node = stack_node[--top];
                continue;
            }
        } else {
            __global const lv_wide_node *n = lv_node(sc, LV_LEAF_NODE(node));
            uint lane = LV_LEAF_LANE(node);
            int first = n->index[lane], count = n->count[lane];
            if (!in_mesh) {
                /* A top-level leaf holds one instance: enter its mesh. */
                inst = (uint)first;
                __global const lv_instance *placed = &sc->instances[inst];
                lv_ray object_ray =
                    lv_ray_make(lv_transform(placed->object_from_world, r.origin, 1.0f),
                                lv_transform(placed->object_from_world, r.dir, 0.0f), hit.t, LV_NO_HIT, LV_NO_HIT);
                s = lv_shear_ray(object_ray);
                b = lv_box_ray_make(object_ray.origin, object_ray.dir);
                stack_node[top] = LV_LEAVE_INSTANCE;
                stack_t[top++] = 0.0f;
                node = (int)placed->root;
                in_mesh = 1;
                continue;
            }
            uint end = (uint)(first + count), skip = inst == r.skip_inst ? r.skip : LV_NO_HIT;
            for (uint g = (uint)first / LV_TRI_GROUP; g * LV_TRI_GROUP < end; g++) {
                int lane = lv_intersect_group(&s, lv_tri_group(sc, g), g, (uint)first, end, skip, any_hit, &hit.t,
                                              &hit.b1, &hit.b2);
                if (lane >= 0) {
                    hit.tri = LV_TRI_GROUP * g + (uint)lane;
                    hit.inst = inst;
                    if (any_hit) return hit;
                }
            }
        }
        /* The next entry the ray can still reach. */
        for (;;) {
            if (top == 0) return hit;
            node = stack_node[--top];
            if (node == LV_LEAVE_INSTANCE) {
                /* Back to the top level and the world-space ray. */
                s = lv_shear_ray(r);
                b = lv_box_ray_make(r.origin, r.dir);
                in_mesh = 0;
                continue;
            }
            if (any_hit || stack_t[top] <= hit.t * 1.0000004f) break;
        }
    }
}

inline int lv_occluded(const lv_scene *sc, float3 origin, float3 dir, float tmax, uint skip_inst, uint skip)
{
    return lv_trace(sc, lv_ray_make(origin, dir, tmax, skip_inst, skip), 1).tri != LV_NO_HIT;
}

#endif
