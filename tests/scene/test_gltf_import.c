/* glTF import: world transforms, winding, camera, lights, materials,
 * textures, GLB, and one clear error for each kind of broken file.
 * Usage: test_gltf_import DATA_DIR (tests/data/gltf).
 *
 * The robustness loops hide the importer's warnings by sending stderr to a
 * temporary file, then check it for sanitizer reports; set
 * LVCL_TEST_VERBOSE=1 to see everything (e.g. when a sanitizer aborts). */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "../../host/scene/scene.h"
#include "../check.h"
#include "capture.h"

static const char *data_dir;

static const char *data_path(const char *name)
{
    static char buf[4096];
    snprintf(buf, sizeof buf, "%s/%s", data_dir, name);
    return buf;
}

/* ---- helpers ---- */

static int near(float a, float b)
{
    return fabsf(a - b) < 1e-5f;
}

static int near3(const float *v, float x, float y, float z)
{
    return near(v[0], x) && near(v[1], y) && near(v[2], z);
}

static const float *corner(const lvcl_scene *s, size_t tri, int c)
{
    return &s->positions[3 * s->indices[3 * tri + (size_t)c]];
}

/* Checks the world positions of triangle `tri` (corners in file order). */
static void check_triangle(const char *name, const lvcl_scene *s, size_t tri, const float e[9])
{
    int ok = tri < s->triangle_count;
    for (int c = 0; ok && c < 3; c++) ok = near3(corner(s, tri, c), e[3 * c], e[3 * c + 1], e[3 * c + 2]);
    const float *a = ok ? corner(s, tri, 0) : e;
    CHECK(name, ok, "triangle %zu corner 0 is (%g %g %g)", tri, a[0], a[1], a[2]);
}

static int same_scene(const lvcl_scene *a, const lvcl_scene *b)
{
    if (a->vertex_count != b->vertex_count || a->triangle_count != b->triangle_count ||
        a->mesh_count != b->mesh_count || a->instance_count != b->instance_count ||
        memcmp(a->meshes, b->meshes, a->mesh_count * sizeof *a->meshes) ||
        memcmp(a->instances, b->instances, a->instance_count * sizeof *a->instances) ||
        a->material_count != b->material_count || a->texture_count != b->texture_count ||
        a->punctual_count != b->punctual_count)
        return 0;
    size_t v = a->vertex_count, t = a->triangle_count;
    if (memcmp(a->positions, b->positions, 3 * v * sizeof(float)) ||
        memcmp(a->normals, b->normals, 3 * v * sizeof(float)) || memcmp(a->uvs, b->uvs, 2 * v * sizeof(float)) ||
        memcmp(a->indices, b->indices, 3 * t * sizeof(uint32_t)) ||
        memcmp(a->tri_material, b->tri_material, t * sizeof(uint32_t)) ||
        memcmp(a->tri_flags, b->tri_flags, t * sizeof(uint32_t)) ||
        memcmp(a->materials, b->materials, a->material_count * sizeof(lvcl_material_desc)) ||
        memcmp(a->punctuals, b->punctuals, a->punctual_count * sizeof(lv_punctual_light)) ||
        memcmp(&a->camera, &b->camera, sizeof a->camera))
        return 0;
    for (size_t i = 0; i < a->texture_count; i++) {
        const lvcl_texture_data *x = &a->textures[i], *y = &b->textures[i];
        if (x->width != y->width || x->height != y->height || memcmp(x->rgba, y->rgba, 4u * x->width * x->height))
            return 0;
    }
    return 1;
}

static int is_zeroed(const lvcl_scene *s)
{
    static const lvcl_scene zero;
    return memcmp(s, &zero, sizeof zero) == 0;
}

/* ---- features.gltf ---- */

/* Mesh 0 is used by five nodes: stored once and placed five times; mesh 1
 * (one node) is baked into world space as mesh 0 of the scene. */
static void check_instancing(const lvcl_scene *s)
{
    int ok = s->triangle_count == 2 && s->mesh_count == 2 && s->instance_count == 6 && s->instances[0].mesh == 0 &&
        s->meshes[0].triangle_count == 1 && s->meshes[1].triangle_count == 1;
    for (size_t i = 1; ok && i < 6; i++) ok = s->instances[i].mesh == 1;
    CHECK("features: a mesh five nodes use is stored once and instanced", ok,
          "%zu triangles, %zu meshes, %zu instances", s->triangle_count, s->mesh_count, s->instance_count);
}

/* The flattened scene: the baked triangle first, then the instances in
 * node order. */
static void check_geometry(const lvcl_scene *s)
{
    CHECK("features: six triangles", s->triangle_count == 6, "got %zu", s->triangle_count);
    if (s->triangle_count != 6) return;

    /* TRS: translate (1,2,3), rotate 90 degrees about Z, scale 2. */
    const float trs[9] = {1, 2, 3, 1, 4, 3, -1, 2, 3};
    check_triangle("TRS node transform", s, 1, trs);
    /* Column-major matrix: rotate 90 degrees about Z, translate (5,0,0). */
    const float mat[9] = {5, 0, 0, 5, 1, 0, 4, 0, 0};
    check_triangle("matrix node transform", s, 2, mat);
    /* parent T(0,0,10) > child S(3) > grandchild T(1,0,0). */
    const float child[9] = {0, 0, 10, 3, 0, 10, 0, 3, 10};
    const float grandchild[9] = {3, 0, 10, 6, 0, 10, 3, 3, 10};
    check_triangle("nested hierarchy (child)", s, 3, child);
    check_triangle("nested hierarchy (grandchild)", s, 4, grandchild);
    const float plain[9] = {0, 0, -1, 1, 0, -1, 0, 1, -1};
    check_triangle("non-indexed primitive", s, 0, plain);

    /* Mirrored node: the geometric normal from the winding must still agree
     * with the (mirrored) shading normal, +Z. */
    const float *p0 = corner(s, 5, 0), *p1 = corner(s, 5, 1), *p2 = corner(s, 5, 2);
    float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
    float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
    float nz = e1[0] * e2[1] - e1[1] * e2[0];
    const float *sn = &s->normals[3 * s->indices[15]];
    CHECK("mirrored node flips winding", nz > 0.5f && near3(sn, 0, 0, 1),
          "geometric normal z %g, shading normal (%g %g %g)", nz, sn[0], sn[1], sn[2]);

    const float *n0 = &s->normals[3 * s->indices[3]];
    const float *uv1 = &s->uvs[2 * s->indices[4]];
    CHECK("normals and uvs of the TRS triangle",
          near3(n0, 0, 0, 1) && near(uv1[0], 1) && near(uv1[1], 0) &&
              s->tri_flags[1] == (LV_TRI_HAS_NORMALS | LV_TRI_HAS_UVS) && s->tri_flags[0] == 0,
          "normal (%g %g %g) uv (%g %g) flags %u %u", n0[0], n0[1], n0[2], uv1[0], uv1[1], s->tri_flags[1],
          s->tri_flags[0]);
}

static void check_camera_and_lights(const lvcl_scene *s)
{
    /* Camera at (0,1,5) rotated 90 degrees about +Y. */
    const lvcl_camera_desc *c = &s->camera;
    CHECK("camera position and directions",
          c->present && near3(c->position, 0, 1, 5) && near3(c->right, 0, 0, -1) && near3(c->up, 0, 1, 0) &&
              near3(c->back, 1, 0, 0) && near(c->yfov, 0.8f) && near(c->aspect, 1.5f),
          "present %d pos (%g %g %g) right (%g %g %g) back (%g %g %g) yfov %g aspect %g", c->present, c->position[0],
          c->position[1], c->position[2], c->right[0], c->right[1], c->right[2], c->back[0], c->back[1], c->back[2],
          c->yfov, c->aspect);

    CHECK("three punctual lights", s->punctual_count == 3, "got %zu", s->punctual_count);
    if (s->punctual_count != 3) return;
    const lv_punctual_light *pt = &s->punctuals[0], *sp = &s->punctuals[1], *sun = &s->punctuals[2];
    CHECK("point light in world space",
          pt->type == LV_PUNCTUAL_POINT && near3(pt->position, 1, 5, 0) && near3(pt->intensity, 100, 50, 25),
          "type %u pos (%g %g %g) intensity (%g %g %g)", pt->type, pt->position[0], pt->position[1], pt->position[2],
          pt->intensity[0], pt->intensity[1], pt->intensity[2]);
    CHECK("spot light in world space",
          sp->type == LV_PUNCTUAL_SPOT && near3(sp->position, 1, 0, 2) && near3(sp->direction, 0, 1, 0) &&
              near3(sp->intensity, 10, 10, 10) && near(sp->cos_outer, cosf(0.5f)) && near(sp->cos_inner, cosf(0.25f)),
          "type %u pos (%g %g %g) dir (%g %g %g) cos %g %g", sp->type, sp->position[0], sp->position[1],
          sp->position[2], sp->direction[0], sp->direction[1], sp->direction[2], sp->cos_outer, sp->cos_inner);
    CHECK("directional light along its node's -z, irradiance = colour x intensity (default 1)",
          sun->type == LV_PUNCTUAL_DIRECTIONAL && near3(sun->direction, 0, 0, -1) && near3(sun->intensity, 1, 1, 1),
          "type %u dir (%g %g %g) intensity (%g %g %g)", sun->type, sun->direction[0], sun->direction[1],
          sun->direction[2], sun->intensity[0], sun->intensity[1], sun->intensity[2]);
}

static void check_materials(const lvcl_scene *s)
{
    CHECK("three materials (two + default)", s->material_count == 3, "got %zu", s->material_count);
    if (s->material_count != 3 || s->triangle_count != 6) return;
    const lvcl_material_desc *g = &s->materials[0], *p = &s->materials[1], *d = &s->materials[2];
    CHECK("material extensions parsed",
          near(g->base_color[0], 0.9f) && near(g->base_color[2], 0.7f) && g->metallic == 0 &&
              near(g->roughness, 0.1f) && near3(g->emissive, 4, 2, 0) && near(g->transmission, 0.75f) &&
              near(g->ior, 1.33f) && near(g->specular, 0.5f) && g->has_volume == 1 &&
              near3(g->attenuation_color, 0.5f, 0.6f, 0.7f) && near(g->attenuation_distance, 2) &&
              g->double_sided == 1 && g->base_color_texture == 0,
          "emissive (%g %g %g) transmission %g ior %g specular %g volume %d dist %g tex %d", g->emissive[0],
          g->emissive[1], g->emissive[2], g->transmission, g->ior, g->specular, g->has_volume, g->attenuation_distance,
          g->base_color_texture);
    CHECK("material defaults",
          p->transmission == 0 && near(p->ior, 1.5f) && p->specular == 1 && p->has_volume == 0 &&
              isinf(p->attenuation_distance) && near3(p->attenuation_color, 1, 1, 1) && p->base_color_texture == -1 &&
              p->double_sided == 0,
          "ior %g specular %g dist %g tex %d", p->ior, p->specular, p->attenuation_distance, p->base_color_texture);
    CHECK("default material for primitives without one",
          s->tri_material[0] == 2 && s->tri_material[1] == 0 && d->base_color[0] == 1 && d->base_color[3] == 1 &&
              d->metallic == 1 && d->roughness == 1 && d->base_color_texture == -1,
          "tri 0 material %u, metallic %g roughness %g", s->tri_material[0], d->metallic, d->roughness);

    static const uint8_t expect[16] = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255};
    int ok = s->texture_count == 1 && s->textures[0].width == 2 && s->textures[0].height == 2 &&
        memcmp(s->textures[0].rgba, expect, 16) == 0;
    CHECK("2x2 PNG decoded to RGBA8", ok, "texture_count %zu", s->texture_count);
}

static void test_features(void)
{
    lvcl_scene gltf, glb, mem;
    lvcl_status st = {0};
    lvcl_error e = lvcl_scene_load_gltf_file(data_path("features.gltf"), &gltf, &st);
    CHECK("load features.gltf", e == LVCL_OK, "%s", st.message);
    if (e != LVCL_OK) return;
    check_instancing(&gltf);

    e = lvcl_scene_load_gltf_file(data_path("features.glb"), &glb, &st);
    CHECK("load features.glb", e == LVCL_OK, "%s", st.message);
    if (e == LVCL_OK) {
        CHECK(".glb loads the same as .gltf", same_scene(&gltf, &glb), "scenes differ");
        lvcl_scene_free(&glb);
    }

    size_t size = 0;
    unsigned char *bytes = read_all(data_path("features.gltf"), &size);
    e = lvcl_scene_load_gltf_memory(bytes, size, data_dir, &mem, &st);
    CHECK("load from memory", e == LVCL_OK && same_scene(&gltf, &mem), "%s", e ? st.message : "scenes differ");
    if (e == LVCL_OK) lvcl_scene_free(&mem);
    free(bytes);

    e = lvcl_scene_flatten(&gltf, &st);
    CHECK("flatten the instances", e == LVCL_OK, "%s", st.message);
    if (e == LVCL_OK) {
        check_geometry(&gltf);
        check_camera_and_lights(&gltf);
        check_materials(&gltf);
    }
    lvcl_scene_free(&gltf);
}

static void test_nan_vertex(void)
{
    lvcl_scene s;
    lvcl_status st = {0};
    capture cap;
    capture_begin(&cap);
    lvcl_error e = lvcl_scene_load_gltf_file(data_path("nan_vertex.gltf"), &s, &st);
    char *warnings = capture_end(&cap);
    int finite = 1;
    for (size_t i = 0; e == LVCL_OK && i < 3 * s.vertex_count; i++) finite &= isfinite(s.positions[i]);
    CHECK("NaN vertex: its triangle skipped", e == LVCL_OK && s.triangle_count == 1 && finite,
          "error %d (%s), %zu triangles", e, st.message, e ? 0 : s.triangle_count);
    if (!verbose())
        CHECK("NaN vertex: one warning with the count",
              warnings && strstr(warnings, "skipped 1 triangles with non-finite"), "stderr: %s",
              warnings ? warnings : "(null)");
    free(warnings);
    if (e == LVCL_OK) lvcl_scene_free(&s);
}

/* Interleaved attributes, normalized ubyte UVs and a sparse accessor. */
static void test_sparse_strided(void)
{
    lvcl_scene s;
    lvcl_status st = {0};
    lvcl_error e = lvcl_scene_load_gltf_file(data_path("sparse_strided.gltf"), &s, &st);
    CHECK("load sparse_strided.gltf", e == LVCL_OK && s.triangle_count == 1, "%s", st.message);
    if (e != LVCL_OK) return;
    const float expect[9] = {0, 0, 0, 1, 0, 0, 0, 2, 0};
    check_triangle("sparse accessor and byteStride", &s, 0, expect);
    const float *uv1 = &s.uvs[2 * s.indices[1]], *uv2 = &s.uvs[2 * s.indices[2]];
    const float *n2 = &s.normals[3 * s.indices[2]];
    CHECK("normalized ubyte UVs and interleaved normals",
          near(uv1[0], 1) && near(uv1[1], 0) && near(uv2[1], 1) && near3(n2, 0, 0, 1) &&
              s.tri_flags[0] == (LV_TRI_HAS_NORMALS | LV_TRI_HAS_UVS),
          "uv1 (%g %g) uv2 (%g %g) n2 (%g %g %g)", uv1[0], uv1[1], uv2[0], uv2[1], n2[0], n2[1], n2[2]);
    lvcl_scene_free(&s);
}

static lvcl_error load_edited_scene(const char *key, char until, const char *with, lvcl_scene *s, char **warnings);

/* features.gltf with the text from `key` up to the next `until` (or `key`
 * alone where until is 0) replaced by `with`: loads either way; returns
 * the decoded textures (-1 if it did not load) and the warnings in
 * *warnings (the caller frees them). Textures report as width x 10 +
 * height where there is one. */
static long load_edited(const char *key, char until, const char *with, char **warnings)
{
    lvcl_scene s;
    long textures = -1;
    if (load_edited_scene(key, until, with, &s, warnings) == LVCL_OK) {
        textures = (long)s.texture_count;
        if (s.texture_count == 1) textures = s.textures[0].width * 10L + s.textures[0].height;
        lvcl_scene_free(&s);
    }
    return textures;
}

static lvcl_error load_edited_scene(const char *key, char until, const char *with, lvcl_scene *s, char **warnings)
{
    size_t size = 0;
    char *text = (char *)read_all(data_path("features.gltf"), &size);
    char *at = text ? strstr(text, key) : NULL;
    char *end = !at ? NULL : until ? strchr(at + strlen(key), until) : at + strlen(key);
    lvcl_error e = LVCL_ERR_PARSE;
    *warnings = NULL;
    if (end) {
        size_t head = (size_t)(at - text), tail = size - (size_t)(end - text);
        char *edited = malloc(head + strlen(with) + tail + 16);
        size_t n = (size_t)sprintf(edited, "%.*s%s", (int)head, text, with);
        memcpy(edited + n, end, tail);
        lvcl_status st = {0};
        capture cap;
        capture_begin(&cap);
        e = lvcl_scene_load_gltf_memory((unsigned char *)edited, n + tail, data_dir, s, &st);
        *warnings = capture_end(&cap);
        free(edited);
    }
    free(text);
    return e;
}

/* features.gltf with its texture's data URI replaced by `uri`. */
static long load_with_image(const char *uri, char **warnings)
{
    char with[512];
    snprintf(with, sizeof with, "\"uri\": \"%s", uri);
    return load_edited("\"uri\": \"data:image/png;base64,", '"', with, warnings);
}

/* A sampler's wrap modes and nearest filtering are read (clamp to edge on
 * u, mirrored repeat on v, nearest); and what lvcl does not read, it
 * names: vertex colours (COLOR_0, which glTF multiplies into the base
 * colour). */
static void test_sampler_and_warnings(void)
{
    char *warnings;
    lvcl_scene s;
    lvcl_error e = load_edited_scene("\"textures\": [", 0,
                                     "\"samplers\": [{\"wrapS\": 33071, \"wrapT\": 33648, \"magFilter\": 9728}], "
                                     "\"textures\": [{\"source\": 0, \"sampler\": 0}], \"unused\": [",
                                     &s, &warnings);
    free(warnings);
    unsigned want = LV_WRAP_CLAMP | LV_WRAP_MIRROR << LV_WRAP_V_SHIFT | LV_TEXTURE_NEAREST;
    CHECK("a sampler's clamp, mirrored repeat and nearest filtering are read",
          e == LVCL_OK && s.material_count > 0 && s.materials[0].texture_sampling == want, "error %d, sampling %u",
          (int)e, e == LVCL_OK && s.material_count > 0 ? s.materials[0].texture_sampling : 0u);
    if (e == LVCL_OK) lvcl_scene_free(&s);
    long textures;
    textures = load_edited("\"attributes\": {", 0, "\"attributes\": {\"COLOR_0\": 0, ", &warnings);
    CHECK("a primitive with vertex colours loads", textures == 22, "got %ld", textures);
    if (!verbose())
        CHECK("vertex colours: one warning", warnings && strstr(warnings, "vertex colours (COLOR_0) are not supported"),
              "stderr: %s", warnings ? warnings : "(null)");
    free(warnings);
}

/* KHR_texture_transform on the base colour texture, its specification's
 * example (offset (0, 1), a quarter turn, scale 1/2: the lower left
 * quadrant turned clockwise): the texture is read at (v / 2, 1 - u / 2). */
static void test_texture_transform(void)
{
    char *warnings;
    lvcl_scene s;
    lvcl_error e =
        load_edited_scene("\"baseColorTexture\": {", 0,
                          "\"baseColorTexture\": {\"extensions\": {\"KHR_texture_transform\": {\"offset\": [0, 1], "
                          "\"rotation\": 1.57079632679, \"scale\": [0.5, 0.5]}}, ",
                          &s, &warnings);
    free(warnings);
    if (e != LVCL_OK) {
        CHECK("KHR_texture_transform: loads", 0, "error %d", (int)e);
        return;
    }
    const lvcl_material_desc *m = &s.materials[0];
    const float want[6] = {0, 0.5f, 0, -0.5f, 0, 1};
    int ok = m->has_uv_transform;
    for (int k = 0; k < 6; k++) ok &= fabsf(m->uv_transform[k] - want[k]) < 1e-6f;
    CHECK("KHR_texture_transform: the example reads (v / 2, 1 - u / 2)", ok, "has %d, (%g %g %g / %g %g %g)",
          m->has_uv_transform, m->uv_transform[0], m->uv_transform[1], m->uv_transform[2], m->uv_transform[3],
          m->uv_transform[4], m->uv_transform[5]);
    lvcl_scene_free(&s);
}

/* Only PNG and JPEG, as glTF 2.0 allows, and at most 16384 pixels a side:
 * other formats stb_image reads (here a valid GIF) and larger images load
 * untextured with one warning. Textures report as width x 10 + height. */
static void test_image_formats(void)
{
    static const struct {
        const char *name, *uri;
        long textures;
    } cases[] = {
        {"a 1x1 GIF", "data:image/gif;base64,R0lGODlhAQABAIAAAP///wAAACwAAAAAAQABAAACAkQBADs=", 0},
        /* Grey 8-bit PNGs of 16384 x 1 and 16385 x 1 pixels (zlib-compressed zeros). */
        {"a 16384 x 1 PNG",
         "data:image/"
         "png;base64,iVBORw0KGgoAAAANSUhEUgAAQAAAAAABCAAAAAAD9OmEAAAAJ0lEQVR42u3BIQEAAAACIKc73RkWIAUAAAAAAAAAAAAA"
         "AAAAAADuBkR1AeF+PGb0AAAAAElFTkSuQmCC",
         163841},
        {"a 16385 x 1 PNG",
         "data:image/"
         "png;base64,iVBORw0KGgoAAAANSUhEUgAAQAEAAAABCAAAAADsNoK6AAAAJ0lEQVR42u3BIQEAAAACIKc73RkWIAUAAAAAAAAAAAAA"
         "AAAAAAD+BkbWAmHKSJ8+AAAAAElFTkSuQmCC",
         0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *warnings;
        long textures = load_with_image(cases[i].uri, &warnings);
        char name[96];
        snprintf(name, sizeof name, "texture from %s", cases[i].name);
        CHECK(name, textures == cases[i].textures, "got %ld, want %ld", textures, cases[i].textures);
        if (cases[i].textures == 0 && !verbose()) {
            snprintf(name, sizeof name, "%s: one warning naming the formats", cases[i].name);
            CHECK(name, warnings && strstr(warnings, "could not be decoded as a PNG or JPEG"), "stderr: %s",
                  warnings ? warnings : "(null)");
        }
        free(warnings);
    }
}

/* ---- broken inputs ---- */

static void expect_error(const char *file, lvcl_error want)
{
    char name[128];
    snprintf(name, sizeof name, "error for %s", file);
    lvcl_scene s;
    memset(&s, 0xab, sizeof s); /* the loader must zero it */
    lvcl_status st = {0};
    lvcl_error e = lvcl_scene_load_gltf_file(data_path(file), &s, &st);
    CHECK(name,
          e == want && st.code == want && st.message[0] && strstr(st.message, file) && !strchr(st.message, '\n') &&
              is_zeroed(&s),
          "got %d (want %d): \"%s\"", e, want, st.message);
    if (e == want) printf("  message: %s\n", st.message);
    if (e == LVCL_OK) lvcl_scene_free(&s);
}

static void test_errors(void)
{
    expect_error("does_not_exist.gltf", LVCL_ERR_IO);
    expect_error("malformed.gltf", LVCL_ERR_PARSE);
    expect_error("truncated.glb", LVCL_ERR_PARSE);
    expect_error("bad_buffer_index.gltf", LVCL_ERR_PARSE);
    expect_error("accessor_past_end.gltf", LVCL_ERR_PARSE);
    expect_error("bad_bufferview_index.gltf", LVCL_ERR_PARSE);
    expect_error("bad_index_value.gltf", LVCL_ERR_PARSE);
    expect_error("node_cycle.gltf", LVCL_ERR_PARSE);
    expect_error("draco_required.gltf", LVCL_ERR_UNSUPPORTED);
    expect_error("no_triangles.gltf", LVCL_ERR_UNSUPPORTED);

    lvcl_scene s;
    lvcl_status st = {0};
    lvcl_error e = lvcl_scene_load_gltf_memory("hello", 5, "", &s, &st);
    CHECK("error for garbage in memory", e == LVCL_ERR_PARSE && st.message[0], "got %d", e);
    e = lvcl_scene_load_gltf_memory(NULL, 0, "", &s, &st);
    CHECK("error for empty memory", e != LVCL_OK && st.message[0] && is_zeroed(&s), "got %d", e);
}

/* Loads `data` from memory; counts successes, failures without a message
 * and failures that left the scene non-empty. */
static void fuzz_one(const unsigned char *data, size_t size, int *ok, int *bad)
{
    lvcl_scene s;
    lvcl_status st = {0};
    lvcl_error e = lvcl_scene_load_gltf_memory(data, size, data_dir, &s, &st);
    if (e == LVCL_OK) {
        (*ok)++;
        lvcl_scene_free(&s);
    } else if (!st.message[0] || !is_zeroed(&s)) {
        (*bad)++;
    }
}

/* Every truncation and many one-byte corruptions must fail cleanly or load. */
static void test_corruptions(void)
{
    size_t glb_size = 0, gltf_size = 0;
    unsigned char *glb = read_all(data_path("features.glb"), &glb_size);
    unsigned char *gltf = read_all(data_path("features.gltf"), &gltf_size);
    if (!glb || !gltf) {
        CHECK("corruption fixtures readable", 0, "cannot read features.glb / features.gltf");
        free(glb);
        free(gltf);
        return;
    }
    unsigned char *copy = malloc(glb_size > gltf_size ? glb_size : gltf_size);
    int ok = 0, bad = 0, loads = 0;
    capture cap;
    capture_begin(&cap);

    for (size_t n = 0; n < glb_size; n++, loads++) fuzz_one(glb, n, &ok, &bad);
    int truncated_ok = ok;
    for (size_t i = 0; i < glb_size; i++, loads++) {
        memcpy(copy, glb, glb_size);
        copy[i] ^= 0x5a;
        fuzz_one(copy, glb_size, &ok, &bad);
    }
    /* Digits in the JSON are indices, counts, offsets and base64 data. */
    static const char swaps[] = "907";
    for (size_t i = 0; i < gltf_size; i++) {
        if (gltf[i] < '0' || gltf[i] > '9') continue;
        for (const char *c = swaps; *c; c++, loads++) {
            memcpy(copy, gltf, gltf_size);
            copy[i] = (unsigned char)*c;
            fuzz_one(copy, gltf_size, &ok, &bad);
        }
    }

    char *log = capture_end(&cap);
    CHECK("truncated GLBs all fail", truncated_ok == 0, "%d truncations loaded", truncated_ok);
    CHECK("corrupted inputs fail cleanly", bad == 0,
          "%d of %d loads failed without a message "
          "or left data behind",
          bad, loads);
    CHECK("corrupted inputs: no sanitizer reports", !sanitizer_report(log), "%s", log);
    printf("  %d corrupted loads, %d still loaded\n", loads, ok);
    free(log);
    free(copy);
    free(glb);
    free(gltf);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s TESTS_DIR\n", argv[0]);
        return 2;
    }
    static char dir[4096];
    snprintf(dir, sizeof dir, "%s/data/gltf", argv[1]);
    data_dir = dir;
    test_features();
    test_nan_vertex();
    test_sparse_strided();
    test_image_formats();
    test_sampler_and_warnings();
    test_texture_transform();
    test_errors();
    test_corruptions();
    CHECK_EXIT();
}
