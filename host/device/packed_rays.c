/* Walks of the packed scene's placed trees on the host: every instance's
 * binary tree with its boxes placed in the world, for the light volume's
 * grid (host/render/volume_grid.c) and for the few rays its checks cast
 * (host/render/volume_planes.c). Slow: no top-level tree. */
#include <math.h>

#include "../util/vec3.h"
#include "packed_scene.h"

/* Whether o + t d for t in [0, len] meets box [lo, hi]. */
static int segment_meets_box(const float lo[3], const float hi[3], const double o[3], const double d[3], double len)
{
    double t0 = 0, t1 = len;
    for (int k = 0; k < 3; k++) {
        if (d[k] == 0) {
            if (o[k] < lo[k] || o[k] > hi[k]) return 0;
            continue;
        }
        double a = (lo[k] - o[k]) / d[k], b = (hi[k] - o[k]) / d[k];
        if (a > b) {
            double t = a;
            a = b, b = t;
        }
        t0 = fmax(t0, a), t1 = fmin(t1, b);
        if (t0 > t1) return 0;
    }
    return 1;
}

double lvcl_segment_meets_triangle(const float v[9], const double o[3], const double d[3], double len)
{
    double e1[3], e2[3], s[3], p[3], q[3];
    for (int k = 0; k < 3; k++) e1[k] = (double)v[3 + k] - v[k], e2[k] = (double)v[6 + k] - v[k], s[k] = o[k] - v[k];
    lvcl_cross3(d, e2, p);
    double det = lvcl_dot3(e1, p);
    if (det == 0) return 0;
    double u = lvcl_dot3(s, p) / det;
    if (u < 0 || u > 1) return 0;
    lvcl_cross3(s, e1, q);
    double w = lvcl_dot3(d, q) / det;
    if (w < 0 || u + w > 1) return 0;
    double t = lvcl_dot3(e2, q) / det;
    return t > 0 && t <= len ? t : 0;
}

int lvcl_packed_walk(const lvcl_packed_scene *p, lvcl_node_filter enter, lvcl_triangle_visitor triangle, void *ctx)
{
    int stack[LVCL_BVH_MAX_DEPTH + 1];
    for (size_t in = 0; in < p->instance_count; in++) {
        const lv_instance *inst = &p->instances[in];
        int top = 0;
        stack[top++] = (int)p->mesh_tree_root[inst->mesh];
        while (top > 0) {
            const lvcl_bvh_node *n = &p->tree_nodes[stack[--top]];
            float lo[3], hi[3];
            lvcl_transform_box(inst->world_from_object, n->bmin, n->bmax, lo, hi);
            if (!enter(ctx, lo, hi)) continue;
            if (n->count == 0) {
                stack[top++] = (int)(n - p->tree_nodes) + 1;
                stack[top++] = n->index;
                continue;
            }
            for (size_t t = (size_t)n->index; t < (size_t)n->index + (size_t)n->count; t++) {
                float v[9];
                lvcl_packed_triangle_world(p, in, t, v);
                if (triangle(ctx, v)) return 1;
            }
        }
    }
    return 0;
}

typedef struct {
    const double *o, *d;
    double len;
    int shortened; /* lvcl_packed_first_hit: len is a hit's */
} segment;

static int box_on_segment(void *ctx, const float lo[3], const float hi[3])
{
    const segment *s = ctx;
    return segment_meets_box(lo, hi, s->o, s->d, s->len);
}

static int triangle_on_segment(void *ctx, const float v[9])
{
    const segment *s = ctx;
    return lvcl_segment_meets_triangle(v, s->o, s->d, s->len) > 0;
}

/* Shortens the segment to the triangle's hit, and goes on. */
static int triangle_nearer(void *ctx, const float v[9])
{
    segment *s = ctx;
    double t = lvcl_segment_meets_triangle(v, s->o, s->d, s->len);
    if (t > 0) s->len = t, s->shortened = 1;
    return 0;
}

int lvcl_packed_segment_hits(const lvcl_packed_scene *p, const double o[3], const double d[3], double len)
{
    segment s = {o, d, len, 0};
    return lvcl_packed_walk(p, box_on_segment, triangle_on_segment, &s);
}

double lvcl_packed_first_hit(const lvcl_packed_scene *p, const double o[3], const double d[3], double len)
{
    segment s = {o, d, len, 0};
    lvcl_packed_walk(p, box_on_segment, triangle_nearer, &s);
    return s.shortened ? s.len : 0;
}
