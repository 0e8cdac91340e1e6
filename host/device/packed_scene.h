/* The scene packed into the kernels' layouts (kernels/shared_types.h) on
 * the host: the BVH nodes and triangles in leaf order, the instances, the
 * materials, textures and the light table. */
#ifndef LVCL_PACKED_SCENE_H
#define LVCL_PACKED_SCENE_H

#include "../accel/accel.h"
#include "../accel/bvh_wide.h"
#include "../scene/scene.h"

/* The kernels' arrays, packed on the host (also used by host-side checks). */
typedef struct {
    lv_wide_node *nodes; /* the kernels' trees: the top level, then every mesh's */
    size_t node_count;
    int bvh_width;             /* children per node: LV_BVH_WIDTH, or 2 where that would overflow the traversal stack */
    int stack_need;            /* traversal stack entries the deepest path can hold */
    lvcl_bvh_node *tree_nodes; /* the same trees binary (lvcl_accel.node_count), for walks on the host */
    size_t *mesh_tree_root;    /* each mesh's root in tree_nodes */
    lv_instance *instances;    /* in the top level's leaf order */
    size_t instance_count;
    size_t *mesh_first, *mesh_size; /* each mesh's range of the leaf-ordered triangles */
    size_t mesh_count;
    float *tri_groups; /* object-space corners, LV_TRI_GROUP triangles in 36 floats (kernels/shared_types.h) */
    size_t group_count;
    lv_triangle *triangles; /* leaf order */
    size_t triangle_count;
    lv_material *materials;
    size_t material_count;
    lv_texture *textures;
    size_t texture_count;
    lv_ushort4 *texels; /* linear RGBA16 (lv_texture) */
    size_t texel_count;
    lv_light *lights;
    size_t light_count;
    lv_punctual_light *punctuals; /* a punctual light's lv_light.index points here */
    size_t punctual_count;
    float *light_odds; /* each light's pdf_select as packed (lvcl_packed_set_light_odds departs from it) */
    lv_scene_info info;
    float bounds_min[3], bounds_max[3];
    int lit_from_outside; /* a directional light shines in from beyond the bounds: open space may be lit */
} lvcl_packed_scene;

/* The share of light choices spread evenly over the lights (the triangles
 * of one emissive material together, or one punctual light) rather than by
 * their power: a lamp a thousand times dimmer than another, alone in its room,
 * still gets a quarter of the particles and light samples (with two
 * lamps), while no light gets less than half its power's share, so where
 * all lights shine into one space the variance grows by at most 2x
 * (docs/light-volume.md, "Which light a particle leaves"). */
#define LVCL_EVEN_LIGHT_SHARE 0.5

/* Sets the lights' odds (pdf_select and cdf) to
 * (1 - keep) w_g / W * q_i / q_g + keep q_i, q_i the odds as packed, w_g
 * the weight of light i's group (lv_light.group; groups of weight 0 get
 * only their share of `keep`), W the weights' sum and q_g the group's
 * packed odds; with `group_weight` NULL, or W 0, the odds as packed.
 * Returns whether any light's odds changed. */
int lvcl_packed_set_light_odds(lvcl_packed_scene *p, const double *group_weight, double keep);
/* The number of light groups (one past the largest lv_light.group). */
size_t lvcl_packed_light_groups(const lvcl_packed_scene *p);

/* Packs scene and its acceleration structure. The packed scene borrows
 * nothing from either. */
lvcl_error lvcl_pack_scene(const lvcl_scene *scene, const lvcl_accel *accel, uint32_t seed, uint32_t max_depth,
                           lvcl_packed_scene *packed, lvcl_status *st);

/* The world-space corners (9 floats) of leaf-ordered triangle tri as
 * placed by instance `instance`. */
void lvcl_packed_triangle_world(const lvcl_packed_scene *p, size_t instance, size_t tri, float v[9]);
/* Walks every instance's binary tree depth first, each node's box placed
 * in the world: enter(ctx, lo, hi) says whether to go into a node (its
 * children, or a leaf's triangles), and triangle(ctx, v) gets the world
 * corners of each triangle of the leaves entered; it ends the walk by
 * returning nonzero, and then so does the walk (packed_rays.c). */
typedef int (*lvcl_node_filter)(void *ctx, const float lo[3], const float hi[3]);
typedef int (*lvcl_triangle_visitor)(void *ctx, const float v[9]);
int lvcl_packed_walk(const lvcl_packed_scene *p, lvcl_node_filter enter, lvcl_triangle_visitor triangle, void *ctx);

/* The t in (0, len] at which o + t d meets triangle v (world corners,
 * either face), or 0. */
double lvcl_segment_meets_triangle(const float v[9], const double o[3], const double d[3], double len);

/* Whether the segment o + t d, 0 < t <= len (d unit), meets a triangle of
 * the packed scene (a walk of every instance's tree: for the few rays of
 * host-side checks). */
int lvcl_packed_segment_hits(const lvcl_packed_scene *p, const double o[3], const double d[3], double len);
/* The t of the segment's nearest hit, or 0 where it meets nothing (the
 * same walk). */
double lvcl_packed_first_hit(const lvcl_packed_scene *p, const double o[3], const double d[3], double len);

void lvcl_packed_scene_free(lvcl_packed_scene *packed);

#endif
