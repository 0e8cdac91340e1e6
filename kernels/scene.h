/* The scene as the kernels see it: a private struct of pointers to the
 * uploaded buffers. Every kernel that needs the scene takes LV_SCENE_PARAMS
 * as its first arguments (in this order; host/device_scene.c sets them) and
 * opens them with LV_SCENE_OPEN. */
#ifndef LV_SCENE_H
#define LV_SCENE_H

#include "shared_types.h"

typedef struct {
    __global const lv_bvh_node *nodes;     /* top-level tree, then every mesh's */
    __global const lv_instance *instances; /* top-level leaf order */
    __global const float4 *tri_vertices;   /* 3 per triangle, leaf order, object space */
    __global const lv_triangle *triangles; /* leaf order */
    __global const float *normals;         /* 3 per vertex */
    __global const float *uvs;             /* 2 per vertex */
    __global const lv_material *materials;
    __global const lv_texture *textures;
    __global const uchar4 *texels;
    __global const lv_light *lights;
    __global const lv_punctual_light *punctuals;
    lv_scene_info info;
} lv_scene;

#define LV_SCENE_PARAMS                                                              \
    __global const lv_bvh_node *scene_nodes, __global const lv_instance *scene_instances, \
        __global const float4 *scene_tri_vertices,                                       \
        __global const lv_triangle *scene_triangles, __global const float *scene_normals, \
        __global const float *scene_uvs, __global const lv_material *scene_materials,    \
        __global const lv_texture *scene_textures, __global const uchar4 *scene_texels,  \
        __global const lv_light *scene_lights,                                           \
        __global const lv_punctual_light *scene_punctuals, lv_scene_info scene_info

#define LV_SCENE_OPEN(s)                     \
    lv_scene s;                              \
    s.nodes = scene_nodes;                   \
    s.instances = scene_instances;           \
    s.tri_vertices = scene_tri_vertices;     \
    s.triangles = scene_triangles;           \
    s.normals = scene_normals;               \
    s.uvs = scene_uvs;                       \
    s.materials = scene_materials;           \
    s.textures = scene_textures;             \
    s.texels = scene_texels;                 \
    s.lights = scene_lights;                 \
    s.punctuals = scene_punctuals;           \
    s.info = scene_info

#endif
