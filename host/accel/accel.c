#include "accel.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The box over every finite corner of a mesh's triangles, degenerate ones
 * included (they still say how far the scene reaches). */
static void mesh_vertex_box(const lvcl_scene *scene, const lvcl_mesh *mesh, lvcl_bvh_node *box)
{
    for (int k = 0; k < 3; k++) {
        box->bmin[k] = FLT_MAX;
        box->bmax[k] = -FLT_MAX;
    }
    for (size_t i = 3 * mesh->first_triangle; i < 3 * (mesh->first_triangle + mesh->triangle_count); i++) {
        const float *p = &scene->positions[3 * (size_t)scene->indices[i]];
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) continue;
        for (int k = 0; k < 3; k++) {
            if (p[k] < box->bmin[k]) box->bmin[k] = p[k];
            if (p[k] > box->bmax[k]) box->bmax[k] = p[k];
        }
    }
}

static int is_identity(const float m[12])
{
    return memcmp(m, lvcl_identity_transform, sizeof lvcl_identity_transform) == 0;
}

/* The scene's meshes and instances, or the one mesh and identity instance
 * of a flat scene, as arrays the accel owns. */
static lvcl_error copy_layout(const lvcl_scene *scene, lvcl_accel *a, lvcl_status *st)
{
    int flat = scene->mesh_count == 0;
    a->mesh_count = flat ? 1 : scene->mesh_count;
    a->instance_count = flat ? 1 : scene->instance_count;
    a->meshes = malloc(a->mesh_count * sizeof *a->meshes);
    a->instances = malloc((a->instance_count ? a->instance_count : 1) * sizeof *a->instances);
    a->mesh_bvh = calloc(a->mesh_count, sizeof *a->mesh_bvh);
    if (!a->meshes || !a->instances || !a->mesh_bvh)
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for %zu instances", a->instance_count);
    if (flat) {
        a->meshes[0] = (lvcl_mesh){0, scene->triangle_count};
        a->instances[0].mesh = 0;
        memcpy(a->instances[0].world_from_object, lvcl_identity_transform, sizeof lvcl_identity_transform);
    } else {
        memcpy(a->meshes, scene->meshes, a->mesh_count * sizeof *a->meshes);
        memcpy(a->instances, scene->instances, a->instance_count * sizeof *a->instances);
    }
    return LVCL_OK;
}

lvcl_error lvcl_accel_build(const lvcl_scene *scene, lvcl_accel *a, lvcl_status *st)
{
    memset(a, 0, sizeof *a);
    lvcl_error e = copy_layout(scene, a, st);
    if (e) goto fail;

    for (size_t m = 0; m < a->mesh_count; m++) {
        const lvcl_mesh *mesh = &a->meshes[m];
        e = lvcl_bvh_build(scene->positions, scene->indices + 3 * mesh->first_triangle, mesh->triangle_count,
                           &a->mesh_bvh[m], st);
        if (e == LVCL_ERR_UNSUPPORTED && a->mesh_count > 1) {
            /* A mesh with no usable triangle: its instances are left out. */
            a->skipped += mesh->triangle_count;
            memset(&a->mesh_bvh[m], 0, sizeof a->mesh_bvh[m]);
            continue;
        }
        if (e) goto fail;
        a->skipped += a->mesh_bvh[m].skipped;
        a->triangle_count += a->mesh_bvh[m].triangle_count;
        a->node_count += a->mesh_bvh[m].node_count;
        if (a->mesh_bvh[m].depth > a->depth) a->depth = a->mesh_bvh[m].depth;
    }

    /* Instances of empty meshes drop out; the rest get world boxes. */
    float *boxes = malloc((a->instance_count ? a->instance_count : 1) * 6 * sizeof(float));
    if (!boxes) {
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for %zu instance boxes", a->instance_count);
        goto fail;
    }
    size_t live = 0;
    for (size_t i = 0; i < a->instance_count; i++) {
        const lvcl_bvh *b = &a->mesh_bvh[a->instances[i].mesh];
        if (b->node_count == 0) continue;
        a->instances[live] = a->instances[i];
        lvcl_transform_box(a->instances[live].world_from_object, b->nodes[0].bmin, b->nodes[0].bmax, &boxes[6 * live],
                           &boxes[6 * live + 3]);
        a->instanced_triangles += b->triangle_count;
        live++;
    }
    a->instance_count = live;
    if (live == 0) {
        free(boxes);
        e = lvcl_fail(st, LVCL_ERR_UNSUPPORTED, "scene has no triangle of non-zero area");
        goto fail;
    }
    e = lvcl_bvh_build_boxes(boxes, live, &a->top, st);
    free(boxes);
    if (e) goto fail;
    for (int k = 0; k < 3; k++) {
        a->bounds_min[k] = FLT_MAX;
        a->bounds_max[k] = -FLT_MAX;
    }
    lvcl_bvh_node *vertex_box = malloc(a->mesh_count * sizeof *vertex_box);
    if (!vertex_box) {
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for %zu mesh boxes", a->mesh_count);
        goto fail;
    }
    for (size_t m = 0; m < a->mesh_count; m++) mesh_vertex_box(scene, &a->meshes[m], &vertex_box[m]);
    for (size_t i = 0; i < live; i++) {
        const lvcl_bvh_node *box = &vertex_box[a->instances[i].mesh];
        float lo[3], hi[3];
        lvcl_transform_box(a->instances[i].world_from_object, box->bmin, box->bmax, lo, hi);
        for (int k = 0; k < 3; k++) {
            if (lo[k] < a->bounds_min[k]) a->bounds_min[k] = lo[k];
            if (hi[k] > a->bounds_max[k]) a->bounds_max[k] = hi[k];
        }
    }
    free(vertex_box);
    a->flat = live == 1 && is_identity(a->instances[0].world_from_object);
    a->node_count += a->top.node_count;
    a->depth += a->top.depth;
    return LVCL_OK;

fail:
    lvcl_accel_free(a);
    return e;
}

void lvcl_accel_free(lvcl_accel *a)
{
    for (size_t m = 0; a->mesh_bvh && m < a->mesh_count; m++) lvcl_bvh_free(&a->mesh_bvh[m]);
    free(a->mesh_bvh);
    free(a->meshes);
    free(a->instances);
    lvcl_bvh_free(&a->top);
    memset(a, 0, sizeof *a);
}
