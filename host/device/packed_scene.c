#include "packed_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "../scene/materials.h"
#include "../util/colour.h"

/* The kernels' luminance (kernels/shared_types.h) of an RGB triple. */
static float luminance(const float c[3])
{
    return LV_LUMINANCE(c[0], c[1], c[2]);
}

/* Area of a triangle given by three world-space corners. */
static float triangle_area(const float v[9])
{
    float e1[3], e2[3];
    for (int k = 0; k < 3; k++) {
        e1[k] = v[3 + k] - v[k];
        e2[k] = v[6 + k] - v[k];
    }
    float n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
    return 0.5f * sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

/* Where corner c's axis k of leaf-ordered triangle tri is stored. */
static size_t corner_at(size_t tri, int c, int k)
{
    return (tri / LV_TRI_GROUP) * 9 * LV_TRI_GROUP + (size_t)(3 * c + k) * LV_TRI_GROUP + tri % LV_TRI_GROUP;
}

void lvcl_packed_triangle_world(const lvcl_packed_scene *p, size_t instance, size_t tri, float v[9])
{
    const lv_instance *in = &p->instances[instance];
    for (int c = 0; c < 3; c++) {
        float object[3];
        for (int k = 0; k < 3; k++) object[k] = p->tri_groups[corner_at(tri, c, k)];
        lvcl_transform_point(in->world_from_object, object, 1.0f, &v[3 * c]);
    }
}

/* Power (luminance watts) of a punctual light: 4 pi I for a point light,
 * the solid angle of its cone (to the middle of the falloff) times I for a
 * spot, and for a directional light its irradiance over the disc its
 * particles leave from (radius: the sphere round the scene bounds). */
static float punctual_power(const lv_punctual_light *l, float radius)
{
    float i = luminance(l->intensity);
    if (l->type == LV_PUNCTUAL_SPOT) return 2.0f * 3.14159265f * (1.0f - 0.5f * (l->cos_inner + l->cos_outer)) * i;
    if (l->type == LV_PUNCTUAL_DIRECTIONAL) return 3.14159265f * radius * radius * i;
    return 4.0f * 3.14159265f * i;
}

/* Numbers each mesh's emitting triangles (lv_triangle.light) and returns
 * how many area lights all instances make. */
static size_t number_emitters(lvcl_packed_scene *p, size_t *emitters_per_mesh)
{
    for (size_t m = 0; m < p->mesh_count; m++) {
        size_t k = 0;
        for (size_t t = p->mesh_first[m]; t < p->mesh_first[m] + p->mesh_size[m]; t++)
            if (luminance(p->materials[p->triangles[t].material].emission) > 0.0f) p->triangles[t].light = (lv_u32)k++;
        emitters_per_mesh[m] = k;
    }
    size_t n = 0;
    for (size_t i = 0; i < p->instance_count; i++) n += emitters_per_mesh[p->instances[i].mesh];
    return n;
}

/* Builds the light table: every instance's emitting triangles and the
 * punctual lights. A light is chosen with probability
 * (1 - e) P_i / P + e P_i / (P_g L), e = LVCL_EVEN_LIGHT_SHARE, where P_i is
 * its power, P the total, P_g its material's (a punctual light's own) and L
 * the number of emissive materials and punctual lights: lamps of different
 * brightness have different materials, and lamps of one material differ
 * only in size, which their power already weighs. */
static lvcl_error build_lights(const lvcl_scene *scene, lvcl_packed_scene *p, lvcl_status *st)
{
    size_t *emitters = calloc(p->mesh_count, sizeof *emitters);
    if (!emitters) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory building the light table");
    size_t n = number_emitters(p, emitters) + scene->punctual_count;
    float *power = malloc((n ? n : 1) * sizeof *power);
    size_t *group = malloc((n ? n : 1) * sizeof *group), groups = p->material_count + scene->punctual_count;
    double *group_power = calloc(groups ? groups : 1, sizeof *group_power);
    p->lights = calloc(n ? n : 1, sizeof *p->lights);
    p->light_odds = malloc((n ? n : 1) * sizeof *p->light_odds);
    p->punctuals = malloc((scene->punctual_count ? scene->punctual_count : 1) * sizeof *p->punctuals);
    size_t *number = malloc((groups ? groups : 1) * sizeof *number); /* lv_light.group of each group */
    if (!power || !group || !group_power || !p->lights || !p->light_odds || !p->punctuals || !number) {
        free(power);
        free(group);
        free(group_power);
        free(number);
        free(emitters);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory building a table of %zu lights", n);
    }
    size_t i = 0;
    for (size_t in = 0; in < p->instance_count; in++) {
        uint32_t m = p->instances[in].mesh;
        p->instances[in].light_base = emitters[m] ? (lv_u32)i : LV_NO_LIGHT;
        if (!emitters[m]) continue;
        for (size_t t = p->mesh_first[m]; t < p->mesh_first[m] + p->mesh_size[m]; t++) {
            if (p->triangles[t].light == LV_NO_LIGHT) continue;
            float v[9];
            lvcl_packed_triangle_world(p, in, t, v);
            p->lights[i].kind = LV_LIGHT_AREA;
            p->lights[i].index = (lv_u32)t;
            p->lights[i].instance = (lv_u32)in;
            group[i] = p->triangles[t].material;
            power[i++] = luminance(p->materials[p->triangles[t].material].emission) * triangle_area(v) * 3.14159265f;
        }
    }
    free(emitters);
    for (size_t k = 0; k < scene->punctual_count; k++) {
        p->punctuals[k] = scene->punctuals[k];
        p->lit_from_outside |= scene->punctuals[k].type == LV_PUNCTUAL_DIRECTIONAL;
        p->lights[i].kind = LV_LIGHT_PUNCTUAL;
        p->lights[i].index = (lv_u32)k;
        group[i] = p->material_count + k;
        power[i++] = punctual_power(&scene->punctuals[k], p->info.bounds_radius);
    }
    p->punctual_count = scene->punctual_count;
    double total = 0;
    for (i = 0; i < n; i++) {
        total += power[i];
        group_power[group[i]] += power[i];
    }
    size_t lit_groups = 0;
    for (size_t g = 0; g < groups; g++) lit_groups += group_power[g] > 0;
    /* Each group's factor on its lights' power, (1 - e) + e P / (P_g L):
     * with one group exactly 1, so such scenes pick by power alone, bit
     * for bit as before. */
    double *factor = group_power;
    for (size_t g = 0; g < groups; g++)
        factor[g] = group_power[g] > 0
            ? (1.0 - LVCL_EVEN_LIGHT_SHARE) + LVCL_EVEN_LIGHT_SHARE * (total / (group_power[g] * (double)lit_groups))
            : 0.0;
    double weight_total = 0;
    for (i = 0; i < n; i++) weight_total += (double)power[i] * factor[group[i]];
    double acc = 0;
    /* The groups numbered from 0 in the order their first light comes. */
    size_t numbered = 0;
    for (size_t g = 0; g < groups; g++) number[g] = SIZE_MAX;
    for (i = 0; i < n; i++)
        if (number[group[i]] == SIZE_MAX) number[group[i]] = numbered++;
    for (i = 0; i < n; i++) {
        double w = (double)power[i] * factor[group[i]];
        acc += w;
        p->lights[i].pdf_select = (float)(w / weight_total);
        p->lights[i].cdf = i + 1 == n ? 1.0f : (float)(acc / weight_total);
        p->lights[i].group = (lv_u32)number[group[i]];
        p->light_odds[i] = p->lights[i].pdf_select;
    }
    free(number);
    p->light_count = total > 0 ? n : 0;
    p->info.light_count = (lv_u32)p->light_count;
    p->info.total_light_power = (float)total;
    if (p->light_count == 0) lvcl_warn("the scene has no lights: the image will be black");
    free(power);
    free(group);
    free(group_power);
    return LVCL_OK;
}

size_t lvcl_packed_light_groups(const lvcl_packed_scene *p)
{
    size_t groups = 0;
    for (size_t i = 0; i < p->light_count; i++)
        if (p->lights[i].group + (size_t)1 > groups) groups = p->lights[i].group + (size_t)1;
    return groups;
}

int lvcl_packed_set_light_odds(lvcl_packed_scene *p, const double *group_weight, double keep)
{
    size_t n = p->light_count, groups = lvcl_packed_light_groups(p);
    double total = 0, *packed_group = calloc(groups ? groups : 1, sizeof *packed_group);
    if (!packed_group) return 0; /* out of memory: the odds stay as they are */
    for (size_t i = 0; i < n; i++) packed_group[p->lights[i].group] += p->light_odds[i];
    for (size_t g = 0; group_weight && g < groups; g++) total += group_weight[g];
    int changed = 0;
    double acc = 0;
    for (size_t i = 0; i < n; i++) {
        double q = p->light_odds[i], w = q;
        if (total > 0 && q > 0) {
            uint32_t g = p->lights[i].group;
            w = (1.0 - keep) * (group_weight[g] / total) * (q / packed_group[g]) + keep * q;
        }
        acc += w;
        float pdf = (float)w, cdf = i + 1 == n ? 1.0f : (float)acc;
        changed |= pdf != p->lights[i].pdf_select || cdf != p->lights[i].cdf;
        p->lights[i].pdf_select = pdf;
        p->lights[i].cdf = cdf;
    }
    free(packed_group);
    return changed;
}

/* A texel of the scene's RGBA8 (sRGB colour, linear alpha) as the kernels
 * read it: linear RGBA16. Decoding before the kernels filter makes a
 * bilinear lookup blend light; blending the encoded values and decoding the
 * blend darkened every edge between two colours (a 50:50 mix of 0 and 255
 * read 0.21 instead of 0.5). */
static lv_ushort4 linear_texel(const uint8_t rgba[4])
{
    lv_ushort4 t;
    for (int k = 0; k < 3; k++) {
        t.s[k] = (uint16_t)lround(lvcl_srgb_to_linear(rgba[k] / 255.0) * 65535.0);
    }
    t.s[3] = (uint16_t)(rgba[3] * 257u);
    return t;
}

/* Copies a binary tree after the nodes already packed, with its indices
 * made absolute. */
static void pack_tree(const lvcl_bvh *b, size_t node_base, size_t leaf_base, lvcl_bvh_node *out)
{
    for (size_t i = 0; i < b->node_count; i++) {
        lvcl_bvh_node n = b->nodes[i];
        n.index += (int32_t)(n.count > 0 ? leaf_base : node_base);
        out[node_base + i] = n;
    }
}

/* Likewise for a wide tree. */
static void pack_wide_tree(const lvcl_wide_bvh *w, size_t node_base, size_t leaf_base, lv_wide_node *out)
{
    for (size_t i = 0; i < w->node_count; i++) {
        lv_wide_node n = w->nodes[i];
        for (int c = 0; c < LV_BVH_WIDTH; c++)
            if (n.count[c] != LV_EMPTY_CHILD) n.index[c] += (lv_i32)(n.count[c] > 0 ? leaf_base : node_base);
        out[node_base + i] = n;
    }
}

/* The mesh's triangles in leaf order after those already packed. */
static void pack_triangles(const lvcl_scene *scene, const lvcl_mesh *mesh, const lvcl_bvh *b, size_t tri_base,
                           lvcl_packed_scene *p)
{
    for (size_t i = 0; i < b->triangle_count; i++) {
        size_t t = mesh->first_triangle + b->tri_order[i], slot = tri_base + i;
        for (int c = 0; c < 3; c++) {
            uint32_t v = scene->indices[3 * t + c];
            for (int k = 0; k < 3; k++) p->tri_groups[corner_at(slot, c, k)] = scene->positions[3 * v + k];
            p->triangles[slot].v[c] = v;
        }
        p->triangles[slot].material = scene->tri_material[t];
        p->triangles[slot].prim_id = (lv_u32)t;
        p->triangles[slot].light = LV_NO_LIGHT;
        p->triangles[slot].flags = scene->tri_flags[t];
    }
}

/* Collapses the top level and every mesh's tree LV_BVH_WIDTH wide, or 2
 * wide where the wider trees could overflow the kernels' traversal stack
 * (a binary path pushes one entry a level, so LVCL_BVH_MAX_DEPTH bounds
 * it), and packs them into p->nodes, leaves at p->mesh_first; mesh_root
 * gets each mesh's root. */
static lvcl_error pack_wide_trees(const lvcl_accel *a, lvcl_packed_scene *p, size_t *mesh_root, lvcl_status *st)
{
    lvcl_wide_bvh top = {0}, *mesh = calloc(a->mesh_count, sizeof *mesh);
    if (!mesh) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for %zu BVHs", a->mesh_count);
    static const int widths[] = {LV_BVH_WIDTH, 2};
    lvcl_error e = LVCL_OK;
    for (size_t w = 0; w < sizeof widths / sizeof widths[0]; w++) {
        if (w > 0) {
            lvcl_wide_bvh_free(&top);
            for (size_t m = 0; m < a->mesh_count; m++) lvcl_wide_bvh_free(&mesh[m]);
        }
        e = lvcl_bvh_widen(&a->top, widths[w], &top, st);
        int mesh_need = 0;
        for (size_t m = 0; m < a->mesh_count && !e; m++) {
            e = lvcl_bvh_widen(&a->mesh_bvh[m], widths[w], &mesh[m], st);
            if (mesh[m].stack_need > mesh_need) mesh_need = mesh[m].stack_need;
        }
        /* Below a top-level leaf: the marker back to the top level, then a mesh. */
        p->stack_need = top.stack_need + 1 + mesh_need;
        p->bvh_width = widths[w];
        if (e || p->stack_need <= LV_TRAVERSAL_STACK) break;
    }
    if (!e && p->stack_need > LV_TRAVERSAL_STACK)
        e = lvcl_fail(st, LVCL_ERR_TOO_LARGE, "the BVH needs %d traversal stack entries, the kernels have %d",
                      p->stack_need, LV_TRAVERSAL_STACK);
    size_t count = top.node_count;
    for (size_t m = 0; m < a->mesh_count; m++) count += mesh[m].node_count;
    /* The traversal names a leaf by its node and lane in a negative int. */
    if (!e && count > (size_t)(INT32_MAX - 2) / LV_BVH_WIDTH)
        e = lvcl_fail(st, LVCL_ERR_TOO_LARGE, "%zu BVH nodes exceed the kernels' 32-bit leaf references", count);
    if (!e && !(p->nodes = malloc(count * sizeof *p->nodes)))
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for %zu BVH nodes", count);
    if (!e) {
        pack_wide_tree(&top, 0, 0, p->nodes);
        size_t node_base = top.node_count;
        for (size_t m = 0; m < a->mesh_count; m++) {
            pack_wide_tree(&mesh[m], node_base, p->mesh_first[m], p->nodes);
            mesh_root[m] = node_base;
            node_base += mesh[m].node_count;
        }
        p->node_count = count;
    }
    lvcl_wide_bvh_free(&top);
    for (size_t m = 0; m < a->mesh_count; m++) lvcl_wide_bvh_free(&mesh[m]);
    free(mesh);
    return e;
}

lvcl_error lvcl_pack_scene(const lvcl_scene *scene, const lvcl_accel *a, uint32_t seed, uint32_t max_depth,
                           lvcl_packed_scene *p, lvcl_status *st)
{
    memset(p, 0, sizeof *p);
    size_t n = a->triangle_count;
    p->tree_nodes = malloc(a->node_count * sizeof *p->tree_nodes);
    p->mesh_tree_root = calloc(a->mesh_count, sizeof *p->mesh_tree_root);
    p->instances = calloc(a->instance_count, sizeof *p->instances);
    p->mesh_first = calloc(a->mesh_count, sizeof *p->mesh_first);
    p->mesh_size = calloc(a->mesh_count, sizeof *p->mesh_size);
    size_t *mesh_root = calloc(a->mesh_count, sizeof *mesh_root);
    p->group_count = (n + LV_TRI_GROUP - 1) / LV_TRI_GROUP;
    p->tri_groups = calloc(p->group_count * 9 * LV_TRI_GROUP, sizeof(float));
    p->triangles = calloc(n, sizeof *p->triangles);
    p->materials = calloc(scene->material_count ? scene->material_count : 1, sizeof *p->materials);
    p->textures = calloc(scene->texture_count ? scene->texture_count : 1, sizeof *p->textures);
    size_t texels = 0;
    for (size_t t = 0; t < scene->texture_count; t++)
        texels += (size_t)scene->textures[t].width * scene->textures[t].height;
    p->texels = calloc(texels ? texels : 1, sizeof *p->texels);
    if (!p->tree_nodes || !p->mesh_tree_root || !p->instances || !p->mesh_first || !p->mesh_size || !mesh_root ||
        !p->tri_groups || !p->triangles || !p->materials || !p->textures || !p->texels) {
        free(mesh_root);
        lvcl_packed_scene_free(p);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory packing %zu triangles", n);
    }

    /* Nodes: the top level first (the kernels start at node 0), then each
     * mesh's tree; triangles mesh after mesh. */
    pack_tree(&a->top, 0, 0, p->tree_nodes);
    size_t node_base = a->top.node_count, tri_base = 0;
    for (size_t m = 0; m < a->mesh_count; m++) {
        const lvcl_bvh *b = &a->mesh_bvh[m];
        pack_tree(b, node_base, tri_base, p->tree_nodes);
        pack_triangles(scene, &a->meshes[m], b, tri_base, p);
        p->mesh_tree_root[m] = node_base;
        p->mesh_first[m] = tri_base;
        p->mesh_size[m] = b->triangle_count;
        node_base += b->node_count;
        tri_base += b->triangle_count;
    }
    p->triangle_count = n;
    p->mesh_count = a->mesh_count;
    lvcl_error e = pack_wide_trees(a, p, mesh_root, st);
    if (e) {
        free(mesh_root);
        lvcl_packed_scene_free(p);
        return e;
    }

    /* Instances in the top level's leaf order (one per leaf). */
    for (size_t slot = 0; slot < a->instance_count; slot++) {
        const lvcl_instance *in = &a->instances[a->top.tri_order[slot]];
        lv_instance *out = &p->instances[slot];
        memcpy(out->world_from_object, in->world_from_object, sizeof out->world_from_object);
        int mirrored;
        lvcl_transform_invert(in->world_from_object, out->object_from_world, &mirrored);
        out->root = (lv_u32)mesh_root[in->mesh];
        out->flags = mirrored ? LV_INSTANCE_MIRRORED : 0u;
        out->mesh = in->mesh;
    }
    free(mesh_root);
    p->instance_count = a->instance_count;

    p->material_count = scene->material_count;
    for (size_t m = 0; m < scene->material_count; m++)
        lvcl_material_from_desc(&scene->materials[m], m, &p->materials[m]);

    p->texture_count = scene->texture_count;
    size_t offset = 0;
    for (size_t t = 0; t < scene->texture_count; t++) {
        const lvcl_texture_data *td = &scene->textures[t];
        size_t count = (size_t)td->width * td->height;
        p->textures[t].offset = (lv_u32)offset;
        p->textures[t].width = td->width;
        p->textures[t].height = td->height;
        for (size_t i = 0; i < count; i++) p->texels[offset + i] = linear_texel(&td->rgba[4 * i]);
        offset += count;
    }
    p->texel_count = texels;

    memcpy(p->bounds_min, a->bounds_min, sizeof p->bounds_min);
    memcpy(p->bounds_max, a->bounds_max, sizeof p->bounds_max);
    float extent = 0.0f, diagonal = 0.0f;
    for (int k = 0; k < 3; k++) {
        float side = p->bounds_max[k] - p->bounds_min[k];
        extent = fmaxf(extent, side);
        diagonal += side * side;
        p->info.bounds_centre[k] = 0.5f * (p->bounds_min[k] + p->bounds_max[k]);
    }
    p->info.bounds_radius = 0.5f * sqrtf(diagonal);
    p->info.triangle_count = (lv_u32)n;
    p->info.max_depth = max_depth;
    p->info.seed = seed;
    p->info.scene_scale = extent > 0.0f ? extent : 1.0f;
    p->info.instance_count = (lv_u32)a->instance_count;
    p->info.flat = a->flat ? 1u : 0u;
    return build_lights(scene, p, st);
}

void lvcl_packed_scene_free(lvcl_packed_scene *p)
{
    free(p->nodes);
    free(p->tree_nodes);
    free(p->mesh_tree_root);
    free(p->instances);
    free(p->mesh_first);
    free(p->mesh_size);
    free(p->tri_groups);
    free(p->triangles);
    free(p->materials);
    free(p->textures);
    free(p->texels);
    free(p->lights);
    free(p->light_odds);
    free(p->punctuals);
    memset(p, 0, sizeof *p);
}
