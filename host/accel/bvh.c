#include "bvh.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../util/parallel.h"

#define BIN_COUNT 16
/* Triangles per leaf at most; instances get one leaf each, since entering
 * an instance costs a ray transform. */
#define MAX_LEAF_TRIANGLES 8
/* Past this depth the builder splits at the object median, which halves the
 * count each level, so no tree gets deeper than LVCL_BVH_MAX_DEPTH. */
#define MEDIAN_SPLIT_DEPTH 28

typedef struct {
    float lo[3], hi[3];
} box3;

typedef struct {
    box3 *tri_box;
    float *centroid; /* 3 per triangle */
    uint32_t *order; /* working permutation of triangle indices */
    lvcl_bvh_node *nodes;
    size_t node_count;
    size_t max_leaf;
    int depth;
    struct subtree_task *tasks; /* the top levels' builder only: subtrees left to threads */
    int task_count;
} builder;

/* The top levels are split on the calling thread; at FORK_DEPTH each
 * subtree of at least FORK_MIN items is built on a thread of its own into
 * its own nodes, and the trees are joined in depth-first order, so the
 * result is the one-thread tree node for node. */
#define FORK_DEPTH 3
#define FORK_MIN 16384

typedef struct subtree_task {
    builder bd; /* its own nodes; the item arrays are shared, its range of order[] its own */
    size_t first, count;
    int depth;
    int done;
} subtree_task;

/* Plain comparisons: fminf/fmaxf are library calls here (NaN rules), and
 * the builder feeds them only finite values. */
static inline float min_f(float a, float b)
{
    return a < b ? a : b;
}
static inline float max_f(float a, float b)
{
    return a > b ? a : b;
}

static box3 box_empty(void)
{
    box3 b = {{FLT_MAX, FLT_MAX, FLT_MAX}, {-FLT_MAX, -FLT_MAX, -FLT_MAX}};
    return b;
}

static inline void box_grow_point(box3 *b, const float p[3])
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = min_f(b->lo[k], p[k]);
        b->hi[k] = max_f(b->hi[k], p[k]);
    }
}

static inline void box_grow_box(box3 *b, const box3 *o)
{
    for (int k = 0; k < 3; k++) {
        b->lo[k] = min_f(b->lo[k], o->lo[k]);
        b->hi[k] = max_f(b->hi[k], o->hi[k]);
    }
}

static inline float box_area(const box3 *b)
{
    float d[3];
    for (int k = 0; k < 3; k++) d[k] = b->hi[k] - b->lo[k];
    if (d[0] < 0) return 0;
    return 2 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

/* Twice the area, or 0 for degenerate or non-finite triangles. */
static int triangle_usable(const float *a, const float *b, const float *c)
{
    for (int k = 0; k < 3; k++)
        if (!isfinite(a[k]) || !isfinite(b[k]) || !isfinite(c[k])) return 0;
    double e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = (double)b[k] - a[k];
        e2[k] = (double)c[k] - a[k];
    }
    double n0 = e1[1] * e2[2] - e1[2] * e2[1];
    double n1 = e1[2] * e2[0] - e1[0] * e2[2];
    double n2 = e1[0] * e2[1] - e1[1] * e2[0];
    return n0 * n0 + n1 * n1 + n2 * n2 > 0.0;
}

static void make_leaf(lvcl_bvh_node *node, size_t first, size_t count)
{
    node->index = (int32_t)first;
    node->count = (int32_t)count;
}

/* Finds the binned-SAH split of order[first, first+count). Returns the number
 * of triangles that go left (0 if a leaf is cheaper), after partitioning. */
static size_t sah_partition(builder *bd, size_t first, size_t count, const box3 *bounds)
{
    box3 cb = box_empty();
    for (size_t i = first; i < first + count; i++) box_grow_point(&cb, &bd->centroid[3 * bd->order[i]]);

    float best_cost = FLT_MAX;
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; axis++) {
        float extent = cb.hi[axis] - cb.lo[axis];
        if (!(extent > 0)) continue;
        float scale = BIN_COUNT / extent;
        box3 bin_box[BIN_COUNT];
        size_t bin_count[BIN_COUNT] = {0};
        for (int b = 0; b < BIN_COUNT; b++) bin_box[b] = box_empty();
        for (size_t i = first; i < first + count; i++) {
            uint32_t t = bd->order[i];
            int b = (int)((bd->centroid[3 * t + axis] - cb.lo[axis]) * scale);
            if (b >= BIN_COUNT) b = BIN_COUNT - 1;
            if (b < 0) b = 0;
            bin_count[b]++;
            box_grow_box(&bin_box[b], &bd->tri_box[t]);
        }
        /* Sweep from the right, then from the left, to cost every bin boundary. */
        float right_area[BIN_COUNT];
        size_t right_count[BIN_COUNT];
        box3 acc = box_empty();
        size_t n = 0;
        for (int b = BIN_COUNT - 1; b > 0; b--) {
            box_grow_box(&acc, &bin_box[b]);
            n += bin_count[b];
            right_area[b] = box_area(&acc);
            right_count[b] = n;
        }
        acc = box_empty();
        n = 0;
        for (int b = 0; b < BIN_COUNT - 1; b++) {
            box_grow_box(&acc, &bin_box[b]);
            n += bin_count[b];
            if (n == 0 || right_count[b + 1] == 0) continue;
            float cost = box_area(&acc) * (float)n + right_area[b + 1] * (float)right_count[b + 1];
            if (cost < best_cost) {
                best_cost = cost;
                best_axis = axis;
                best_bin = b;
            }
        }
    }

    /* Costs relative to the parent's area: one traversal step plus one
     * intersection per triangle, against intersecting them all here. */
    float parent_area = box_area(bounds);
    float split_cost = best_axis < 0 ? FLT_MAX : 1.0f + best_cost / max_f(parent_area, FLT_MIN);
    if (best_axis < 0 || (split_cost >= (float)count && count <= bd->max_leaf)) {
        if (count <= bd->max_leaf) return 0;
        return count / 2; /* all centroids coincide: any split will do */
    }

    float scale = BIN_COUNT / (cb.hi[best_axis] - cb.lo[best_axis]);
    size_t i = first, j = first + count;
    while (i < j) {
        uint32_t t = bd->order[i];
        int b = (int)((bd->centroid[3 * t + best_axis] - cb.lo[best_axis]) * scale);
        if (b >= BIN_COUNT) b = BIN_COUNT - 1;
        if (b <= best_bin) {
            i++;
        } else {
            bd->order[i] = bd->order[--j];
            bd->order[j] = t;
        }
    }
    return i - first;
}

/* Puts the count/2 items of smallest centroid along the longest axis first
 * (Hoare's selection: no shared state, so threads may run it). */
static size_t median_partition(builder *bd, size_t first, size_t count, const box3 *bounds)
{
    float d[3];
    for (int k = 0; k < 3; k++) d[k] = bounds->hi[k] - bounds->lo[k];
    int axis = d[0] > d[1] ? (d[0] > d[2] ? 0 : 2) : (d[1] > d[2] ? 1 : 2);
    uint32_t *o = bd->order + first;
    const float *c = bd->centroid;
    ptrdiff_t lo = 0, hi = (ptrdiff_t)count - 1, k = (ptrdiff_t)(count / 2);
    while (lo < hi) {
        float pivot = c[3 * o[(lo + hi) / 2] + axis];
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (c[3 * o[i] + axis] < pivot) i++;
            while (c[3 * o[j] + axis] > pivot) j--;
            if (i <= j) {
                uint32_t t = o[i];
                o[i++] = o[j];
                o[j--] = t;
            }
        }
        if (k <= j) hi = j;
        else if (k >= i) lo = i;
        else break;
    }
    return count / 2;
}

static void build_node(builder *bd, size_t node_index, size_t first, size_t count, int depth)
{
    lvcl_bvh_node *node = &bd->nodes[node_index];
    box3 bounds = box_empty();
    for (size_t i = first; i < first + count; i++) box_grow_box(&bounds, &bd->tri_box[bd->order[i]]);
    memcpy(node->bmin, bounds.lo, sizeof node->bmin);
    memcpy(node->bmax, bounds.hi, sizeof node->bmax);
    if (depth > bd->depth) bd->depth = depth;
    if (bd->tasks && depth == FORK_DEPTH && count >= FORK_MIN) {
        subtree_task *t = &bd->tasks[bd->task_count];
        *t = (subtree_task){.bd = *bd, .first = first, .count = count, .depth = depth};
        t->bd.tasks = NULL;
        t->bd.nodes = NULL;
        node->count = -1 - bd->task_count++; /* its place in the joined tree */
        return;
    }

    size_t left_count = 0;
    if (count > 1)
        left_count = depth >= MEDIAN_SPLIT_DEPTH ? median_partition(bd, first, count, &bounds)
                                                 : sah_partition(bd, first, count, &bounds);
    if (left_count == 0) {
        make_leaf(node, first, count);
        return;
    }
    size_t left = bd->node_count++;
    build_node(bd, left, first, left_count, depth + 1);
    size_t right = bd->node_count++;
    bd->nodes[node_index].index = (int32_t)right;
    bd->nodes[node_index].count = 0;
    build_node(bd, right, first + left_count, count - left_count, depth + 1);
}

static void *build_subtree(void *job)
{
    subtree_task *t = job;
    t->bd.nodes = malloc((2 * t->count - 1) * sizeof *t->bd.nodes);
    if (t->bd.nodes) {
        t->bd.node_count = 1;
        build_node(&t->bd, 0, t->first, t->count, t->depth);
    }
    t->done = 1;
    return NULL;
}

/* Writes the top levels' subtree at `node` to out[at...] in depth-first
 * order, each task's tree in place of its mark; returns the nodes written. */
static size_t join(const builder *top, const subtree_task *tasks, size_t node, lvcl_bvh_node *out, size_t at)
{
    const lvcl_bvh_node *n = &top->nodes[node];
    if (n->count < 0) {
        const subtree_task *t = &tasks[-1 - n->count];
        for (size_t i = 0; i < t->bd.node_count; i++) {
            out[at + i] = t->bd.nodes[i];
            if (out[at + i].count == 0) out[at + i].index += (int32_t)at;
        }
        return t->bd.node_count;
    }
    out[at] = *n;
    if (n->count > 0) return 1;
    size_t left = join(top, tasks, node + 1, out, at + 1);
    out[at].index = (int32_t)(at + 1 + left);
    return 1 + left + join(top, tasks, (size_t)n->index, out, at + 1 + left);
}

/* Builds the subtrees of the top levels' marks on threads and joins them
 * in; a task whose thread could not start runs here. */
static int build_subtrees(builder *bd)
{
    lvcl_status ignored = {0};
    if (lvcl_run_parallel(build_subtree, bd->tasks, sizeof *bd->tasks, bd->task_count, &ignored))
        for (int i = 0; i < bd->task_count; i++)
            if (!bd->tasks[i].done) build_subtree(&bd->tasks[i]);
    size_t total = bd->node_count - (size_t)bd->task_count;
    int ok = 1;
    for (int i = 0; i < bd->task_count; i++) {
        ok &= bd->tasks[i].bd.nodes != NULL;
        total += bd->tasks[i].bd.node_count;
        if (bd->tasks[i].bd.depth > bd->depth) bd->depth = bd->tasks[i].bd.depth;
    }
    lvcl_bvh_node *joined = ok ? malloc(total * sizeof *joined) : NULL;
    if (joined) join(bd, bd->tasks, 0, joined, 0);
    for (int i = 0; i < bd->task_count; i++) free(bd->tasks[i].bd.nodes);
    free(bd->nodes);
    bd->nodes = joined;
    bd->node_count = total;
    return joined != NULL;
}

/* Builds the tree over the `used` items listed in bd->order, whose boxes
 * and centroids are filled; takes ownership of bd's arrays. */
static lvcl_error build_tree(builder *bd, size_t used, lvcl_bvh *bvh, const char *what, lvcl_status *st)
{
    subtree_task tasks[1 << FORK_DEPTH];
    bd->tasks = tasks;
    bd->nodes = used ? malloc((2 * used - 1) * sizeof *bd->nodes) : NULL;
    if (bd->nodes) {
        bd->node_count = 1;
        build_node(bd, 0, 0, used, 0);
        if (bd->task_count && !build_subtrees(bd)) bd->nodes = NULL;
    }
    free(bd->tri_box);
    free(bd->centroid);
    if (!bd->nodes) {
        free(bd->order);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory building the BVH over %zu %s", used, what);
    }
    bvh->nodes = bd->nodes;
    bvh->node_count = bd->node_count;
    bvh->tri_order = bd->order;
    bvh->triangle_count = used;
    bvh->depth = bd->depth;
    return LVCL_OK;
}

static lvcl_error start_builder(builder *bd, size_t count, size_t max_leaf, const char *what, lvcl_status *st)
{
    memset(bd, 0, sizeof *bd);
    if (count >= (size_t)INT32_MAX / 2)
        return lvcl_fail(st, LVCL_ERR_TOO_LARGE, "%zu %s exceed the BVH's 32-bit indices", count, what);
    bd->max_leaf = max_leaf;
    bd->tri_box = malloc((count ? count : 1) * sizeof *bd->tri_box);
    bd->centroid = malloc((count ? count : 1) * 3 * sizeof(float));
    bd->order = malloc((count ? count : 1) * sizeof(uint32_t));
    if (bd->tri_box && bd->centroid && bd->order) return LVCL_OK;
    free(bd->tri_box);
    free(bd->centroid);
    free(bd->order);
    return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory building the BVH over %zu %s", count, what);
}

static void set_item(builder *bd, uint32_t i, const box3 *b)
{
    bd->tri_box[i] = *b;
    for (int k = 0; k < 3; k++) bd->centroid[3 * i + k] = 0.5f * (b->lo[k] + b->hi[k]);
}

lvcl_error lvcl_bvh_build(const float *positions, const uint32_t *indices, size_t count, lvcl_bvh *bvh, lvcl_status *st)
{
    memset(bvh, 0, sizeof *bvh);
    builder bd;
    lvcl_error e = start_builder(&bd, count, MAX_LEAF_TRIANGLES, "triangles", st);
    if (e) return e;
    size_t used = 0;
    for (size_t t = 0; t < count; t++) {
        const float *v[3];
        for (int c = 0; c < 3; c++) v[c] = positions + 3 * (size_t)indices[3 * t + c];
        if (!triangle_usable(v[0], v[1], v[2])) {
            bvh->skipped++;
            continue;
        }
        box3 b = box_empty();
        for (int c = 0; c < 3; c++) box_grow_point(&b, v[c]);
        set_item(&bd, (uint32_t)t, &b);
        bd.order[used++] = (uint32_t)t;
    }
    if (used == 0) {
        free(bd.tri_box);
        free(bd.centroid);
        free(bd.order);
        return lvcl_fail(st, LVCL_ERR_UNSUPPORTED, "scene has no triangle of non-zero area");
    }
    return build_tree(&bd, used, bvh, "triangles", st);
}

lvcl_error lvcl_bvh_build_boxes(const float *boxes, size_t count, lvcl_bvh *bvh, lvcl_status *st)
{
    memset(bvh, 0, sizeof *bvh);
    builder bd;
    lvcl_error e = start_builder(&bd, count, 1, "instances", st);
    if (e) return e;
    for (size_t i = 0; i < count; i++) {
        box3 b;
        memcpy(b.lo, &boxes[6 * i], sizeof b.lo);
        memcpy(b.hi, &boxes[6 * i + 3], sizeof b.hi);
        set_item(&bd, (uint32_t)i, &b);
        bd.order[i] = (uint32_t)i;
    }
    return build_tree(&bd, count, bvh, "instances", st);
}

void lvcl_bvh_free(lvcl_bvh *bvh)
{
    free(bvh->nodes);
    free(bvh->tri_order);
    memset(bvh, 0, sizeof *bvh);
}
