#include "bvh_wide.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    const lvcl_bvh *b;
    lv_wide_node *out;
    size_t count;
    int width;
} widener;

static float node_area(const lvcl_bvh_node *n)
{
    float d[3];
    for (int k = 0; k < 3; k++) d[k] = n->bmax[k] - n->bmin[k];
    return d[0] * d[1] + d[1] * d[2] + d[2] * d[0];
}

/* Fills wide node `at` from the binary subtree under `node` and returns the
 * stack entries its traversal can push: while a child is visited, the
 * node's other children wait on the stack. */
static int widen_node(widener *w, size_t at, size_t node)
{
    const lvcl_bvh_node *nodes = w->b->nodes;
    size_t child[LV_BVH_WIDTH];
    int n = 0;
    if (nodes[node].count > 0) {
        child[n++] = node; /* a tree that is one leaf */
    } else {
        child[n++] = node + 1;
        child[n++] = (size_t)nodes[node].index;
    }
    while (n < w->width) {
        int open = -1;
        for (int i = 0; i < n; i++)
            if (nodes[child[i]].count == 0 &&
                (open < 0 || node_area(&nodes[child[i]]) > node_area(&nodes[child[open]])))
                open = i;
        if (open < 0) break;
        size_t opened = child[open];
        memmove(&child[open + 2], &child[open + 1], (size_t)(n - open - 1) * sizeof child[0]);
        child[open] = opened + 1;
        child[open + 1] = (size_t)nodes[opened].index;
        n++;
    }

    lv_wide_node *out = &w->out[at];
    memset(out, 0, sizeof *out);
    for (int i = n; i < LV_BVH_WIDTH; i++) out->count[i] = LV_EMPTY_CHILD;
    for (int i = 0; i < n; i++) {
        const lvcl_bvh_node *c = &nodes[child[i]];
        for (int k = 0; k < 3; k++) {
            out->lo[k][i] = c->bmin[k];
            out->hi[k][i] = c->bmax[k];
        }
        out->index[i] = c->index;
        out->count[i] = c->count;
    }
    /* Each interior child gets the next node just before the recursion
     * fills it, so the nodes are in depth-first order. */
    int deepest = 0;
    for (int i = 0; i < n; i++) {
        if (nodes[child[i]].count > 0) continue;
        size_t below = w->count++;
        w->out[at].index[i] = (int32_t)below;
        int need = widen_node(w, below, child[i]);
        if (need > deepest) deepest = need;
    }
    return n - 1 + deepest;
}

lvcl_error lvcl_bvh_widen(const lvcl_bvh *b, int width, lvcl_wide_bvh *wide, lvcl_status *st)
{
    memset(wide, 0, sizeof *wide);
    if (b->node_count == 0) return LVCL_OK; /* a mesh with no usable triangle */
    /* Every wide node but a lone leaf's consumes at least one binary interior node. */
    size_t interior = 0;
    for (size_t i = 0; i < b->node_count; i++) interior += b->nodes[i].count == 0;
    widener w = {b, malloc((interior ? interior : 1) * sizeof *w.out), 1, width};
    if (!w.out) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for %zu BVH nodes", interior);
    wide->stack_need = widen_node(&w, 0, 0);
    wide->nodes = w.out;
    wide->node_count = w.count;
    return LVCL_OK;
}

void lvcl_wide_bvh_free(lvcl_wide_bvh *wide)
{
    free(wide->nodes);
    memset(wide, 0, sizeof *wide);
}
