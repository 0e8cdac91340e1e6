/* The kernels' side of the host/kernel contract (kernels/shared_types.h):
 * the tables there expanded into kernel parameter lists and into the
 * structs the kernels read.
 *
 * A kernel declares its parameters with LV_KERNEL_PARAMS(its argument list),
 * e.g. __kernel void lv_pt_pass(LV_KERNEL_PARAMS(LV_PT_PASS_ARGS)); the
 * host binds them by the same list (host/device/kernel_args.h). The scene
 * block's parameters are opened into an lv_scene with LV_SCENE_OPEN, the
 * volume block's into an lv_grid (kernels/volume/grid.h) with
 * LV_VOLUME_OPEN. Kernels outside the production program (tests, benches)
 * may take LV_SCENE_PARAMS first and bind it with the host's scene binder.
 *
 * The tables that grow with the geometry (nodes, triangles, vertex
 * attributes) may not fit one buffer on a GPU, whose largest allocation is
 * often a quarter of its memory; they come in LV_SCENE_PARTS buffers of
 * lv_scene_info.*_per_part elements each, read through the accessors below
 * (a scene that fits one buffer pays one well-predicted comparison). */
#ifndef LV_SCENE_BUFFERS_H
#define LV_SCENE_BUFFERS_H

#include "shared_types.h"

/* The scene as the kernels see it: a private struct of pointers to the
 * uploaded buffers (a field per LV_SCENE_BUFFERS entry), then the info. */
#define LV_SCENE_FIELD_SPLIT(type, name, stride, per_part, what) __global const type *name[LV_SCENE_PARTS];
#define LV_SCENE_FIELD_ONE(type, name, what) __global const type *name;
typedef struct {
    LV_SCENE_BUFFERS(LV_SCENE_FIELD_SPLIT, LV_SCENE_FIELD_ONE)
    lv_scene_info info;
} lv_scene;

/* LV_SPLIT_AT and the parameter lists below spell out the four parts. */
#if LV_SCENE_PARTS != 4 || LV_TALLY_PARTS != 4
#error "kernels/scene_buffers.h assumes LV_SCENE_PARTS and LV_TALLY_PARTS are 4"
#endif
/* The address of element i (of `stride` values) of a table split over
 * parts of n elements. Unsigned wrap-around keeps i - k n exact. */
#define LV_SPLIT_AT(parts, n, i, stride)                                          \
    ((i) < (n)                   ? (parts)[0] + (size_t)(stride) * (i)            \
         : (i) - (n) < (n)       ? (parts)[1] + (size_t)(stride) * ((i) - (n))    \
         : (i) - (n) - (n) < (n) ? (parts)[2] + (size_t)(stride) * ((i)-2u * (n)) \
                                 : (parts)[3] + (size_t)(stride) * ((i)-3u * (n)))

inline __global const lv_wide_node *lv_node(const lv_scene *sc, uint i)
{
    return LV_SPLIT_AT(sc->nodes, sc->info.nodes_per_part, i, lv_scene_stride_nodes);
}

/* Group g of LV_TRI_GROUP triangles' corners (kernels/shared_types.h). */
inline __global const float4 *lv_tri_group(const lv_scene *sc, uint g)
{
    return LV_SPLIT_AT(sc->tri_groups, sc->info.groups_per_part, g, lv_scene_stride_tri_groups);
}

/* Triangle tri's three object-space corners. */
inline void lv_tri_corners(const lv_scene *sc, uint tri, float3 *v0, float3 *v1, float3 *v2)
{
    __global const float *g = (__global const float *)lv_tri_group(sc, tri / LV_TRI_GROUP) + tri % LV_TRI_GROUP;
    *v0 = (float3)(g[0], g[LV_TRI_GROUP], g[2 * LV_TRI_GROUP]);
    *v1 = (float3)(g[3 * LV_TRI_GROUP], g[4 * LV_TRI_GROUP], g[5 * LV_TRI_GROUP]);
    *v2 = (float3)(g[6 * LV_TRI_GROUP], g[7 * LV_TRI_GROUP], g[8 * LV_TRI_GROUP]);
}

inline lv_triangle lv_triangle_record(const lv_scene *sc, uint tri)
{
    return *LV_SPLIT_AT(sc->triangles, sc->info.triangles_per_part, tri, lv_scene_stride_triangles);
}

inline float3 lv_vertex_normal(const lv_scene *sc, uint v)
{
    return vload3(0, LV_SPLIT_AT(sc->normals, sc->info.vertices_per_part, v, lv_scene_stride_normals));
}

inline float2 lv_vertex_uv(const lv_scene *sc, uint v)
{
    return vload2(0, LV_SPLIT_AT(sc->uvs, sc->info.vertices_per_part, v, lv_scene_stride_uvs));
}

/* Four __global pointers name0..name3, each followed by a comma. */
#define LV_PARTS_PARAMS(qual, type, name) \
    __global qual type *name##0, __global qual type *name##1, __global qual type *name##2, __global qual type *name##3,
#define LV_PARTS_OPEN(field, name) \
    field[0] = name##0;            \
    field[1] = name##1;            \
    field[2] = name##2;            \
    field[3] = name##3;

/* The scene block: scene_<table> per buffer, then scene_info. */
#define LV_SCENE_PARAM_SPLIT(type, name, stride, per_part, what) LV_PARTS_PARAMS(const, type, scene_##name)
#define LV_SCENE_PARAM_ONE(type, name, what) __global const type *scene_##name,
#define LV_SCENE_PARAMS LV_SCENE_BUFFERS(LV_SCENE_PARAM_SPLIT, LV_SCENE_PARAM_ONE) lv_scene_info scene_info

/* Declares lv_scene s and fills it from the scene block. */
#define LV_SCENE_OPEN_SPLIT(type, name, stride, per_part, what) LV_PARTS_OPEN(lv_opened_scene_->name, scene_##name)
#define LV_SCENE_OPEN_ONE(type, name, what) lv_opened_scene_->name = scene_##name;
#define LV_SCENE_OPEN(s)                                     \
    lv_scene s;                                              \
    lv_scene *lv_opened_scene_ = &(s);                       \
    LV_SCENE_BUFFERS(LV_SCENE_OPEN_SPLIT, LV_SCENE_OPEN_ONE) \
    lv_opened_scene_->info = scene_info

/* The volume block: a parameter per buffer (its table name), then grid_info. */
#define LV_VOLUME_PARAM_SPLIT(type, name) LV_PARTS_PARAMS(, type, name)
#define LV_VOLUME_PARAM_ONE(type, name) __global type *name,
#define LV_VOLUME_PARAMS LV_VOLUME_BUFFERS(LV_VOLUME_PARAM_SPLIT, LV_VOLUME_PARAM_ONE) lv_grid_info grid_info

/* Fills lv_grid `grid` (declared by the caller) from the volume block. */
#define LV_VOLUME_OPEN_SPLIT(type, name) LV_PARTS_OPEN(lv_grid_opened_->name, name)
#define LV_VOLUME_OPEN_ONE(type, name) lv_grid_opened_->name = name;
#define LV_VOLUME_OPEN(grid)                                        \
    do {                                                            \
        lv_grid *lv_grid_opened_ = &(grid);                         \
        LV_VOLUME_BUFFERS(LV_VOLUME_OPEN_SPLIT, LV_VOLUME_OPEN_ONE) \
        lv_grid_opened_->subcells_seen = 0;                         \
        lv_grid_opened_->restarted_only = 0u;                       \
        lv_grid_opened_->g = grid_info;                             \
    } while (0)

/* A kernel's parameter list from its argument list. */
#define LV_KERNEL_PARAM(kernel, kind, type, name) LV_KERNEL_PARAM_##kind(type, name)
#define LV_KERNEL_PARAM_SCENE(type, name) LV_SCENE_PARAMS
#define LV_KERNEL_PARAM_VOLUME(type, name) LV_VOLUME_PARAMS
#define LV_KERNEL_PARAM_VALUE(type, name) type name
#define LV_KERNEL_PARAM_BUFFER(type, name) __global type *name
#define LV_KERNEL_PARAMS(LIST) LIST(LV_KERNEL_PARAM, LV_SEP_COMMA)

#endif
