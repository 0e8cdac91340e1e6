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
    static const struct {
        uint64_t seed;
        size_t triangles;
    } cases[] = {{1, 2000}, {2, 4000}, {3, 10000}};
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        rng r = {cases[c].seed};
        tri_list soup = {0};
        ray_list rays = {0};
        make_soup(&r, cases[c].triangles, 1, &soup);
        make_soup_rays(&r, 50000, &rays);
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
    test_split_tables();
    traversal_close();
    CHECK_EXIT();
}
