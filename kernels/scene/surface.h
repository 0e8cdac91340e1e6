/* What a ray hit: position, normals, texture coordinates and the BSDF there. */
#ifndef LV_SURFACE_H
#define LV_SURFACE_H

#include "../closure/bsdf.h"
#include "../bvh/traverse.h"

typedef struct {
    float3 p;
    /* The arriving ray at the hit, its origin + t dir: on the side the ray
     * came from of every surface it passed near, where p, from the
     * barycentrics, may round a few ulps past a surface the ray grazed
     * (lv_leave_point). */
    float3 arrived;
    float3 ng; /* geometric normal of the front face (counter-clockwise winding), unit */
    float3 ns; /* shading normal on the same side as ng, unit */
    float2 uv;
    uint material;
    int front; /* the ray arrived on the front face */
} lv_surface;

#ifdef LV_FEATURE_TEXTURES
/* Texel index i of a row or column of n, wrapped by mode (LV_WRAP_*). */
inline uint lv_wrap_texel(int i, int n, uint mode)
{
    if (mode == LV_WRAP_CLAMP) return (uint)clamp(i, 0, n - 1);
    int period = mode == LV_WRAP_MIRROR ? 2 * n : n, k = i % period;
    if (k < 0) k += period;
    return (uint)(k < n ? k : period - 1 - k);
}

inline float4 lv_texel(const lv_scene *sc, lv_texture t, int x, int y, uint sampling)
{
    uint u = lv_wrap_texel(x, (int)t.width, sampling & 3u),
         v = lv_wrap_texel(y, (int)t.height, sampling >> LV_WRAP_V_SHIFT & 3u);
    return convert_float4(sc->texels[t.offset + v * t.width + u]) * (1.0f / 65535.0f);
}

/* A lookup of linear texels, bilinear or nearest, wrapped as `sampling`
 * (lv_material.texture_sampling) says. */
inline float3 lv_texture_rgb(const lv_scene *sc, int index, float2 uv, uint sampling)
{
    lv_texture t = sc->textures[index];
    float x = uv.x * (float)t.width, y = uv.y * (float)t.height;
    if (sampling & LV_TEXTURE_NEAREST) return lv_texel(sc, t, (int)floor(x), (int)floor(y), sampling).xyz;
    x -= 0.5f;
    y -= 0.5f;
    float fx = floor(x), fy = floor(y);
    int x0 = (int)fx, y0 = (int)fy;
    float ax = x - fx, ay = y - fy;
    float4 c = mix(mix(lv_texel(sc, t, x0, y0, sampling), lv_texel(sc, t, x0 + 1, y0, sampling), ax),
                   mix(lv_texel(sc, t, x0, y0 + 1, sampling), lv_texel(sc, t, x0 + 1, y0 + 1, sampling), ax), ay);
    return c.xyz;
}
#endif

/* The world-space corners of triangle tri of instance inst; returns the
 * sign that turns cross(v1 - v0, v2 - v0) into the front normal (-1 for a
 * mirrored instance, whose transform reverses the winding). */
inline float lv_triangle_world(const lv_scene *sc, uint inst, uint tri, float3 *v0, float3 *v1, float3 *v2)
{
    lv_tri_corners(sc, tri, v0, v1, v2);
    if (sc->info.flat) return 1.0f;
    __global const lv_instance *placed = &sc->instances[inst];
    *v0 = lv_transform(placed->world_from_object, *v0, 1.0f);
    *v1 = lv_transform(placed->world_from_object, *v1, 1.0f);
    *v2 = lv_transform(placed->world_from_object, *v2, 1.0f);
    return (placed->flags & LV_INSTANCE_MIRRORED) ? -1.0f : 1.0f;
}

/* A shading normal from object to world space: by the inverse transpose,
 * which keeps it perpendicular to the surface under non-uniform scale. */
inline float3 lv_normal_to_world(const lv_scene *sc, uint inst, float3 n)
{
    if (sc->info.flat) return n;
    __global const float *m = sc->instances[inst].object_from_world;
    return (float3)(m[0] * n.x + m[4] * n.y + m[8] * n.z, m[1] * n.x + m[5] * n.y + m[9] * n.z,
                    m[2] * n.x + m[6] * n.y + m[10] * n.z);
}

inline lv_surface lv_surface_at(const lv_scene *sc, lv_ray r, lv_hit h)
{
    lv_surface s;
    float3 v0, v1, v2;
    float front_sign = lv_triangle_world(sc, h.inst, h.tri, &v0, &v1, &v2);
    float b0 = 1.0f - h.b1 - h.b2;
    s.p = b0 * v0 + h.b1 * v1 + h.b2 * v2;
    s.arrived = r.origin + r.dir * h.t;
    s.ng = front_sign * normalize(cross(v1 - v0, v2 - v0));
    s.front = dot(r.dir, s.ng) < 0.0f;
    lv_triangle tri = lv_triangle_record(sc, h.tri);
    s.material = tri.material;
    s.ns = s.ng;
    if (tri.flags & LV_TRI_HAS_NORMALS) {
        float3 n = b0 * lv_vertex_normal(sc, tri.v[0]) + h.b1 * lv_vertex_normal(sc, tri.v[1]) +
            h.b2 * lv_vertex_normal(sc, tri.v[2]);
        n = lv_normal_to_world(sc, h.inst, n);
        float len2 = dot(n, n);
        if (len2 > 0.0f && isfinite(len2)) {
            n *= rsqrt(len2);
            s.ns = dot(n, s.ng) < 0.0f ? -n : n;
        }
    }
    s.uv = (float2)(0.0f);
    if (tri.flags & LV_TRI_HAS_UVS)
        s.uv = b0 * lv_vertex_uv(sc, tri.v[0]) + h.b1 * lv_vertex_uv(sc, tri.v[1]) + h.b2 * lv_vertex_uv(sc, tri.v[2]);
    return s;
}

inline lv_bsdf lv_surface_bsdf(const lv_scene *sc, const lv_surface *s)
{
    __global const lv_material *m = &sc->materials[s->material];
    lv_bsdf b;
    b.type = m->bsdf;
    b.base = LV_F3(m->base_color);
#ifdef LV_FEATURE_TEXTURES
    if (m->base_color_texture >= 0) {
        float2 uv = (float2)(m->uv_transform[0] * s->uv.x + m->uv_transform[1] * s->uv.y + m->uv_transform[2],
                             m->uv_transform[3] * s->uv.x + m->uv_transform[4] * s->uv.y + m->uv_transform[5]);
        b.base *= lv_texture_rgb(sc, m->base_color_texture, uv, m->texture_sampling);
    }
#endif
    b.alpha = m->alpha;
    b.ior = m->ior;
    b.specular = m->specular;
    return b;
}

/* Whether the segment that ended at s ran inside a glass volume (it
 * arrived at the back face), where Beer-Lambert absorption applies. */
inline int lv_inside_glass(__global const lv_material *m, const lv_surface *s)
{
#ifdef LV_FEATURE_GLASS
    return m->bsdf == LV_BSDF_GLASS && !s->front;
#else
    return 0;
#endif
}

/* The shading frame at s for a ray arriving along dir, and whether the
 * surface scatters light on that side at all. Opaque surfaces turn the frame
 * toward the viewer when double-sided and are black from behind otherwise;
 * dielectrics keep +z on the front face. */
inline int lv_shading_frame(const lv_scene *sc, const lv_surface *s, float3 dir, lv_frame *f)
{
    __global const lv_material *m = &sc->materials[s->material];
    float3 n = s->ns;
    if (!lv_bsdf_transmits(m->bsdf) && !s->front) {
        if (!m->double_sided) return 0;
        n = -n;
    }
    *f = lv_frame_make(n);
    return 1;
}

#endif
