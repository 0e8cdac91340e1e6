/* Warps from the unit square to directions and points, with their pdfs. */
#ifndef LV_SAMPLING_H
#define LV_SAMPLING_H

#include "geometry.h"

/* (cos phi, sin phi) for the samplers' angles (|phi| up to a few pi):
 * folded by quarter turns to [-pi/4, pi/4], then Taylor series to the
 * x^9 and x^8 terms (truncation below 4e-8 there). PoCL's sin and cos run a
 * general argument reduction that took 6% of a path trace. */
inline float2 lv_cos_sin(float phi)
{
#if LV_HAS_FP_REASSOCIATE_PRAGMA
#pragma clang fp reassociate(off) /* fast math would fold the two parts of pi/2 */
#endif
    float q = rint(phi * (2.0f / LV_PI));
    /* pi/2 in two parts (Cody and Waite), the first of 20 bits so that
     * q times it is exact for |q| < 16 and x keeps its low bits */
    float x = (phi - q * 1.57079601287841796875f) - q * 3.139164786504813e-7f, x2 = x * x;
    float s = x + x * x2 * (-1.0f / 6.0f + x2 * (1.0f / 120.0f + x2 * (-1.0f / 5040.0f + x2 * (1.0f / 362880.0f))));
    float c = 1.0f + x2 * (-0.5f + x2 * (1.0f / 24.0f + x2 * (-1.0f / 720.0f + x2 * (1.0f / 40320.0f))));
    int k = (int)q & 3;
    return k == 0 ? (float2)(c, s) : k == 1 ? (float2)(-s, c) : k == 2 ? (float2)(-c, -s) : (float2)(s, -c);
}

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
    return r * lv_cos_sin(phi);
}

/* Cosine-weighted direction about +z; pdf = z / pi. */
inline float3 lv_sample_cosine_hemisphere(float2 u)
{
    float2 d = lv_square_to_disk(u);
    float z = sqrt(fmax(0.0f, 1.0f - d.x * d.x - d.y * d.y));
    return (float3)(d.x, d.y, z);
}

/* A direction from the von Mises-Fisher distribution about unit mu of
 * concentration kappa > 0, density kappa exp(kappa (mu . w - 1)) /
 * (2 pi (1 - exp(-2 kappa))). The angle from mu comes from inverting its
 * cdf for 1 - cos, which keeps the precision that 1 + log(..) / kappa
 * loses near mu when kappa is large. */
inline float3 lv_sample_vmf(float3 mu, float kappa, float2 u)
{
    float below = fmax(u.x + (1.0f - u.x) * exp(-2.0f * kappa), 1e-30f);
    float t = clamp(-log(below) / kappa, 0.0f, 2.0f); /* 1 - cos theta */
    float s = sqrt(fmax(0.0f, t * (2.0f - t)));
    float2 cs = lv_cos_sin(2.0f * LV_PI * u.y);
    return lv_to_world(lv_frame_make(mu), (float3)(s * cs.x, s * cs.y, 1.0f - t));
}

/* lv_sample_vmf's density at unit w; mu . w - 1 as -|w - mu|^2 / 2, exact
 * where they are close. */
inline float lv_vmf_pdf(float3 mu, float kappa, float3 w)
{
    float3 d = w - mu;
    return kappa / (2.0f * LV_PI * -expm1(-2.0f * kappa)) * exp(-0.5f * kappa * dot(d, d));
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
