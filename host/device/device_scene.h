/* The scene on a device: the host packs the imported scene and its BVH into
 * the kernels' layouts (kernels/shared_types.h), checks the sizes against
 * the device's memory budget and uploads them. */
#ifndef LVCL_DEVICE_SCENE_H
#define LVCL_DEVICE_SCENE_H

#include "../accel/accel.h"
#include "device.h"
#include "../scene/scene.h"

/* The kernels' arrays, packed on the host (also used by host-side checks). */
typedef struct {
    lv_bvh_node *nodes;        /* the top level, then every mesh's tree */
    size_t node_count;
    lv_instance *instances;    /* in the top level's leaf order */
    size_t instance_count;
    size_t *mesh_first, *mesh_size; /* each mesh's range of the leaf-ordered triangles */
    size_t mesh_count;
    float *tri_vertices;       /* 12 floats (3 x float4) per triangle, leaf order, object space */
    lv_triangle *triangles;    /* leaf order */
    size_t triangle_count;
    lv_material *materials;
    size_t material_count;
    lv_texture *textures;
    size_t texture_count;
    uint32_t *texels;          /* RGBA8 */
    size_t texel_count;
    lv_light *lights;
    size_t light_count;
    lv_scene_info info;
    float bounds_min[3], bounds_max[3];
} lvcl_packed_scene;

/* The uploaded tables. The large ones come in up to LV_SCENE_PARTS
 * buffers (kernels/scene.h); parts a scene does not need stay NULL, and the
 * kernels get part 0 in their place. */
typedef struct {
    cl_mem nodes[LV_SCENE_PARTS], tri_vertices[LV_SCENE_PARTS], triangles[LV_SCENE_PARTS];
    cl_mem normals[LV_SCENE_PARTS], uvs[LV_SCENE_PARTS];
    cl_mem instances, materials, textures, texels, lights, punctuals;
    lv_scene_info info;
    size_t device_bytes;
    int split_tables; /* how many of the tables take more than one buffer */
} lvcl_device_scene;

/* Packs scene and its acceleration structure. The packed scene borrows
 * nothing from either. */
lvcl_error lvcl_pack_scene(const lvcl_scene *scene, const lvcl_accel *accel, uint32_t seed, uint32_t max_depth,
                           lvcl_packed_scene *packed, lvcl_status *st);

/* The world-space corners (9 floats) of leaf-ordered triangle tri as
 * placed by instance `instance`. */
void lvcl_packed_triangle_world(const lvcl_packed_scene *p, size_t instance, size_t tri, float v[9]);
void lvcl_packed_scene_free(lvcl_packed_scene *packed);

/* Uploads, splitting the large tables over up to LV_SCENE_PARTS buffers
 * where one would exceed the device's largest allocation; fails with
 * LVCL_ERR_TOO_LARGE, naming the sizes, if that is not enough or all of
 * them exceed its memory. */
lvcl_error lvcl_device_scene_upload(const lvcl_device *dev, const lvcl_scene *scene, const lvcl_packed_scene *packed,
                                    lvcl_device_scene *ds, lvcl_status *st);
void lvcl_device_scene_release(lvcl_device_scene *ds);

/* Sets the LV_SCENE_PARAMS arguments (kernels/scene.h) of kernel k from
 * index `first`; returns the index of the next argument, or -1 on error. */
int lvcl_device_scene_set_args(const lvcl_device_scene *ds, cl_kernel k, cl_uint first);

#endif
