/* Warps from the unit square to directions and points, with their pdfs. */
#ifndef LV_SAMPLING_H
#define LV_SAMPLING_H

#include "geometry.h"

/* Shirley and Chiu's concentric map: square [0,1)^2 to the unit disk,
 * area-preserving and with low distortion. */
inline float2 lv_square_to_disk(float2 u)
{
    float a = 2.0f * u.x - 1.0f, b = 2.0f * u.y - 1.0f;
    if (a == 0.0f && b == 0.0f) return (float2)(0.0f, 0.0f);
    float r, phi;
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (LV_PI / 4.0f) * (b / a);
    } else {
        r = b;
        phi = (LV_PI / 2.0f) - (LV_PI / 4.0f) * (a / b);
    }
    return (float2)(r * cos(phi), r * sin(phi));
}

/* Cosine-weighted direction about +z; pdf = z / pi. */
inline float3 lv_sample_cosine_hemisphere(float2 u)
{
    float2 d = lv_square_to_disk(u);
    float z = sqrt(fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    return (float3)(d.x, d.y, z);
}

/* Uniform barycentrics (b1, b2) on a triangle (the square-root warp); the
 * point is (1 - b1 - b2) v0 + b1 v1 + b2 v2. */
inline float2 lv_sample_triangle(float2 u)
{
    float s = sqrt(u.x);
    return (float2)(1.0f - s, u.y * s);
}

/* Converts an area density at a point seen at distance d under cosine cos_l
 * to a solid-angle density. */
inline float lv_area_to_solid_angle(float pdf_area, float dist2, float cos_l)
{
    return pdf_area * dist2 / fmax(fabs(cos_l), 1e-12f);
}

/* Veach's power heuristic with exponent 2. */
inline float lv_power_heuristic(float pdf_a, float pdf_b)
{
    float a = pdf_a * pdf_a, b = pdf_b * pdf_b;
    return a + b > 0.0f ? a / (a + b) : 0.0f;
}

#endif
