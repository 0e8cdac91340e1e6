#include "bvh.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../util/parallel.h"

#ifdef __SSE__
#include <immintrin.h>
#endif

#define BIN_COUNT 16
/* Triangles per leaf at most; instances get one leaf each, since entering
 * an instance costs a ray transform. */
#define MAX_LEAF_TRIANGLES 8
/* Past this depth the builder splits at the object median, which halves the
 * count each level, so no tree gets deeper than LVCL_BVH_MAX_DEPTH. */
#define MEDIAN_SPLIT_DEPTH 28

/* Four floats in one SSE register (a GNU vector); boxes use lanes 0-2. */
typedef float vec4 __attribute__((vector_size(16)));

/* Lane by lane, a < b ? a : b and a > b ? a : b, as the scalar
 * comparisons below: the same result whatever the lanes hold. */
static inline vec4 vec4_min(vec4 a, vec4 b)
{
#ifdef __SSE__
    return _mm_min_ps(a, b);
#else
    for (int k = 0; k < 4; k++) a[k] = a[k] < b[k] ? a[k] : b[k];
    return a;
#endif
}

static inline vec4 vec4_max(vec4 a, vec4 b)
{
#ifdef __SSE__
    return _mm_max_ps(a, b);
#else
    for (int k = 0; k < 4; k++) a[k] = a[k] > b[k] ? a[k] : b[k];
    return a;
#endif
}

/* An axis-aligned box in lanes 0-2 of lo and hi; lane 3 is free (an
 * item keeps its index there). */
typedef struct {
    vec4 lo, hi;
} box3;

/* An item as the builder moves it: its box, with its index in lo's
 * fourth lane, half a cache line. The partitions swap these records, so
 * each pass over a node's range reads memory in order rather than
 * through an index. */
typedef box3 item_ref;

static inline uint32_t item_id(const item_ref *r)
{
    uint32_t id;
    memcpy(&id, (const char *)&r->lo + 3 * sizeof(float), sizeof id);
    return id;
}

static inline void item_set_id(item_ref *r, uint32_t id)
{
    memcpy((char *)&r->lo + 3 * sizeof(float), &id, sizeof id);
}

/* A node's range before it is split: the union of its items' boxes and of
 * their centroids. */
typedef struct {
    box3 bounds, centroids;
} range_bounds;

typedef struct {
    item_ref *items;
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
    builder bd; /* its own nodes; the items are shared, its range of them its own */
    size_t first, count;
    range_bounds rb;
    int depth;
    int done;
} subtree_task;

static inline float max_f(float a, float b)
{
    return a > b ? a : b;
}

static box3 box_empty(void)
{
    box3 b = {{FLT_MAX, FLT_MAX, FLT_MAX, FLT_MAX}, {-FLT_MAX, -FLT_MAX, -FLT_MAX, -FLT_MAX}};
    return b;
}

static inline void box_grow_point(box3 *b, vec4 p)
{
    b->lo = vec4_min(b->lo, p);
    b->hi = vec4_max(b->hi, p);
}

static inline void box_grow_box(box3 *b, const box3 *o)
{
    b->lo = vec4_min(b->lo, o->lo);
    b->hi = vec4_max(b->hi, o->hi);
}

static inline float box_area(const box3 *b)
{
    vec4 d = b->hi - b->lo;
    if (d[0] < 0) return 0;
    return 2 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

/* Where the builder bins an item: its box's centre (lanes 0-2). Lane 3
 * of lo, the index, is cleared first: as a float it is subnormal, and
 * arithmetic on subnormals takes a slow path on x86 (the build 4x slower). */
static inline vec4 centroid_of(const item_ref *r)
{
    typedef int32_t lanes __attribute__((vector_size(16)));
    vec4 lo = (vec4)((lanes)r->lo & (lanes){-1, -1, -1, 0});
    return 0.5f * (lo + r->hi);
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

/* The bounds of items[first, first+count), for the splits that do not
 * bin (the median's, equal centroids'). */
static range_bounds range_bounds_of(const item_ref *items, size_t first, size_t count)
{
    range_bounds rb = {box_empty(), box_empty()};
    for (size_t i = first; i < first + count; i++) {
        box_grow_box(&rb.bounds, &items[i]);
        box_grow_point(&rb.centroids, centroid_of(&items[i]));
    }
    return rb;
}

/* The bin of an item whose centroid lies `scaled` bin widths above the
 * range's lowest centroid. */
static inline int bin_at(float scaled)
{
    int b = (int)scaled;
    return b >= BIN_COUNT ? BIN_COUNT - 1 : b < 0 ? 0 : b;
}

/* Finds the binned-SAH split of items[first, first+count), whose bounds are
 * rb, binning all three axes in one pass. Returns the number of items that
 * go left (0 if a leaf is cheaper), after partitioning; where it
 * partitioned, *left and *right are the two sides' bounds (the union of
 * their bins, and their centroids gathered as the partition moves them),
 * otherwise the caller computes them. */
static size_t sah_partition(builder *bd, size_t first, size_t count, const range_bounds *rb, range_bounds *left,
                            range_bounds *right, int *bounded)
{
    const box3 *cb = &rb->centroids;
    float scale[3];
    int binned[3];
    /* Two sets of bins in large ranges, for even and odd items: neighbours
     * mostly fall in the same bins, and one set would make each item's
     * update wait for the last one's. Small ranges (most nodes) take one,
     * to save setting up and merging the other. */
    int sets = count >= 64 ? 2 : 1;
    box3 bin_box[2][3][BIN_COUNT];
    uint32_t bin_count[2][3][BIN_COUNT];
    memset(bin_count, 0, (size_t)sets * sizeof bin_count[0]);
    for (int axis = 0; axis < 3; axis++) {
        float extent = cb->hi[axis] - cb->lo[axis];
        binned[axis] = extent > 0;
        scale[axis] = binned[axis] ? BIN_COUNT / extent : 0.0f;
        for (int set = 0; set < sets; set++)
            for (int b = 0; b < BIN_COUNT; b++) bin_box[set][axis][b] = box_empty();
    }
    vec4 offset = cb->lo, scales = {scale[0], scale[1], scale[2], 0.0f};
    for (size_t i = first; i < first + count; i++) {
        const item_ref *r = &bd->items[i];
        int set = (int)(i & (size_t)(sets - 1));
        vec4 at = (centroid_of(r) - offset) * scales;
        int b0 = bin_at(at[0]), b1 = bin_at(at[1]), b2 = bin_at(at[2]);
        bin_count[set][0][b0]++;
        bin_count[set][1][b1]++;
        bin_count[set][2][b2]++;
        box_grow_box(&bin_box[set][0][b0], r);
        box_grow_box(&bin_box[set][1][b1], r);
        box_grow_box(&bin_box[set][2][b2], r);
    }
    for (int axis = 0; axis < 3 && sets == 2; axis++)
        for (int b = 0; b < BIN_COUNT; b++) {
            box_grow_box(&bin_box[0][axis][b], &bin_box[1][axis][b]);
            bin_count[0][axis][b] += bin_count[1][axis][b];
        }

    float best_cost = FLT_MAX;
    int best_axis = -1, best_bin = 0;
    for (int axis = 0; axis < 3; axis++) {
        if (!binned[axis]) continue;
        /* Sweep from the right, then from the left, to cost every bin boundary. */
        float right_area[BIN_COUNT];
        size_t right_count[BIN_COUNT];
        box3 acc = box_empty();
        size_t n = 0;
        for (int b = BIN_COUNT - 1; b > 0; b--) {
            box_grow_box(&acc, &bin_box[0][axis][b]);
            n += bin_count[0][axis][b];
            right_area[b] = box_area(&acc);
            right_count[b] = n;
        }
        acc = box_empty();
        n = 0;
        for (int b = 0; b < BIN_COUNT - 1; b++) {
            box_grow_box(&acc, &bin_box[0][axis][b]);
            n += bin_count[0][axis][b];
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
    float parent_area = box_area(&rb->bounds);
    float split_cost = best_axis < 0 ? FLT_MAX : 1.0f + best_cost / max_f(parent_area, FLT_MIN);
    *bounded = 0;
    if (best_axis < 0 || (split_cost >= (float)count && count <= bd->max_leaf)) {
        if (count <= bd->max_leaf) return 0;
        return count / 2; /* all centroids coincide: any split will do */
    }

    *left = (range_bounds){box_empty(), box_empty()};
    *right = *left;
    for (int b = 0; b < BIN_COUNT; b++)
        box_grow_box(b <= best_bin ? &left->bounds : &right->bounds, &bin_box[0][best_axis][b]);
    item_ref *items = bd->items;
    size_t i = first, j = first + count;
    while (i < j) {
        item_ref t = items[i];
        vec4 c = centroid_of(&t);
        if (bin_at((c[best_axis] - cb->lo[best_axis]) * scale[best_axis]) <= best_bin) {
            box_grow_point(&left->centroids, c);
            i++;
        } else {
            box_grow_point(&right->centroids, c);
            items[i] = items[--j];
            items[j] = t;
        }
    }
    *bounded = 1;
    return i - first;
}

/* Puts the count/2 items of smallest centroid along the longest axis first
 * (Hoare's selection: no shared state, so threads may run it). */
static size_t median_partition(builder *bd, size_t first, size_t count, const box3 *bounds)
{
    float d[3];
    for (int k = 0; k < 3; k++) d[k] = bounds->hi[k] - bounds->lo[k];
    int axis = d[0] > d[1] ? (d[0] > d[2] ? 0 : 2) : (d[1] > d[2] ? 1 : 2);
    item_ref *o = bd->items + first;
    ptrdiff_t lo = 0, hi = (ptrdiff_t)count - 1, k = (ptrdiff_t)(count / 2);
    while (lo < hi) {
        float pivot = centroid_of(&o[(lo + hi) / 2])[axis];
        ptrdiff_t i = lo, j = hi;
        while (i <= j) {
            while (centroid_of(&o[i])[axis] < pivot) i++;
            while (centroid_of(&o[j])[axis] > pivot) j--;
            if (i <= j) {
                item_ref t = o[i];
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

static void build_node(builder *bd, size_t node_index, size_t first, size_t count, int depth, const range_bounds *rb)
{
    lvcl_bvh_node *node = &bd->nodes[node_index];
    memcpy(node->bmin, &rb->bounds.lo, sizeof node->bmin);
    memcpy(node->bmax, &rb->bounds.hi, sizeof node->bmax);
    if (depth > bd->depth) bd->depth = depth;
    if (bd->tasks && depth == FORK_DEPTH && count >= FORK_MIN) {
        subtree_task *t = &bd->tasks[bd->task_count];
        *t = (subtree_task){.bd = *bd, .first = first, .count = count, .rb = *rb, .depth = depth};
        t->bd.tasks = NULL;
        t->bd.nodes = NULL;
        node->count = -1 - bd->task_count++; /* its place in the joined tree */
        return;
    }

    size_t left_count = 0;
    range_bounds left_rb, right_rb;
    int bounded = 0;
    if (count > 1)
        left_count = depth >= MEDIAN_SPLIT_DEPTH ? median_partition(bd, first, count, &rb->bounds)
                                                 : sah_partition(bd, first, count, rb, &left_rb, &right_rb, &bounded);
    if (left_count == 0) {
        make_leaf(node, first, count);
        return;
    }
    if (!bounded) {
        left_rb = range_bounds_of(bd->items, first, left_count);
        right_rb = range_bounds_of(bd->items, first + left_count, count - left_count);
    }
    size_t left = bd->node_count++;
    build_node(bd, left, first, left_count, depth + 1, &left_rb);
    size_t right = bd->node_count++;
    bd->nodes[node_index].index = (int32_t)right;
    bd->nodes[node_index].count = 0;
    build_node(bd, right, first + left_count, count - left_count, depth + 1, &right_rb);
}

static void *build_subtree(void *job)
{
    subtree_task *t = job;
    t->bd.nodes = malloc((2 * t->count - 1) * sizeof *t->bd.nodes);
    if (t->bd.nodes) {
        t->bd.node_count = 1;
        build_node(&t->bd, 0, t->first, t->count, t->depth, &t->rb);
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

/* Builds the tree over bd's first `used` items; takes ownership of them. */
static lvcl_error build_tree(builder *bd, size_t used, lvcl_bvh *bvh, const char *what, lvcl_status *st)
{
    subtree_task tasks[1 << FORK_DEPTH];
    bd->tasks = tasks;
    bd->nodes = used ? malloc((2 * used - 1) * sizeof *bd->nodes) : NULL;
    uint32_t *order = used ? malloc(used * sizeof *order) : NULL;
    if (bd->nodes && order) {
        bd->node_count = 1;
        range_bounds rb = range_bounds_of(bd->items, 0, used);
        build_node(bd, 0, 0, used, 0, &rb);
        if (bd->task_count && !build_subtrees(bd)) bd->nodes = NULL;
    }
    if (!bd->nodes || !order) {
        free(bd->nodes);
        free(bd->items);
        free(order);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory building the BVH over %zu %s", used, what);
    }
    for (size_t i = 0; i < used; i++) order[i] = item_id(&bd->items[i]);
    free(bd->items);
    bvh->nodes = bd->nodes;
    bvh->node_count = bd->node_count;
    bvh->tri_order = order;
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
    bd->items = malloc((count ? count : 1) * sizeof *bd->items);
    if (bd->items) return LVCL_OK;
    return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory building the BVH over %zu %s", count, what);
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
        item_ref *r = &bd.items[used++];
        *r = box_empty();
        for (int c = 0; c < 3; c++) box_grow_point(r, (vec4){v[c][0], v[c][1], v[c][2], 0.0f});
        item_set_id(r, (uint32_t)t);
    }
    if (used == 0) {
        free(bd.items);
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
        const float *b = &boxes[6 * i];
        bd.items[i] = (box3){{b[0], b[1], b[2], 0.0f}, {b[3], b[4], b[5], 0.0f}};
        item_set_id(&bd.items[i], (uint32_t)i);
    }
    return build_tree(&bd, count, bvh, "instances", st);
}

void lvcl_bvh_free(lvcl_bvh *bvh)
{
    free(bvh->nodes);
    free(bvh->tri_order);
    memset(bvh, 0, sizeof *bvh);
}
