/* Types shared by the host (C11) and the kernels (OpenCL C 1.2).
 *
 * Only 32-bit scalars and fixed arrays of them: no vector types, whose size
 * and alignment differ between C and OpenCL C. Every struct is a multiple of
 * 16 bytes; host/device_layout.c checks sizes and offsets with static asserts.
 */
#ifndef LVCL_SHARED_TYPES_H
#define LVCL_SHARED_TYPES_H

#ifdef __OPENCL_C_VERSION__
typedef uint lv_u32;
typedef int lv_i32;
#else
#include <stdint.h>
typedef uint32_t lv_u32;
typedef int32_t lv_i32;
#endif

/* A BVH node in depth-first order. An interior node's first child is the
 * next node; `index` is the second child. A leaf (count > 0) holds `count`
 * items starting at `index`: instances (in the instance array) in the
 * top-level tree, which starts at node 0; triangles (in the leaf-ordered
 * triangle arrays) in a mesh's tree. Indices are absolute. */
typedef struct {
    float bmin[3];
    lv_i32 index;
    float bmax[3];
    lv_i32 count;
} lv_bvh_node;

/* Per triangle, in BVH leaf order: where its attributes live and what it is. */
typedef struct {
    lv_u32 v[3];      /* indices into the vertex attribute arrays */
    lv_u32 material;  /* index into the material array */
    lv_u32 prim_id;   /* global triangle index in glTF order (checksums) */
    lv_u32 light;     /* emitters: which of its mesh's emitting triangles (the light
                         table holds them per instance from lv_instance.light_base), else LV_NO_LIGHT */
    lv_u32 flags;     /* LV_TRI_* */
    lv_u32 pad;
} lv_triangle;

#define LV_NO_LIGHT 0xffffffffu
#define LV_TRI_HAS_NORMALS 1u
#define LV_TRI_HAS_UVS 2u

/* One placement of a mesh: its bottom-level BVH under the top-level BVH
 * of all instances (nodes[0]), with 3 x 4 row-major transforms. A scene
 * without reuse is one instance with the identity (lv_scene_info.flat).
 * Mirrored instances (negative determinant) flip which face is the front,
 * as glTF's winding rule asks. */
#define LV_INSTANCE_MIRRORED 1u

typedef struct {
    float world_from_object[12];
    float object_from_world[12];
    lv_u32 root;       /* the mesh's BVH root in the node array */
    lv_u32 light_base; /* light-table entry of the mesh's first emitting triangle here, or LV_NO_LIGHT */
    lv_u32 flags;      /* LV_INSTANCE_* */
    lv_u32 mesh;
} lv_instance;

/* BSDF families (DESIGN.md section 3); the host maps glTF materials here. */
#define LV_BSDF_DIFFUSE 0     /* Lambertian */
#define LV_BSDF_PLASTIC 1     /* diffuse base under a dielectric GGX (or smooth) layer */
#define LV_BSDF_CONDUCTOR 2   /* GGX or smooth metal, Schlick Fresnel with F0 = base colour */
#define LV_BSDF_GLASS 3       /* solid dielectric, smooth or GGX, Beer-Lambert inside */
#define LV_BSDF_THIN_GLASS 4  /* thin-walled dielectric: reflection, straight transmission */
#define LV_BSDF_COUNT 5

typedef struct {
    float base_color[3];
    lv_i32 base_color_texture; /* index into lv_texture table, -1 if none */
    float emission[3];         /* emitted radiance, W m^-2 sr^-1, front face */
    lv_u32 bsdf;               /* LV_BSDF_* */
    float alpha;               /* GGX alpha = roughness^2; 0 means smooth */
    float ior;                 /* dielectric index of refraction */
    float specular;            /* KHR_materials_specular factor (scales Fresnel) */
    lv_u32 double_sided;
    float attenuation[3];      /* absorption coefficient per metre inside glass */
    float pad;
} lv_material;

/* A texture: width x height RGBA8 texels (sRGB-encoded colour) at `offset`
 * texels into the shared texel buffer. */
typedef struct {
    lv_u32 offset;
    lv_u32 width;
    lv_u32 height;
    lv_u32 pad;
} lv_texture;

/* One light (an emissive triangle or a punctual light), for light sampling.
 * Lights are chosen with probability proportional to their power. */
#define LV_LIGHT_AREA 0
#define LV_LIGHT_PUNCTUAL 1

typedef struct {
    lv_u32 kind;       /* LV_LIGHT_AREA or LV_LIGHT_PUNCTUAL */
    lv_u32 index;      /* leaf-ordered triangle index, or punctual light index */
    lv_u32 instance;   /* the instance an area light's triangle belongs to */
    float cdf;         /* cumulative selection probability up to and including this light */
    float pdf_select;  /* probability of choosing this light */
    lv_u32 pad;
} lv_light;

#define LV_PUNCTUAL_POINT 0
#define LV_PUNCTUAL_SPOT 1

typedef struct {
    float position[3];
    lv_u32 type;
    float direction[3];   /* spot axis, unit */
    float cos_outer;
    float intensity[3];   /* radiant intensity, W/sr */
    float cos_inner;
} lv_punctual_light;

/* The pinhole camera: a ray through pixel (x, y) of a W x H image has
 * direction normalize(forward + sx * right + sy * up), with
 * sx = (2 (x + u) / W - 1) and sy = (1 - 2 (y + v) / H); right and up are
 * already scaled by the image-plane half extents. */
typedef struct {
    float origin[3];
    lv_u32 width;
    float forward[3];
    lv_u32 height;
    float right[3];
    float pad0;
    float up[3];
    float pad1;
} lv_camera;

/* Buffers each of the large scene tables (BVH nodes, triangles, vertex
 * attributes) may be split over, each within the device's largest
 * allocation. */
#define LV_SCENE_PARTS 4

/* Everything a kernel needs to know about the scene besides its buffers. */
typedef struct {
    lv_u32 triangle_count;
    lv_u32 light_count;
    lv_u32 max_depth;
    lv_u32 seed;
    float total_light_power; /* summed over lights (luminance of RGB watts) */
    float scene_scale;       /* largest extent of the scene bounds, metres */
    lv_u32 instance_count;
    lv_u32 flat;             /* one instance, identity transform: rays skip the top level */
    /* Elements per buffer of the tables split over LV_SCENE_PARTS buffers
     * (kernels/scene.h); 0xffffffff where one buffer holds them all. */
    lv_u32 nodes_per_part;
    lv_u32 triangles_per_part; /* tri_vertices and triangles */
    lv_u32 vertices_per_part;  /* normals and uvs */
    lv_u32 pad;
} lv_scene_info;

/* The light volume (DESIGN.md section 1): a regular grid of cubic cells
 * over the scene bounds; each stored cell holds 2 n^2 directional bins of
 * RGB tallies, 64-bit fixed point (LV_TALLY_SCALE units per unit). A tally
 * accumulates (particle weight / particle count) x (track length / cell
 * size), where a particle's weight is its power over the total emitted
 * power; radiance follows as total_power x tally x cell_size / (V x bin
 * solid angle), with V the cell's lit volume. */
#define LV_EMPTY_CELL 0xffffffffu
#define LV_TALLY_SCALE 1099511627776.0f /* 2^40 */
/* Largest single contribution accepted, in tally units of 1: with it every
 * bin stays far below 2^63 (see docs/light-volume.md). */
#define LV_TALLY_MAX_CONTRIBUTION 1048576.0f

typedef struct {
    float origin[3];   /* corner of cell (0,0,0) */
    float cell_size;   /* metres */
    lv_u32 dims[3];    /* cells along x, y, z */
    lv_u32 dirs;       /* n: n x n bins per hemisphere */
    lv_u32 slot_count; /* cells stored */
    lv_u32 bins;       /* 2 n^2 */
    float total_power; /* luminance watts emitted by all lights */
    float particles;   /* particles traced in all (for normalisation) */
    lv_u32 subcells;   /* k: k x k x k binary subcells per cell (k <= 4), 0 = none */
    lv_u32 slots_per_part; /* the tallies are split over buffers of this many slots each */
    float visibility_rate; /* share of tallied surface hits that cast a subcell visibility ray */
    lv_u32 pad;
} lv_grid_info;

/* Buffers the tallies may be split over, each within the device's largest
 * allocation (slot s lies in buffer s / slots_per_part). */
#define LV_TALLY_PARTS 4

/* Subcell records, LV_SUBCELL_STRIDE 32-bit words per stored cell: a mask
 * of two words (bit x + k (y + k z) is switched on when a tallied segment
 * passes subcell (x, y, z); k^3 <= 64), then per subcell the visibility rays
 * cast from it, those that were not blocked, and a lit point: 8 bits of
 * priority (1-255), then a position in the subcell that light reached, 8
 * bits per axis; 0 if no particle hit a surface there. */
#define LV_SUBCELL_MAX 64
#define LV_SUBCELL_CAST 2
#define LV_SUBCELL_OPEN (2 + LV_SUBCELL_MAX)
#define LV_SUBCELL_LIT_POINT (2 + 2 * LV_SUBCELL_MAX)
#define LV_SUBCELL_STRIDE (2 + 3 * LV_SUBCELL_MAX)

#endif
