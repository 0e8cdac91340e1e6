/* The scene as the kernels see it: a private struct of pointers to the
 * uploaded buffers. Every kernel that needs the scene takes LV_SCENE_PARAMS
 * as its first arguments (in this order; host/device_scene.c sets them) and
 * opens them with LV_SCENE_OPEN.
 *
 * The tables that grow with the geometry (nodes, triangles, vertex
 * attributes) may not fit one buffer on a GPU, whose largest allocation is
 * often a quarter of its memory; they come in LV_SCENE_PARTS buffers of
 * lv_scene_info.*_per_part elements each, read through the accessors below
 * (a scene that fits one buffer pays one well-predicted comparison). */
#ifndef LV_SCENE_H
#define LV_SCENE_H

#include "shared_types.h"

typedef struct {
    __global const lv_bvh_node *nodes[LV_SCENE_PARTS];   /* top-level tree, then every mesh's */
    __global const lv_instance *instances;               /* top-level leaf order */
    __global const float4 *tri_vertices[LV_SCENE_PARTS]; /* 3 per triangle, leaf order, object space */
    __global const lv_triangle *triangles[LV_SCENE_PARTS]; /* leaf order */
    __global const float *normals[LV_SCENE_PARTS];       /* 3 per vertex */
    __global const float *uvs[LV_SCENE_PARTS];           /* 2 per vertex */
    __global const lv_material *materials;
    __global const lv_texture *textures;
    __global const uchar4 *texels;
    __global const lv_light *lights;
    __global const lv_punctual_light *punctuals;
    lv_scene_info info;
} lv_scene;

/* LV_SPLIT_AT and the parameter lists below spell out the four parts. */
#if LV_SCENE_PARTS != 4
#error "kernels/scene.h assumes LV_SCENE_PARTS is 4"
#endif

/* The address of element i (of `stride` values) of a table split over
 * parts of n elements. Unsigned wrap-around keeps i - k n exact. */
#define LV_SPLIT_AT(parts, n, i, stride)                                                         \
    ((i) < (n)                ? (parts)[0] + (size_t)(stride) * (i)                              \
     : (i) - (n) < (n)        ? (parts)[1] + (size_t)(stride) * ((i) - (n))                      \
     : (i) - (n) - (n) < (n)  ? (parts)[2] + (size_t)(stride) * ((i) - 2u * (n))                 \
                              : (parts)[3] + (size_t)(stride) * ((i) - 3u * (n)))

inline __global const lv_bvh_node *lv_node(const lv_scene *sc, uint i)
{
    return LV_SPLIT_AT(sc->nodes, sc->info.nodes_per_part, i, 1);
}

/* Triangle tri's three object-space corners. */
inline __global const float4 *lv_tri_corners(const lv_scene *sc, uint tri)
{
    return LV_SPLIT_AT(sc->tri_vertices, sc->info.triangles_per_part, tri, 3);
}

inline lv_triangle lv_triangle_record(const lv_scene *sc, uint tri)
{
    return *LV_SPLIT_AT(sc->triangles, sc->info.triangles_per_part, tri, 1);
}

inline float3 lv_vertex_normal(const lv_scene *sc, uint v)
{
    return vload3(0, LV_SPLIT_AT(sc->normals, sc->info.vertices_per_part, v, 3));
}

inline float2 lv_vertex_uv(const lv_scene *sc, uint v)
{
    return vload2(0, LV_SPLIT_AT(sc->uvs, sc->info.vertices_per_part, v, 2));
}

#define LV_SCENE_PARTS_PARAMS(type, name) \
    __global const type *name##0, __global const type *name##1, __global const type *name##2, __global const type *name##3

#define LV_SCENE_PARAMS                                                                                   \
    LV_SCENE_PARTS_PARAMS(lv_bvh_node, scene_nodes), __global const lv_instance *scene_instances,         \
        LV_SCENE_PARTS_PARAMS(float4, scene_tri_vertices), LV_SCENE_PARTS_PARAMS(lv_triangle, scene_triangles), \
        LV_SCENE_PARTS_PARAMS(float, scene_normals), LV_SCENE_PARTS_PARAMS(float, scene_uvs),             \
        __global const lv_material *scene_materials, __global const lv_texture *scene_textures,           \
        __global const uchar4 *scene_texels, __global const lv_light *scene_lights,                       \
        __global const lv_punctual_light *scene_punctuals, lv_scene_info scene_info

#define LV_SCENE_OPEN_PARTS(field, name) \
    field[0] = name##0;                  \
    field[1] = name##1;                  \
    field[2] = name##2;                  \
    field[3] = name##3

#define LV_SCENE_OPEN(s)                                        \
    lv_scene s;                                                 \
    LV_SCENE_OPEN_PARTS(s.nodes, scene_nodes);                  \
    s.instances = scene_instances;                              \
    LV_SCENE_OPEN_PARTS(s.tri_vertices, scene_tri_vertices);    \
    LV_SCENE_OPEN_PARTS(s.triangles, scene_triangles);          \
    LV_SCENE_OPEN_PARTS(s.normals, scene_normals);              \
    LV_SCENE_OPEN_PARTS(s.uvs, scene_uvs);                      \
    s.materials = scene_materials;                              \
    s.textures = scene_textures;                                \
    s.texels = scene_texels;                                    \
    s.lights = scene_lights;                                    \
    s.punctuals = scene_punctuals;                              \
    s.info = scene_info

#endif
