/* Bounding volume hierarchy over triangles: a binned-SAH build on the host
 * into a binary tree, flattened depth first. The host walks it as it is;
 * the kernels get it collapsed into 4-wide nodes (bvh_wide.h). */
#ifndef LVCL_BVH_H
#define LVCL_BVH_H

#include <stddef.h>
#include <stdint.h>

#include "../util/status.h"
#include "../../kernels/shared_types.h"

/* A binary node. An interior node's first child is the next node; `index`
 * is the second child. A leaf (count > 0) holds `count` items starting at
 * `index` in the tree's leaf order. */
typedef struct {
    float bmin[3];
    int32_t index;
    float bmax[3];
    int32_t count;
} lvcl_bvh_node;

/* Deepest path from the root the builder makes (edges). */
#define LVCL_BVH_MAX_DEPTH 60

typedef struct {
    lvcl_bvh_node *nodes;
    size_t node_count;
    uint32_t *tri_order;   /* leaf slot -> original triangle (or box) index */
    size_t triangle_count; /* items in the tree (degenerate triangles left out) */
    size_t skipped;        /* zero-area or non-finite triangles left out */
    int depth;
} lvcl_bvh;

/* Builds over `count` triangles given by 3 indices each into `positions`
 * (3 floats per vertex). Triangles of zero area or with non-finite vertices
 * are left out and counted in `skipped`. */
lvcl_error lvcl_bvh_build(const float *positions, const uint32_t *indices, size_t count, lvcl_bvh *bvh,
                          lvcl_status *st);

/* Builds over `count` boxes (6 floats each: min xyz, max xyz, finite), one
 * per leaf; tri_order then lists box indices. For the top level of
 * instances. */
lvcl_error lvcl_bvh_build_boxes(const float *boxes, size_t count, lvcl_bvh *bvh, lvcl_status *st);

void lvcl_bvh_free(lvcl_bvh *bvh);

#endif
