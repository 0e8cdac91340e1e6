/* Types shared by the host (C11) and the kernels (OpenCL C 1.2).
 *
 * Only 32-bit scalars and fixed arrays of them: no vector types, whose size
 * and alignment differ between C and OpenCL C. Every struct is a multiple of
 * 16 bytes but lv_light (24); host/device/layout_checks.c checks the sizes.
 *
 * The end of this file is the host/kernel contract: every buffer table and
 * every kernel's argument list, each declared once as an X-macro list.
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

/* A node of the kernels' 4-wide BVH (host/accel/bvh_wide.c collapses the
 * binary build into it), in depth-first order, root first. The four child
 * boxes are stored axis by axis, so one float4 load gives one bound of all
 * four and the slab test runs on all of them at once. Child i is:
 *   count[i] == 0: an interior node, at `index[i]`;
 *   count[i] > 0: a leaf of count[i] items from `index[i]`: instances (in
 *     the instance array) in the top-level tree, which starts at node 0;
 *     triangles (in the leaf-ordered triangle arrays) in a mesh's tree;
 *   count[i] == LV_EMPTY_CHILD: nothing (its box is never tested as hit).
 * Indices are absolute. A node of a tree too deep for the traversal stack
 * at width 4 uses two lanes only (lvcl_pack_scene). */
#define LV_BVH_WIDTH 4
#define LV_EMPTY_CHILD (-1)
/* Entries of the kernels' traversal stack (kernels/bvh/traverse.h); the
 * host checks every tree against it. */
#define LV_TRAVERSAL_STACK 128

typedef struct {
    float lo[3][LV_BVH_WIDTH]; /* lo[axis][child] */
    float hi[3][LV_BVH_WIDTH];
    lv_i32 index[LV_BVH_WIDTH];
    lv_i32 count[LV_BVH_WIDTH];
} lv_wide_node;

/* The triangles' object-space corners, in BVH leaf order, four at a time:
 * group g holds triangles 4g .. 4g + 3 as 9 float4, corner by corner and
 * axis by axis (v0.x of the four, v0.y, v0.z, v1.x, ... v2.z), so that the
 * ray-triangle test runs on four triangles at once. A group may hold
 * triangles of two leaves or meshes; a test takes the lanes of its leaf. */
#define LV_TRI_GROUP 4

/* Per triangle, in BVH leaf order: where its attributes live and what it is. */
typedef struct {
    lv_u32 v[3];     /* indices into the vertex attribute arrays */
    lv_u32 material; /* index into the material array */
    lv_u32 prim_id;  /* global triangle index in glTF order (checksums) */
    lv_u32 light;    /* emitters: which of its mesh's emitting triangles (the light
                         table holds them per instance from lv_instance.light_base), else LV_NO_LIGHT */
    lv_u32 flags;    /* LV_TRI_* */
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

/* BSDF families (docs/design.md, Kernels); the host maps glTF materials here. */
#define LV_BSDF_DIFFUSE 0    /* Lambertian */
#define LV_BSDF_PLASTIC 1    /* diffuse base under a dielectric GGX (or smooth) layer */
#define LV_BSDF_CONDUCTOR 2  /* GGX or smooth metal, Schlick Fresnel with F0 = base colour */
#define LV_BSDF_GLASS 3      /* solid dielectric, smooth or GGX, Beer-Lambert inside */
#define LV_BSDF_THIN_GLASS 4 /* thin-walled dielectric: reflection, straight transmission */
#define LV_BSDF_COUNT 5

/* lv_material.texture_sampling, glTF's sampler: a wrap mode for u (bits
 * 0-1) and for v (bits 2-3), and nearest filtering instead of bilinear. */
#define LV_WRAP_REPEAT 0u
#define LV_WRAP_CLAMP 1u
#define LV_WRAP_MIRROR 2u
#define LV_WRAP_V_SHIFT 2u
#define LV_TEXTURE_NEAREST 16u

typedef struct {
    float base_color[3];
    lv_i32 base_color_texture; /* index into lv_texture table, -1 if none */
    float emission[3];         /* emitted radiance, W m^-2 sr^-1, front face */
    lv_u32 bsdf;               /* LV_BSDF_* */
    float alpha;               /* GGX alpha = roughness^2; 0 means smooth */
    float ior;                 /* dielectric index of refraction */
    float specular;            /* KHR_materials_specular factor (scales Fresnel) */
    lv_u32 double_sided;
    float attenuation[3];    /* absorption coefficient per metre inside glass */
    lv_u32 texture_sampling; /* how the base colour texture is read: LV_WRAP_* per axis, LV_TEXTURE_NEAREST */
    /* The base colour texture is read at (u', v') = (t0 u + t1 v + t2,
     * t3 u + t4 v + t5): KHR_texture_transform, or the identity. */
    float uv_transform[6];
    float pad2[2];
} lv_material;

/* A texture: width x height RGBA16 texels at `offset` texels into the
 * shared texel buffer: linear colour, decoded from glTF's sRGB by the host
 * (host/device/packed_scene.c), so that bilinear filtering blends light,
 * not encoded values, as a GPU's sRGB textures do. */
typedef struct {
    lv_u32 offset;
    lv_u32 width;
    lv_u32 height;
    lv_u32 pad;
} lv_texture;

/* One light (an emissive triangle or a punctual light), for light sampling.
 * pdf_select mixes the light's power share with an even share per emissive
 * material (host/device/packed_scene.c, LVCL_EVEN_LIGHT_SHARE). */
#define LV_LIGHT_AREA 0
#define LV_LIGHT_PUNCTUAL 1

typedef struct {
    lv_u32 kind;      /* LV_LIGHT_AREA or LV_LIGHT_PUNCTUAL */
    lv_u32 index;     /* leaf-ordered triangle index, or punctual light index */
    lv_u32 instance;  /* the instance an area light's triangle belongs to */
    float cdf;        /* cumulative selection probability up to and including this light */
    float pdf_select; /* probability of choosing this light */
    lv_u32 group;     /* its emissive material's or punctual light's number among them, from 0 */
} lv_light;

#define LV_PUNCTUAL_POINT 0
#define LV_PUNCTUAL_SPOT 1
#define LV_PUNCTUAL_DIRECTIONAL 2 /* a sun: parallel light from beyond the scene */

typedef struct {
    float position[3]; /* (directional: unused) */
    lv_u32 type;
    float direction[3]; /* spot axis, or the way a directional light's light travels; unit */
    float cos_outer;
    float intensity[3]; /* radiant intensity, W/sr; directional: irradiance on a surface facing it, W/m^2 */
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
    lv_u32 flat; /* one instance, identity transform: rays skip the top level */
    /* Elements per buffer of the tables split over LV_SCENE_PARTS buffers
     * (kernels/scene_buffers.h); 0xffffffff where one buffer holds them all. */
    lv_u32 nodes_per_part;
    lv_u32 triangles_per_part; /* triangles */
    lv_u32 vertices_per_part;  /* normals and uvs */
    lv_u32 groups_per_part;    /* tri_groups */
    /* The sphere round the scene bounds: a directional light's particles
     * set out from a disc of this radius in front of it. */
    float bounds_centre[3];
    float bounds_radius;
} lv_scene_info;

/* The light volume (paper section 4): a regular grid of cubic cells
 * over the scene bounds; each stored cell holds 2 n^2 directional bins of
 * RGB tallies, 64-bit fixed point (LV_TALLY_SCALE units per unit). A tally
 * accumulates particle weight x (track length / cell size), where a
 * particle's weight is its power over the total emitted power; radiance
 * follows as total_power x tally x cell_size / (particles x V x bin solid
 * angle), with V the cell's lit volume. The particle count enters only
 * there, so passes of particles add to the same tallies. */
#define LV_EMPTY_CELL 0xffffffffu
/* Set in cell_slot where the cell has planes (docs/light-volume.md,
 * "Regions"); the low 31 bits are its first slot. A cell without planes
 * never reads the region table. */
#define LV_CUT_CELL 0x80000000u
#define LV_TALLY_SCALE 16777216.0f /* 2^24 */
/* The mean tally (units of one) that one particle's piece of segment adds
 * to a cell's bins, per channel: a weight near one (power over total
 * power, kept near one by the BSDF weights and Russian roulette) times the
 * mean chord of a cube, 2/3 of its side. Tallies over it count pieces;
 * adaptive cells take a bin's variance as this times its tally, as if its
 * pieces were alike; the guide trusts a cell by its pieces. */
#define LV_PIECE_TALLY 0.67f
/* A tally set: its bins' RGB tallies (bin b's at 3b), then its axis
 * corrections, LV_AXES of them after the last bin (after the 2 (2n)^2 bins
 * of a set of fine bins, which takes four sets' room). Per axis normal
 * (+x, -x, +y, -y, +z, -z, lv_axis_normal's order), over the pieces of
 * concentrated light (volume/tally.h) that reach a surface facing that
 * way: their luminance times their own cosine to the normal, minus the same
 * times the mean cosine their bin is read with. Signed. A bin's mean cosine
 * assumes its light spread evenly over the bin; a lamp seen through glass
 * is not, and the corrections make a Lambertian surface facing along an
 * axis gather its luminance exactly (docs/light-volume.md, "Axis corrections"). */
#define LV_AXES 6
/* Then the set's lobe of concentrated light, LV_LOBE_LONGS after the axis
 * corrections: over the same pieces, their luminance times their direction
 * of travel (x, y, z; signed), and their luminance. Its mean direction and
 * spread give guided paths a narrow lobe toward a lamp's image in a mirror
 * or through glass, far smaller than a bin (docs/guided.md, "The lobe"). */
#define LV_LOBE_LONGS 4
/* The lobe's luminance, among its LV_LOBE_LONGS. */
#define LV_LOBE_LUMINANCE 3
#define LV_SET_LONGS(bins) (3 * (size_t)(bins) + LV_AXES + LV_LOBE_LONGS)
/* Largest single contribution accepted, in tally units of 1 (2^36 units):
 * 2^32 particles of weight below 32 cannot overflow a bin (see
 * docs/light-volume.md). */
#define LV_TALLY_MAX_CONTRIBUTION 4096.0f

typedef struct {
    float origin[3];       /* corner of cell (0,0,0) */
    float cell_size;       /* metres */
    lv_u32 dims[3];        /* cells along x, y, z */
    lv_u32 dirs;           /* n: n x n bins per hemisphere */
    lv_u32 slot_count;     /* region slots stored (a cell cut by P planes holds 2^P) */
    lv_u32 bins;           /* 2 n^2 */
    float total_power;     /* luminance watts emitted by all lights */
    float particles;       /* particles traced in all (for normalisation) */
    lv_u32 subcells;       /* k: k x k x k binary subcells per cell (k <= 4), 0 = none */
    lv_u32 slots_per_part; /* the tallies are split over buffers of this many tally sets each */
    float visibility_rate; /* share of tallied surface hits that cast a subcell visibility ray */
    lv_u32 tally_sets;     /* tally sets stored (LV_SET_LONGS): the cells of a merged block share one */
} lv_grid_info;

/* Regions of a cut cell (docs/light-volume.md, "Regions"): a stored cell
 * that up to LV_GEOMETRY_PLANES planes of its geometry cut, and a refined
 * cell (its middle planes beside those, up to LV_REGION_PLANES in all),
 * holds one slot per region: per sign pattern of its planes whose region
 * has volume, consecutive slots from the cell's first. The cell's planes
 * are kept once, in its lv_cell_cut (n, c: a point u in cell units from
 * the cell's corner is on the positive side of plane i if n_i . u > c_i,
 * and its sign pattern m has bit i set where it is), with their count P
 * and the slot of each pattern (LV_REGION_OFFSET). Per slot, an
 * lv_slot_region: the cell's first slot, its cut (LV_NO_CUT for a cell
 * without planes, whose one region is all of it), which pattern this slot
 * is, where its shares start in the region_shares table (the region's
 * volume as a fraction of the cell, then per entry, a subcell the region
 * has volume in, the fraction of the subcell inside the region: exact,
 * from volume_shares.c; LV_NO_SHARES for a cell without planes), its
 * flags, and which subcells are its entries and where they start (the
 * subcell records below). A pattern whose region has no volume in the
 * cell (3 planes leave at most 7 of 8) gets no slot of its own: its points
 * (on a boundary, by rounding) read a neighbouring region's. (Each slot
 * once repeated its cell's planes and offsets: 192 bytes a slot, 4.4 MB of
 * the kitchen's volume.) */
#define LV_GEOMETRY_PLANES 3
#define LV_REGION_PLANES 6
#define LV_NO_SHARES 0xffffffffu
#define LV_NO_CUT 0xffffffffu
/* lv_slot_region.flags. HALF_BOX: a cell refinement split where its light
 * is focused; lookups jitter in half a cell. MIXED: the cell's planes do
 * not keep the two sides of one of its surfaces apart in this region (a
 * curved wall thinner than its bend across the cell, a fourth surface), so
 * its tallies may hold light of both sides and no lookup reads it
 * (host/render/volume_planes.c, mixed_patterns). */
#define LV_REGION_HALF_BOX 1u
#define LV_REGION_MIXED 2u

typedef struct {
    float planes[LV_REGION_PLANES][4];
    lv_u32 plane_count;                          /* P */
    lv_u32 offsets[(1 << LV_REGION_PLANES) / 4]; /* pattern m's slot - the cell's first slot, 8 bits each */
} lv_cell_cut;

typedef struct {
    lv_u32 base_slot;  /* the cell's first slot */
    lv_u32 cut;        /* the cell's lv_cell_cut, or LV_NO_CUT */
    lv_u32 region;     /* its pattern */
    lv_u32 shares;     /* first entry in region_shares, or LV_NO_SHARES */
    lv_u32 flags;      /* LV_REGION_* */
    lv_u32 present[2]; /* the subcells the region has volume in (bit i: subcell i, as the marks) */
    lv_u32 entries;    /* its first entry in subcell_rays and lit_points */
} lv_slot_region;

/* The slot of pattern m of a cell with cut *c, from the cell's first slot. */
#define LV_REGION_OFFSET(c, m) ((c)->offsets[(m) >> 2] >> (8u * ((m)&3u)) & 255u)

/* Buffers the tallies may be split over, each within the device's largest
 * allocation (tally set t lies in buffer t / slots_per_part). Slot s keeps
 * its tallies in set tally_slot[s]: its own, or, in a block of cells that
 * the adaptive grid merged (docs/light-volume.md, "Adaptive cells"), the
 * block's. */
#define LV_TALLY_PARTS 4
/* Set in tally_slot[s]: the set holds fine bins, 2n x 2n per hemisphere
 * (one level down the quadtree over each hemisphere's square; bin (i, j)
 * of n x n covers fine bins (2i..2i+1, 2j..2j+1)), in four consecutive
 * sets' room of one buffer (docs/light-volume.md, "Refined cells and directions"). */
#define LV_FINE_DIRS 0x80000000u
/* Set in tally_slot[s]: the slot's tallies restarted when the volume was
 * refined, and the trace's retrace of the particles before that fills
 * them alone (lv_particle_trace's restarted_only). */
#define LV_RESTARTED 0x40000000u
/* tally_slot[s]'s set, without the flags. */
#define LV_TALLY_SET_OF(t) ((t) & ~(LV_FINE_DIRS | LV_RESTARTED))

/* Subcell records, in three buffers. subcell_marks: two words per slot, a
 * mask (bit x + k (y + k z) is switched on when a tallied segment passes
 * subcell (x, y, z); k^3 <= 64). Then per entry, a subcell that the slot's
 * region has volume in (lv_slot_region.present; every subcell of a cell
 * without planes): subcell_rays, two words (the visibility rays cast from
 * it, those that were not blocked), and lit_points, one word (a lit point:
 * 8 bits of priority (1-255), then a position in the subcell that light
 * reached, 8 bits per axis; 0 if no particle hit a surface there). A slot's
 * entries follow each other in subcell order from lv_slot_region.entries,
 * so a cut cell's regions keep records of their own subcells only. */
#define LV_SUBCELL_MAX 64
#define LV_MARK_WORDS 2
#define LV_RAY_WORDS 2
#define LV_NO_ENTRY 0xffffffffu
#ifdef __OPENCL_C_VERSION__
#define LV_POPCOUNT(x) popcount(x)
#else
#define LV_POPCOUNT(x) ((lv_u32)__builtin_popcount(x))
#endif
/* The entries of a presence mask {lo, hi} below subcell i (0 <= i < 64). */
#define LV_ENTRIES_BELOW(lo, hi, i)                     \
    ((i) < 32u ? LV_POPCOUNT((lo) & ((1u << (i)) - 1u)) \
               : LV_POPCOUNT(lo) + LV_POPCOUNT((hi) & ((1u << ((i)-32u)) - 1u)))

/* The bin table (lv_bin_table; kernels/volume/direction_map.h), floats.
 * First, for each group of LV_BIN_GROUP consecutive bins (the last one
 * padded with zeros), LV_BIN_GROUP_FLOATS floats read for every bin, one
 * vector of the group's values each: the x, y and z of the bins' central
 * directions, the sines of their angular radii, and the x, y and z of the
 * means of their unit directions. Then LV_BIN_EDGE_FLOATS per bin, read
 * only for bins that a horizon may cut: the x, y and z components of eight
 * points of its edge (the square's corners and the middles of its sides),
 * and those of the centres of its LV_BIN_SUBDIRS equal-area parts. */
#define LV_BIN_GROUP 16
#define LV_BIN_GROUP_FLOATS (7 * LV_BIN_GROUP)
#define LV_BIN_EDGE_POINTS 8
#define LV_BIN_SUBDIR_SIDE 4
#define LV_BIN_SUBDIRS (LV_BIN_SUBDIR_SIDE * LV_BIN_SUBDIR_SIDE)
#define LV_BIN_EDGE_FLOATS (3 * (LV_BIN_EDGE_POINTS + LV_BIN_SUBDIRS))
#define LV_BIN_GROUPS(bins) (((bins) + LV_BIN_GROUP - 1) / LV_BIN_GROUP)
#define LV_BIN_TABLE_FLOATS(bins) (LV_BIN_GROUPS(bins) * LV_BIN_GROUP_FLOATS + (bins)*LV_BIN_EDGE_FLOATS)

/* Numbers of a camera sample drawn from the pixel's lattice, and the
 * lattice's generator in 32-bit fixed point (kernels/util/rng.h). */
#define LV_LATTICE_DIMS 12
#define LV_LATTICE_GENERATORS                                                                                   \
    {                                                                                                           \
        0xf22eecf6u, 0xe51cc09bu, 0xd8bf2d50u, 0xcd0c73d0u, 0xc1fb5b84u, 0xb7832b3bu, 0xad9ba24du, 0xa43cf216u, \
            0x9b5fb7d3u, 0x92fcf6cau, 0x8b0e12ceu, 0x838ccb04u                                                  \
    }

/* A 32-bit integer hash with good avalanche (a xorshift-multiply chain):
 * the kernels' random numbers (kernels/util/rng.h) and the dither of
 * adaptive sampling's plan on the host (host/render/adaptive_sampling.c). */
#ifdef __OPENCL_C_VERSION__
inline lv_u32 lv_hash(lv_u32 x)
#else
static inline lv_u32 lv_hash(lv_u32 x)
#endif
{
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}

/* Luminance of linear RGB (Rec. 709 weights): light power, light selection
 * and the volume's normalisation use it on both sides. */
#define LV_LUMINANCE(r, g, b) (0.2126f * (r) + 0.7152f * (g) + 0.0722f * (b))

/* lv_gather_pass's `flags`. */
#define LV_GATHER_ALL 1u         /* the volume holds all light, emitted too: no shadow rays */
#define LV_GATHER_INTEGRATE 2u   /* integrate the BSDF over every bin instead of sampling one */
#define LV_GATHER_SEE_THROUGH 4u /* shadow rays go on through glass; the volume leaves that light out */

/* ======== The host/kernel contract ========
 *
 * Each table below is the one declaration of a set of buffers or of a
 * kernel's arguments, in argument order. kernels/scene_buffers.h expands them into
 * kernel parameter lists and the structs the kernels open; the host
 * (host/device/kernel_args.h) into its buffer structs, the scene upload and
 * the argument binders; the enums here give every argument's index. */

/* The storage of OpenCL vector types, as both sides see it (16 and 8 bytes). */
#ifdef __OPENCL_C_VERSION__
typedef float4 lv_float4;
typedef ushort4 lv_ushort4;
#else
typedef struct {
    float s[4];
} lv_float4;
typedef struct {
    uint16_t s[4];
} lv_ushort4;
#endif

/* The scene's buffers, read-only, in argument order (then lv_scene_info):
 *   SPLIT(type, name, stride, per_part, what): `stride` values of `type` per
 *     element, split over LV_SCENE_PARTS buffers of lv_scene_info.per_part
 *     elements each (kernels/scene_buffers.h reads them with LV_SPLIT_AT);
 *   ONE(type, name, what): one buffer.
 * `what` names the table in the host's messages. */
#define LV_SCENE_BUFFERS(SPLIT, ONE)                                                                              \
    SPLIT(lv_wide_node, nodes, 1, nodes_per_part, "BVH nodes")            /* top-level tree, then every mesh's */ \
    ONE(lv_instance, instances, "instances")                              /* top-level leaf order */              \
    SPLIT(lv_float4, tri_groups, 9, groups_per_part, "triangle vertices") /* LV_TRI_GROUP corners each */         \
    SPLIT(lv_triangle, triangles, 1, triangles_per_part, "triangles")     /* leaf order */                        \
    SPLIT(float, normals, 3, vertices_per_part, "normals")                                                        \
    SPLIT(float, uvs, 2, vertices_per_part, "texture coordinates")                                                \
    ONE(lv_material, materials, "materials")                                                                      \
    ONE(lv_texture, textures, "textures")                                                                         \
    ONE(lv_ushort4, texels, "texels")                                                                             \
    ONE(lv_light, lights, "lights")                                                                               \
    ONE(lv_punctual_light, punctuals, "punctual lights")

/* The light volume's buffers, in argument order (then lv_grid_info):
 * SPLIT(type, name) over LV_TALLY_PARTS buffers of lv_grid_info.slots_per_part
 * slots, ONE(type, name) in one buffer. */
#define LV_VOLUME_BUFFERS(SPLIT, ONE)                                                            \
    ONE(const uint, cell_slot)         /* cell -> first slot (| LV_CUT_CELL) or LV_EMPTY_CELL */ \
    ONE(const lv_slot_region, regions) /* per slot: its region of its cell */                    \
    ONE(const lv_cell_cut, cuts)       /* per cut cell: its planes */                            \
    ONE(const uint, tally_slot)        /* per slot: its tally set */                             \
    ONE(const float, region_shares)    /* per slot of a cut cell: 1 + its entries */             \
    SPLIT(long, tallies)               /* tally set x bin x RGB, 64-bit fixed point */           \
    ONE(uint, subcell_marks)           /* LV_MARK_WORDS per slot */                              \
    ONE(uint, subcell_rays)            /* LV_RAY_WORDS per subcell entry */                      \
    ONE(uint, lit_points)              /* one per subcell entry */                               \
    ONE(float, lit_volume)             /* per slot, filled by lv_lit_volumes */

#define LV_IGNORE_SPLIT(type, name, stride, per_part, what)
#define LV_IGNORE_ONE(type, name, what)

/* Argument indices within the scene's and the volume's blocks. */
#define LV_SCENE_INDEX_SPLIT(type, name, stride, per_part, what) \
    lv_scene_arg_##name, lv_scene_arg_##name##_end = lv_scene_arg_##name + LV_SCENE_PARTS - 1,
#define LV_SCENE_INDEX_ONE(type, name, what) lv_scene_arg_##name,
enum { LV_SCENE_BUFFERS(LV_SCENE_INDEX_SPLIT, LV_SCENE_INDEX_ONE) lv_scene_arg_info, LV_SCENE_ARG_COUNT };

#define LV_VOLUME_INDEX_SPLIT(type, name) \
    lv_volume_arg_##name, lv_volume_arg_##name##_end = lv_volume_arg_##name + LV_TALLY_PARTS - 1,
#define LV_VOLUME_INDEX_ONE(type, name) lv_volume_arg_##name,
enum { LV_VOLUME_BUFFERS(LV_VOLUME_INDEX_SPLIT, LV_VOLUME_INDEX_ONE) lv_volume_arg_info, LV_VOLUME_ARG_COUNT };

/* Values per element of each scene table (lv_scene_stride_nodes, ...). */
#define LV_SCENE_STRIDE_SPLIT(type, name, stride, per_part, what) lv_scene_stride_##name = stride,
enum { LV_SCENE_BUFFERS(LV_SCENE_STRIDE_SPLIT, LV_IGNORE_ONE) lv_scene_stride_end_ };

/* Kernel argument lists, one entry per argument in order:
 *   X(kernel, kind, type, name), with SEP() between entries,
 * kind: SCENE (the scene block above), VOLUME (the volume block), VALUE
 * (passed by value: type is valid on both sides) or BUFFER (a __global
 * pointer to type). SEP is a function-like macro (LV_SEP_COMMA,
 * LV_SEP_NONE), so that lists can pass it on to the lists they include. */
#define LV_SEP_COMMA() ,
#define LV_SEP_NONE()

/* The lists are laid out one argument a line by hand; the formatter would
 * fold them. */
/* clang-format off */

/* The camera passes' pixel arguments. A launch takes one sample of each
 * of the pixels pixel_list[first_pixel .. first_pixel + pixel_count); a
 * pixel's sample index is first_sample plus the samples its sum holds, so
 * pixels may hold different counts (adaptive sampling,
 * host/render/image_pass.c). sum_sq adds the square of each sample's
 * channel mean, for the pixel's variance. */
#define LV_PIXEL_ARGS(X, SEP, kernel)                \
    X(kernel, VALUE, lv_camera, camera) SEP()        \
    X(kernel, BUFFER, const uint, pixel_list) SEP()  \
    X(kernel, VALUE, lv_u32, first_pixel) SEP()      \
    X(kernel, VALUE, lv_u32, pixel_count) SEP()      \
    X(kernel, VALUE, lv_u32, first_sample) SEP()     \
    X(kernel, BUFFER, float4, sum) SEP()             \
    X(kernel, BUFFER, float, sum_sq)

#define LV_PT_PASS_ARGS(X, SEP)                   \
    X(lv_pt_pass, SCENE, , scene) SEP()           \
    X(lv_pt_pass, VALUE, lv_u32, see_through) SEP() /* light samples go on through glass */ \
    LV_PIXEL_ARGS(X, SEP, lv_pt_pass)

#define LV_GATHER_PASS_ARGS(X, SEP)                                    \
    X(lv_gather_pass, SCENE, , scene) SEP()                            \
    X(lv_gather_pass, VOLUME, , volume) SEP()                          \
    X(lv_gather_pass, BUFFER, const float, bin_table) SEP()       \
    X(lv_gather_pass, BUFFER, const float, fine_bin_table) SEP()  /* the bin table of 2n x 2n */ \
    X(lv_gather_pass, BUFFER, const float, axis_sums) SEP()       /* lv_axis_sums's */ \
    X(lv_gather_pass, VALUE, lv_u32, flags) SEP()     /* LV_GATHER_* */ \
    X(lv_gather_pass, VALUE, float, threshold) SEP()  /* near-hit distance, metres */ \
    LV_PIXEL_ARGS(X, SEP, lv_gather_pass)

#define LV_GUIDED_PASS_ARGS(X, SEP)                                   \
    X(lv_guided_pass, SCENE, , scene) SEP()                           \
    X(lv_guided_pass, VOLUME, , volume) SEP()                         \
    X(lv_guided_pass, BUFFER, const float, bin_table) SEP()      \
    X(lv_guided_pass, BUFFER, const float, fine_bin_table) SEP() /* the bin table of 2n x 2n */ \
    X(lv_guided_pass, BUFFER, const float, guide_table) SEP()    /* lv_guide_table's */ \
    X(lv_guided_pass, VALUE, lv_u32, see_through) SEP()          /* as lv_pt_pass's */ \
    LV_PIXEL_ARGS(X, SEP, lv_guided_pass)

/* Fills the guide table: per tally set and bin, the luminance of its
 * tallies (volume/guide.h), laid out as the tallies are, then
 * LV_BIN_GROUP floats of padding, then per tally set the sum and the
 * largest of its bins' (from LV_GUIDE_STATS_AT), then per tally set its
 * lobe (from LV_GUIDE_LOBES_AT): the mean direction of travel of its
 * concentrated light (its length the mean resultant length) and that
 * light's luminance. */
#define LV_GUIDE_STATS_AT(info) ((size_t)(info).tally_sets * (info).bins + LV_BIN_GROUP)
#define LV_GUIDE_LOBES_AT(info) (LV_GUIDE_STATS_AT(info) + 2 * (size_t)(info).tally_sets)
#define LV_GUIDE_TABLE_FLOATS(info) (LV_GUIDE_LOBES_AT(info) + 4 * (size_t)(info).tally_sets)
#define LV_GUIDE_TABLE_ARGS(X, SEP)              \
    X(lv_guide_table, VOLUME, , volume) SEP()    \
    X(lv_guide_table, VALUE, lv_u32, fine_pass) SEP() /* the second pass: slots of fine bins */ \
    X(lv_guide_table, BUFFER, float, guide_table)

/* The axis sums of the integrating gather (integrator/gather.h): per slot
 * and axis normal (+x, -x, +y, -y, +z, -z), the RGB sum of its set's
 * tallies as a Lambertian surface facing that way gathers them: weighted by
 * the bins' mean cosines, then corrected by the set's axis corrections. */
#define LV_AXIS_SUM_FLOATS (3 * LV_AXES)
#define LV_AXIS_SUMS_ARGS(X, SEP)                                 \
    X(lv_axis_sums, VOLUME, , volume) SEP()                       \
    X(lv_axis_sums, BUFFER, const float, bin_table) SEP()         \
    X(lv_axis_sums, BUFFER, const float, fine_bin_table) SEP()    \
    X(lv_axis_sums, BUFFER, float, axis_sums) /* LV_AXIS_SUM_FLOATS per slot */

#define LV_PARTICLE_TRACE_ARGS(X, SEP)                                                       \
    X(lv_particle_trace, SCENE, , scene) SEP()                                               \
    X(lv_particle_trace, VOLUME, , volume) SEP()                                             \
    X(lv_particle_trace, VALUE, lv_u32, first) SEP()         /* first particle of the batch */ \
    X(lv_particle_trace, VALUE, lv_u32, count) SEP()                                         \
    X(lv_particle_trace, VALUE, lv_u32, store_emitted) SEP() /* lv-all: tally the lights' own segments */ \
    X(lv_particle_trace, VALUE, lv_u32, see_through) SEP() /* leave out lamps seen through glass */ \
    X(lv_particle_trace, VALUE, lv_u32, restarted_only) SEP() /* a retrace: LV_RESTARTED slots' tallies only */ \
    X(lv_particle_trace, BUFFER, const uint, subcells_seen) SEP() /* each slot's masks before the batch */ \
    X(lv_particle_trace, BUFFER, const float, bin_table) SEP()                                \
    X(lv_particle_trace, BUFFER, const float, fine_bin_table) SEP() /* the bin table of 2n x 2n */ \
    X(lv_particle_trace, VALUE, lv_u32, view_groups) SEP() /* a view probe's light groups; 0: none */ \
    X(lv_particle_trace, BUFFER, const uint, view_slots) SEP() /* lv_view_probe (particle_trace.h) */ \
    X(lv_particle_trace, BUFFER, long, view_light) SEP() \
    X(lv_particle_trace, BUFFER, uint, ray_counts)           /* segments, visibility rays */

#define LV_LIT_VOLUMES_ARGS(X, SEP)               \
    X(lv_lit_volumes, VOLUME, , volume)

#define LV_BIN_TABLE_ARGS(X, SEP)            \
    X(lv_bin_table, VALUE, lv_u32, n) SEP()  \
    X(lv_bin_table, BUFFER, float, table)

/* clang-format on */

/* The index of argument `name` of `kernel`: LV_ARG(lv_pt_pass, camera). A
 * block's index is that of its first argument. */
#define LV_ARG(kernel, name) kernel##_arg_##name
#define LV_ARG_INDEX(kernel, kind, type, name) LV_ARG_INDEX_##kind(kernel##_arg_##name)
#define LV_ARG_INDEX_VALUE(id) id
#define LV_ARG_INDEX_BUFFER(id) id
#define LV_ARG_INDEX_SCENE(id) id, id##_end = id + LV_SCENE_ARG_COUNT - 1
#define LV_ARG_INDEX_VOLUME(id) id, id##_end = id + LV_VOLUME_ARG_COUNT - 1
#define LV_ARG_INDICES(LIST, kernel) enum { LIST(LV_ARG_INDEX, LV_SEP_COMMA), kernel##_argument_count }

LV_ARG_INDICES(LV_PT_PASS_ARGS, lv_pt_pass);
LV_ARG_INDICES(LV_GATHER_PASS_ARGS, lv_gather_pass);
LV_ARG_INDICES(LV_GUIDED_PASS_ARGS, lv_guided_pass);
LV_ARG_INDICES(LV_GUIDE_TABLE_ARGS, lv_guide_table);
LV_ARG_INDICES(LV_AXIS_SUMS_ARGS, lv_axis_sums);
LV_ARG_INDICES(LV_PARTICLE_TRACE_ARGS, lv_particle_trace);
LV_ARG_INDICES(LV_LIT_VOLUMES_ARGS, lv_lit_volumes);
LV_ARG_INDICES(LV_BIN_TABLE_ARGS, lv_bin_table);

#endif
