/* The scene as imported: world-space triangles with their attributes, glTF
 * materials as described in the file, punctual lights, textures and the
 * camera. Importers fill it; materials.c turns descriptions into BSDFs and
 * bvh.c reorders triangles for traversal. The scene owns all its arrays. */
#ifndef LVCL_SCENE_H
#define LVCL_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include "../util/status.h"
#include "../../kernels/shared_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A glTF material as the file states it (docs/design.md, Scene conventions), before it is
 * mapped to a BSDF. Absent extensions keep their glTF defaults. */
typedef struct {
    float base_color[4];
    int base_color_texture; /* index into scene textures, -1 if none */
    /* KHR_texture_transform on that texture, where has_uv_transform: the
     * texture is read at (u', v') = (m0 u + m1 v + m2, m3 u + m4 v + m5). */
    int has_uv_transform;
    float uv_transform[6];
    unsigned texture_sampling; /* its sampler: LV_WRAP_* per axis, LV_TEXTURE_NEAREST (kernels/shared_types.h) */
    float metallic;
    float roughness;
    float emissive[3];          /* emissiveFactor x KHR_materials_emissive_strength */
    float transmission;         /* KHR_materials_transmission, 0 if absent */
    float ior;                  /* KHR_materials_ior, 1.5 if absent */
    float specular;             /* KHR_materials_specular specularFactor, 1 if absent */
    int has_volume;             /* KHR_materials_volume present with thickness > 0 */
    float attenuation_color[3]; /* KHR_materials_volume, (1,1,1) if absent */
    float attenuation_distance; /* metres; INFINITY if absent */
    int double_sided;
} lvcl_material_desc;

/* Decoded base-colour texture: width x height RGBA8, sRGB-encoded, row 0 at
 * the top (glTF UV v = 0). */
typedef struct {
    uint32_t width, height;
    uint8_t *rgba;
} lvcl_texture_data;

/* The glTF camera in world space; `present` is 0 if the file has none. */
typedef struct {
    int present;
    float position[3];
    float right[3], up[3], back[3]; /* world directions of local +X, +Y, +Z (unit) */
    float yfov;                     /* vertical field of view, radians */
    float aspect;                   /* width / height, 0 if the file leaves it open */
} lvcl_camera_desc;

/* A mesh: a range of the triangle arrays, in its own (object) space. */
typedef struct {
    size_t first_triangle, triangle_count;
} lvcl_mesh;

/* One placement of a mesh: a 3 x 4 row-major affine transform. */
typedef struct {
    uint32_t mesh;
    float world_from_object[12];
} lvcl_instance;

typedef struct {
    /* Vertex attributes, one entry per vertex. */
    float *positions; /* 3 floats per vertex, world space */
    float *normals;   /* 3 per vertex (zero where the mesh has none) */
    float *uvs;       /* 2 per vertex (zero where the mesh has none) */
    size_t vertex_count;

    /* Triangles in glTF order (nodes depth-first, primitives, index order). */
    uint32_t *indices;      /* 3 per triangle */
    uint32_t *tri_material; /* material index per triangle */
    uint32_t *tri_flags;    /* LV_TRI_HAS_NORMALS | LV_TRI_HAS_UVS */
    size_t triangle_count;

    /* Instancing. A scene without meshes is flat: every triangle is in
     * world space, as one mesh placed once. Otherwise every triangle belongs
     * to exactly one mesh, and meshes appear through instances. */
    lvcl_mesh *meshes;
    size_t mesh_count;
    lvcl_instance *instances;
    size_t instance_count;

    lvcl_material_desc *materials;
    size_t material_count;

    lvcl_texture_data *textures;
    size_t texture_count;

    lv_punctual_light *punctuals;
    size_t punctual_count;

    lvcl_camera_desc camera;
} lvcl_scene;

/* Loads a .gltf or .glb file (chosen by content, not extension). On failure
 * the scene is left empty and `st` names the problem. */
lvcl_error lvcl_scene_load_gltf_file(const char *path, lvcl_scene *scene, lvcl_status *st);

/* Loads a glTF from memory; `base_dir` resolves relative URIs (may be ""). */
lvcl_error lvcl_scene_load_gltf_memory(const void *data, size_t size, const char *base_dir, lvcl_scene *scene,
                                       lvcl_status *st);

/* Bakes every instance into world space (a mirroring transform reverses
 * the winding, as glTF says), leaving a flat scene; no-op on a flat one. */
lvcl_error lvcl_scene_flatten(lvcl_scene *scene, lvcl_status *st);

/* The 3 x 4 row-major identity transform. */
extern const float lvcl_identity_transform[12];

/* Applies a 3 x 4 row-major transform to point p (w = 1) or vector (w = 0). */
void lvcl_transform_point(const float m[12], const float p[3], float w, float out[3]);

/* The axis-aligned box around the transformed corners of box lo..hi. */
void lvcl_transform_box(const float m[12], const float lo[3], const float hi[3], float out_lo[3], float out_hi[3]);

/* The inverse of a 3 x 4 affine transform (computed in double precision),
 * and whether it mirrors (negative determinant). */
void lvcl_transform_invert(const float m[12], float out[12], int *mirrored);

/* Frees every array and zeroes the scene. Safe on a zeroed scene. */
void lvcl_scene_free(lvcl_scene *scene);

#ifdef __cplusplus
}
#endif
#endif
