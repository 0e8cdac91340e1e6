/* The scene's acceleration structure: one BVH per mesh (bottom level) and
 * one over the instances' world-space boxes (top level). A flat scene is
 * one mesh of all triangles under one identity instance. */
#ifndef LVCL_ACCEL_H
#define LVCL_ACCEL_H

#include "bvh.h"
#include "../scene/scene.h"

typedef struct {
    lvcl_mesh *meshes; /* the scene's meshes, or the one implicit mesh of a flat scene */
    size_t mesh_count;
    lvcl_instance *instances; /* likewise */
    size_t instance_count;
    int flat;                           /* one instance with the identity transform */
    lvcl_bvh *mesh_bvh;                 /* per mesh; tri_order relative to the mesh's first triangle */
    lvcl_bvh top;                       /* over instances; tri_order lists instance indices */
    float bounds_min[3], bounds_max[3]; /* world bounds of every finite triangle corner */
    size_t triangle_count;              /* unique triangles in all mesh BVHs */
    size_t instanced_triangles;         /* triangles as placed: each mesh's count times its instances */
    size_t skipped;                     /* triangles left out (zero area or non-finite) */
    size_t node_count;                  /* all levels */
    int depth;                          /* top-level depth plus the deepest mesh tree */
} lvcl_accel;

lvcl_error lvcl_accel_build(const lvcl_scene *scene, lvcl_accel *accel, lvcl_status *st);
void lvcl_accel_free(lvcl_accel *accel);

#endif
