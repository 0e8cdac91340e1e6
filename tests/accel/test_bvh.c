/* The BVH against ground truth: on random soups it finds exactly what
 * testing every triangle finds, within its depth limit; split over several
 * buffers (a device with a small largest allocation) its tables give the
 * same hits and surfaces bit for bit, and too large a scene fails saying why. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../check.h"
#include "traversal.h"

/* ---- BVH against brute force ---- */

static void test_random_soups(void)
{
    /* The last soup is large enough for the builder's threads (subtrees of
     * 16,384 items at depth 3, host/accel/bvh.c). */
    static const struct {
        uint64_t seed;
        size_t triangles, rays;
    } cases[] = {{1, 2000, 50000}, {2, 4000, 50000}, {3, 10000, 50000}, {4, 300000, 3000}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        rng r = {cases[c].seed};
        tri_list soup = {0};
        ray_list rays = {0};
        make_soup(&r, cases[c].triangles, 1, &soup);
        make_soup_rays(&r, cases[c].rays, &rays);
        gpu_scene g;
        gpu_scene_make(&soup, &g);
        float *bvh = trace(&g, &rays), *brute = run_rays(&g, "t_trace_brute_force", &rays, NULL);
        char name[128];
        mismatches m = compare_answers(&rays, bvh, brute, NULL);
        size_t hits = count_hits(brute, rays.count);
        snprintf(name, sizeof name, "bvh equals brute force: soup seed %llu, %zu triangles, %zu rays",
                 (unsigned long long)cases[c].seed, soup.count, rays.count);
        /* Mostly misses would make the comparison vacuous. */
        CHECK(name, m.differ == 0 && hits > rays.count / 4,
              "%zu rays differ (%zu of them only by 1-2 ulps in t on the same triangle), %zu of %zu hit; first: %s",
              m.differ, m.rounding, hits, rays.count, m.first);
        snprintf(name, sizeof name, "bvh depth within LVCL_BVH_MAX_DEPTH: soup seed %llu",
                 (unsigned long long)cases[c].seed);
        CHECK(name, g.accel.mesh_bvh[0].depth <= LVCL_BVH_MAX_DEPTH, "depth %d > %d", g.accel.mesh_bvh[0].depth,
              LVCL_BVH_MAX_DEPTH);
        free(bvh);
        free(brute);
        gpu_scene_free(&g);
        free(soup.v);
        free(rays.v);
    }
}

/* ---- the kernels' wide nodes against the binary tree ---- */

/* Walks wide node `at`: every binary leaf below it is seen once, each
 * lane's box is its binary node's, and the stack need is recomputed from
 * the lanes (a node's other live children wait while one is visited). */
typedef struct {
    const lvcl_wide_bvh *w;
    unsigned char *leaf_seen; /* per binary leaf-order item */
    int bad_width, leaf_lanes, node_lanes;
} wide_walk;

static int walk_wide(wide_walk *k, size_t at, int width)
{
    const lv_wide_node *n = &k->w->nodes[at];
    int live = 0, deepest = 0;
    for (int i = 0; i < LV_BVH_WIDTH; i++) {
        if (n->count[i] == LV_EMPTY_CHILD) continue;
        live++;
        if (n->count[i] > 0) {
            k->leaf_lanes++;
            for (int t = n->index[i]; t < n->index[i] + n->count[i]; t++) k->leaf_seen[t]++;
            continue;
        }
        k->node_lanes++;
        int need = walk_wide(k, (size_t)n->index[i], width);
        if (need > deepest) deepest = need;
    }
    if (live > width || live == 0) k->bad_width++;
    return live - 1 + deepest;
}

/* Counts the leaf lanes whose box is not that of the binary leaf with the
 * same items. */
static int lane_boxes_match(const lvcl_bvh *b, const lvcl_wide_bvh *w)
{
    int bad = 0;
    for (size_t at = 0; at < w->node_count; at++)
        for (int i = 0; i < LV_BVH_WIDTH; i++) {
            const lv_wide_node *n = &w->nodes[at];
            if (n->count[i] <= 0) continue;
            int found = 0;
            for (size_t j = 0; j < b->node_count && !found; j++) {
                const lvcl_bvh_node *c = &b->nodes[j];
                if (c->count != n->count[i] || c->index != n->index[i]) continue;
                found = 1;
                for (int a = 0; a < 3; a++) found &= c->bmin[a] == n->lo[a][i] && c->bmax[a] == n->hi[a][i];
            }
            bad += !found;
        }
    return bad;
}

/* The binary tree's depth-first stack need, for width 2's bound. */
static int binary_depth(const lvcl_bvh *b, size_t node)
{
    if (b->nodes[node].count > 0) return 0;
    int l = binary_depth(b, node + 1), r = binary_depth(b, (size_t)b->nodes[node].index);
    return 1 + (l > r ? l : r);
}

static void test_wide_nodes(void)
{
    rng r = {5};
    tri_list soup = {0};
    make_soup(&r, 5000, 1, &soup);
    gpu_scene g;
    gpu_scene_make(&soup, &g);
    const lvcl_bvh *b = &g.accel.mesh_bvh[0];
    size_t leaves = 0;
    for (size_t i = 0; i < b->node_count; i++) leaves += b->nodes[i].count > 0;
    for (int width = 2; width <= LV_BVH_WIDTH; width++) {
        lvcl_wide_bvh w;
        lvcl_status st = {0};
        if (lvcl_bvh_widen(b, width, &w, &st)) {
            CHECK("wide nodes: collapse", 0, "%s", st.message);
            continue;
        }
        wide_walk k = {&w, calloc(b->triangle_count, 1), 0, 0, 0};
        int need = walk_wide(&k, 0, width);
        size_t once = 0;
        for (size_t t = 0; t < b->triangle_count; t++) once += k.leaf_seen[t] == 1;
        int boxes = lane_boxes_match(b, &w);
        char name[128];
        snprintf(name, sizeof name, "wide nodes, width %d: every triangle in one leaf lane, binary leaf boxes", width);
        CHECK(name, once == b->triangle_count && boxes == 0 && k.bad_width == 0,
              "%zu of %zu triangles seen once, %d leaf lanes without their binary box, %d nodes of bad width", once,
              b->triangle_count, boxes, k.bad_width);
        /* Each binary leaf is one lane, each wide node but the root one lane. */
        snprintf(name, sizeof name, "wide nodes, width %d: one lane per leaf and per node, stack need as walked",
                 width);
        CHECK(name,
              (size_t)k.leaf_lanes == leaves && (size_t)k.node_lanes == w.node_count - 1 && need == w.stack_need &&
                  (width != 2 || need == binary_depth(b, 0)) && (width != LV_BVH_WIDTH || w.node_count < leaves / 2),
              "%d leaf lanes for %zu leaves, %d node lanes for %zu nodes; need %d, walk %d, binary depth %d",
              k.leaf_lanes, leaves, k.node_lanes, w.node_count, w.stack_need, need, binary_depth(b, 0));
        free(k.leaf_seen);
        lvcl_wide_bvh_free(&w);
    }
    gpu_scene_free(&g);
    free(soup.v);
}

/* ---- tables split over several buffers ---- */

/* Gives every vertex of g a random normal and uv, re-uploaded to `on`. */
static void random_attributes(const lvcl_device *on, uint64_t seed, gpu_scene *g, lvcl_status *st)
{
    rng r = {seed};
    lvcl_scene *s = &g->scene;
    for (size_t v = 0; v < s->vertex_count; v++) {
        vec3 n = random_unit(&r);
        s->normals[3 * v] = (float)n.x, s->normals[3 * v + 1] = (float)n.y, s->normals[3 * v + 2] = (float)n.z;
        s->uvs[2 * v] = (float)uniform(&r), s->uvs[2 * v + 1] = (float)uniform(&r);
    }
    for (size_t t = 0; t < s->triangle_count; t++) s->tri_flags[t] |= LV_TRI_HAS_NORMALS | LV_TRI_HAS_UVS;
    lvcl_packed_scene_free(&g->packed);
    lvcl_device_scene_release(&g->ds);
    if (lvcl_pack_scene(s, &g->accel, 0, 8, &g->packed, st) ||
        lvcl_device_scene_upload(on, s, &g->packed, &g->ds, st)) {
        printf("FAIL traversal: re-uploading with attributes: %s\n", st->message);
        exit(1);
    }
}

static void test_split_tables(void)
{
    rng r = {7};
    tri_list soup = {0};
    ray_list rays = {0};
    make_soup(&r, 10000, 1, &soup);
    make_soup_rays(&r, 20000, &rays);
    lvcl_status st = {0};
    gpu_scene whole, split;
    if (gpu_scene_prepare(&soup, traversal_device(), &whole, &st)) {
        printf("FAIL traversal: preparing the split-table scene: %s\n", st.message);
        exit(1);
    }
    /* A device whose largest allocation holds a third of the triangle
     * corners: every large table needs two to four buffers. */
    lvcl_device small = *traversal_device();
    small.max_alloc = 10000 * 48 / 3 + 1000;
    if (gpu_scene_prepare(&soup, &small, &split, &st)) {
        CHECK("split tables: a scene over the largest allocation uploads in parts", 0, "%s", st.message);
        gpu_scene_free(&split);
        gpu_scene_free(&whole);
        return;
    }
    random_attributes(traversal_device(), 11, &whole, &st);
    random_attributes(&small, 11, &split, &st);
    const lv_scene_info *in = &split.ds.buffers.info;
    CHECK("split tables: nodes, triangles and vertices each take several buffers",
          split.ds.split_tables == 5 && whole.ds.split_tables == 0 && in->triangles_per_part < 10000 &&
              in->vertices_per_part < 30000 && in->nodes_per_part < split.packed.node_count,
          "%d tables split (one buffer: %d); per part: %u nodes of %zu, %u triangles, %u vertices",
          split.ds.split_tables, whole.ds.split_tables, in->nodes_per_part, split.packed.node_count,
          in->triangles_per_part, in->vertices_per_part);

    float *hits_whole = trace(&whole, &rays), *hits_split = trace(&split, &rays);
    float *surf_whole = run_rays(&whole, "t_surface", &rays, NULL),
          *surf_split = run_rays(&split, "t_surface", &rays, NULL);
    size_t n = 4 * rays.count * sizeof(float);
    size_t hits = count_hits(hits_whole, rays.count);
    CHECK("split tables: hits and surfaces (normals, uvs) equal one buffer's bit for bit",
          !memcmp(hits_whole, hits_split, n) && !memcmp(surf_whole, surf_split, n) && hits > rays.count / 4,
          "hits %s, surfaces %s, %zu of %zu rays hit", memcmp(hits_whole, hits_split, n) ? "differ" : "equal",
          memcmp(surf_whole, surf_split, n) ? "differ" : "equal", hits, rays.count);
    free(hits_whole);
    free(hits_split);
    free(surf_whole);
    free(surf_split);
    gpu_scene_free(&split);

    /* Over four buffers' worth, the upload fails and says what and why. */
    small.max_alloc = 10000 * 48 / 5;
    lvcl_error e = gpu_scene_prepare(&soup, &small, &split, &st);
    CHECK("split tables: more than four buffers' worth fails, naming the table and sizes",
          e == LVCL_ERR_TOO_LARGE && strstr(st.message, "the scene's ") && strstr(st.message, "MiB") &&
              strstr(st.message, "4 buffers at most"),
          "error %d: %s", e, st.message);
    gpu_scene_free(&split);
    gpu_scene_free(&whole);
    free(soup.v);
    free(rays.v);
}

int main(void)
{
    traversal_open();
    test_random_soups();
    test_wide_nodes();
    test_split_tables();
    traversal_close();
    CHECK_EXIT();
}
