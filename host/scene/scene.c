#include "scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void lvcl_scene_free(lvcl_scene *scene)
{
    free(scene->positions);
    free(scene->normals);
    free(scene->uvs);
    free(scene->indices);
    free(scene->tri_material);
    free(scene->tri_flags);
    free(scene->meshes);
    free(scene->instances);
    free(scene->materials);
    for (size_t i = 0; i < scene->texture_count; i++) free(scene->textures[i].rgba);
    free(scene->textures);
    free(scene->punctuals);
    memset(scene, 0, sizeof *scene);
}

const float lvcl_identity_transform[12] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0};

void lvcl_transform_point(const float m[12], const float p[3], float w, float out[3])
{
    for (int r = 0; r < 3; r++) out[r] = m[4 * r] * p[0] + m[4 * r + 1] * p[1] + m[4 * r + 2] * p[2] + m[4 * r + 3] * w;
}

void lvcl_transform_box(const float m[12], const float lo[3], const float hi[3], float out_lo[3], float out_hi[3])
{
    for (int k = 0; k < 3; k++) {
        out_lo[k] = INFINITY;
        out_hi[k] = -INFINITY;
    }
    for (int c = 0; c < 8; c++) {
        float p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]}, q[3];
        lvcl_transform_point(m, p, 1.0f, q);
        for (int k = 0; k < 3; k++) {
            if (q[k] < out_lo[k]) out_lo[k] = q[k];
            if (q[k] > out_hi[k]) out_hi[k] = q[k];
        }
    }
}

void lvcl_transform_invert(const float m[12], float out[12], int *mirrored)
{
    double a[3][3], t[3];
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) a[r][c] = m[4 * r + c];
        t[r] = m[4 * r + 3];
    }
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
        a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    double inv[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            /* Cofactor of (c, r), over the determinant. */
            int r0 = (c + 1) % 3, r1 = (c + 2) % 3, c0 = (r + 1) % 3, c1 = (r + 2) % 3;
            inv[r][c] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
        }
    for (int r = 0; r < 3; r++) {
        for (int c = 0; c < 3; c++) out[4 * r + c] = (float)inv[r][c];
        out[4 * r + 3] = (float)-(inv[r][0] * t[0] + inv[r][1] * t[1] + inv[r][2] * t[2]);
    }
    *mirrored = det < 0.0;
}

/* An instance's copy of the vertex range [lo, hi): positions and normals
 * transformed (inv is the inverse transform), uvs as they are. */
static void place_vertices(const lvcl_scene *s, const lvcl_instance *in, const float inv[12], size_t lo, size_t hi,
                           float *pos, float *nrm, float *uv)
{
    for (size_t v = lo; v < hi; v++) {
        size_t o = v - lo;
        lvcl_transform_point(in->world_from_object, &s->positions[3 * v], 1.0f, &pos[3 * o]);
        /* Normals by the inverse transpose: column k of the inverse. */
        const float *n = &s->normals[3 * v];
        double w[3], len = 0.0;
        for (int k = 0; k < 3; k++) {
            w[k] = (double)inv[k] * n[0] + (double)inv[4 + k] * n[1] + (double)inv[8 + k] * n[2];
            len += w[k] * w[k];
        }
        len = sqrt(len);
        for (int k = 0; k < 3; k++) nrm[3 * o + k] = len > 0.0 ? (float)(w[k] / len) : 0.0f;
        memcpy(&uv[2 * o], &s->uvs[2 * v], 2 * sizeof(float));
    }
}

lvcl_error lvcl_scene_flatten(lvcl_scene *s, lvcl_status *st)
{
    if (s->mesh_count == 0) return LVCL_OK;
    /* Each mesh's vertex range, and the sizes of the flat arrays. */
    size_t *lo = malloc(s->mesh_count * sizeof *lo), *hi = malloc(s->mesh_count * sizeof *hi);
    size_t verts = 0, tris = 0;
    for (size_t m = 0; lo && hi && m < s->mesh_count; m++) {
        lo[m] = SIZE_MAX;
        hi[m] = 0;
        const lvcl_mesh *mesh = &s->meshes[m];
        for (size_t i = 3 * mesh->first_triangle; i < 3 * (mesh->first_triangle + mesh->triangle_count); i++) {
            if (s->indices[i] < lo[m]) lo[m] = s->indices[i];
            if (s->indices[i] + 1 > hi[m]) hi[m] = s->indices[i] + 1;
        }
        if (lo[m] > hi[m]) lo[m] = hi[m] = 0;
    }
    for (size_t i = 0; lo && hi && i < s->instance_count; i++) {
        verts += hi[s->instances[i].mesh] - lo[s->instances[i].mesh];
        tris += s->meshes[s->instances[i].mesh].triangle_count;
    }
    float *pos = malloc((verts ? verts : 1) * 3 * sizeof *pos), *nrm = malloc((verts ? verts : 1) * 3 * sizeof *nrm);
    float *uv = malloc((verts ? verts : 1) * 2 * sizeof *uv);
    uint32_t *idx = malloc((tris ? tris : 1) * 3 * sizeof *idx), *mat = malloc((tris ? tris : 1) * sizeof *mat);
    uint32_t *flags = malloc((tris ? tris : 1) * sizeof *flags);
    if (!lo || !hi || !pos || !nrm || !uv || !idx || !mat || !flags || verts > UINT32_MAX) {
        void *all[] = {lo, hi, pos, nrm, uv, idx, mat, flags};
        for (size_t k = 0; k < sizeof all / sizeof all[0]; k++) free(all[k]);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory flattening %zu triangles", tris);
    }
    size_t v_out = 0, t_out = 0;
    for (size_t i = 0; i < s->instance_count; i++) {
        const lvcl_instance *in = &s->instances[i];
        const lvcl_mesh *mesh = &s->meshes[in->mesh];
        size_t a = lo[in->mesh], b = hi[in->mesh];
        float inv[12];
        int mirrored;
        lvcl_transform_invert(in->world_from_object, inv, &mirrored);
        place_vertices(s, in, inv, a, b, &pos[3 * v_out], &nrm[3 * v_out], &uv[2 * v_out]);
        for (size_t t = mesh->first_triangle; t < mesh->first_triangle + mesh->triangle_count; t++, t_out++) {
            for (int c = 0; c < 3; c++) idx[3 * t_out + c] = (uint32_t)(v_out + s->indices[3 * t + c] - a);
            if (mirrored) { /* glTF: a mirroring transform reverses the winding */
                uint32_t x = idx[3 * t_out + 1];
                idx[3 * t_out + 1] = idx[3 * t_out + 2];
                idx[3 * t_out + 2] = x;
            }
            mat[t_out] = s->tri_material[t];
            flags[t_out] = s->tri_flags[t];
        }
        v_out += b - a;
    }
    free(lo);
    free(hi);
    void *old[] = {s->positions,    s->normals,   s->uvs,    s->indices,
                   s->tri_material, s->tri_flags, s->meshes, s->instances};
    for (size_t k = 0; k < sizeof old / sizeof old[0]; k++) free(old[k]);
    s->positions = pos;
    s->normals = nrm;
    s->uvs = uv;
    s->vertex_count = verts;
    s->indices = idx;
    s->tri_material = mat;
    s->tri_flags = flags;
    s->triangle_count = tris;
    s->meshes = NULL;
    s->instances = NULL;
    s->mesh_count = s->instance_count = 0;
    return LVCL_OK;
}
