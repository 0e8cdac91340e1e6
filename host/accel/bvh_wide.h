/* The kernels' BVH: the binary build (bvh.h) collapsed into nodes of up to
 * LV_BVH_WIDTH children (lv_wide_node, kernels/shared_types.h). Collapsing
 * keeps the binary tree's leaves, so the leaf order of triangles and
 * instances is unchanged. */
#ifndef LVCL_BVH_WIDE_H
#define LVCL_BVH_WIDE_H

#include "bvh.h"

typedef struct {
    lv_wide_node *nodes; /* root first; child indices relative to it, leaf indices into the leaf order */
    size_t node_count;
    int stack_need; /* the most entries a traversal of this tree can push at once */
} lvcl_wide_bvh;

/* Collapses `b` into nodes of at most `width` (2..LV_BVH_WIDTH) children:
 * each node takes its binary node's children and opens the largest of them
 * until it has `width`. */
lvcl_error lvcl_bvh_widen(const lvcl_bvh *b, int width, lvcl_wide_bvh *wide, lvcl_status *st);

void lvcl_wide_bvh_free(lvcl_wide_bvh *wide);

#endif
