/* Small vector helpers, orthonormal frames and ray-origin offsets. */
#ifndef LV_GEOMETRY_H
#define LV_GEOMETRY_H

#include "../shared_types.h"

#define LV_PI 3.14159265358979f
#define LV_INV_PI 0.318309886183791f

/* A float3 from three consecutive floats in any address space. */
#define LV_F3(a) ((float3)((a)[0], (a)[1], (a)[2]))

inline float lv_max3(float3 v)
{
    return fmax(v.x, fmax(v.y, v.z));
}

/* The weights are the host's too (LV_LUMINANCE, shared_types.h). */
inline float lv_luminance(float3 c)
{
    return LV_LUMINANCE(c.x, c.y, c.z);
}

inline int lv_finite3(float3 v)
{
    return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

/* An orthonormal frame around unit n, without branches on n's direction
 * (Duff et al. 2017, "Building an orthonormal basis, revisited"). */
typedef struct {
    float3 t, b, n;
} lv_frame;

inline lv_frame lv_frame_make(float3 n)
{
    float s = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (s + n.z);
    float c = n.x * n.y * a;
    lv_frame f;
    f.t = (float3)(1.0f + s * n.x * n.x * a, s * c, -s * n.x);
    f.b = (float3)(c, s + n.y * n.y * a, -n.y);
    f.n = n;
    return f;
}

inline float3 lv_to_local(lv_frame f, float3 v)
{
    return (float3)(dot(v, f.t), dot(v, f.b), dot(v, f.n));
}

inline float3 lv_to_world(lv_frame f, float3 v)
{
    return v.x * f.t + v.y * f.b + v.z * f.n;
}

/* How far lv_offset_origin moves p along n (below). */
inline float lv_offset_step(float3 p, float3 n, float scene_scale)
{
    return 0x1p-18f * dot(fabs(n), fabs(p)) + 0x1p-20f * scene_scale;
}

/* Moves a surface point off its surface along the unit normal n (on the
 * side the new ray leaves from), so that the new ray cannot hit the surface
 * it starts on. A point interpolated from a triangle's vertices lies within
 * a few float ulps of the true plane, coordinate by coordinate; the step
 * along n covers that error projected on n (the bound pbrt-v4 uses, with a
 * wide margin), plus a millionth of the scene's size for points near the
 * origin, where ulps vanish. Each coordinate then moves one ulp further
 * along n, so rounding the sum cannot bring it back. Every term scales with
 * the scene, so millimetre and kilometre scenes behave alike. */
inline float3 lv_offset_origin(float3 p, float3 n, float scene_scale)
{
    float3 q = p + lv_offset_step(p, n, scene_scale) * n;
    return nextafter(q, q + n);
}

/* No floating-point contraction in everything that follows, which is
 * every other kernel header (each includes this one, kernels/lvcl.h first).
 * Fused multiply-adds would evaluate the edge functions of two triangles
 * sharing an edge differently (bvh/traverse.h) and let rays slip through.
 * The helpers above were always compiled before the switch; moving it
 * above them changes every image's bits, which tests/data/golden.txt pins. */
#pragma OPENCL FP_CONTRACT OFF

/* Code that fast math must not reassociate says so with "#pragma clang fp
 * reassociate(off)", which clang 12 and later take (PoCL, Intel's runtime,
 * Oclgrind). NVIDIA's OpenCL compiler is an older clang that rejects it and
 * fails the whole build. */
#if defined(__clang__) && __clang_major__ >= 12
#define LV_HAS_FP_REASSOCIATE_PRAGMA 1
#else
#define LV_HAS_FP_REASSOCIATE_PRAGMA 0
#endif

/* How far back along its arriving ray, in offset steps, a new ray may
 * start (lv_leave_point). */
#define LV_LEAVE_REACH 8.0f

/* The origin of a new ray leaving surface point p on the side of unit
 * normal n, where p was found by a ray arriving along -back (unit) after t
 * at `arrived` (lv_surface.arrived). Where the new ray leaves on the side
 * the old one came from, it starts on the old ray, LV_LEAVE_REACH offsets
 * back from `arrived` (at most half the way; where that is not an offset's
 * height above the surface, a grazing ray, the rest along n): where two
 * surfaces meet (a partition against a wall, a wall and a floor) the hit
 * on one may lie within an offset of the other, and an offset along n
 * alone would start the new ray behind that other surface, in the space on
 * its far side; the way back lies in the space the old ray crossed. From
 * `arrived`, not p: a particle from a lamp 2 mm from a wall of one
 * polygon, grazing the wall down to the floor, hit the floor 10^-7 m from
 * the wall's foot, p rounded past the wall, and one step back along so
 * grazing a ray stayed there: the next ray left into the next room (red /
 * blue 0.08 in lv there at 1000:1; 10^-5 of the particles). */
inline float3 lv_leave_point(float3 p, float3 arrived, float3 n, float3 back, float t, float scene_scale)
{
    float step = lv_offset_step(p, n, scene_scale), up = dot(back, n);
    if (up > 0.0f) {
        float along = fmin(LV_LEAVE_REACH * step, 0.5f * t);
        p = arrived + back * along;
        step = fmax(step - along * up, 0.0f);
    }
    float3 q = p + step * n;
    return nextafter(q, q + n);
}

/* The distance t > 0 at which the half-line p + t dir crosses the triangle
 * v0 + b1 e1 + b2 e2, either face (Moller and Trumbore's test), or 0 where
 * it does not. */
inline float lv_half_line_crossing(float3 p, float3 dir, float3 v0, float3 e1, float3 e2)
{
    float3 pv = cross(dir, e2);
    float inv = 1.0f / dot(e1, pv);
    float3 s = p - v0;
    float b1 = dot(s, pv) * inv;
    if (b1 < 0.0f || b1 > 1.0f) return 0.0f;
    float3 qv = cross(s, e1);
    float b2 = dot(dir, qv) * inv;
    if (b2 < 0.0f || b1 + b2 > 1.0f) return 0.0f;
    float t = dot(e2, qv) * inv;
    return t > 0.0f ? t : 0.0f;
}

#endif
