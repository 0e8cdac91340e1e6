/* The light volume's directional bins (docs/light-volume.md): each hemisphere
 * maps to an n x n square by an equal-area map (the concentric disk of
 * Shirley and Chiu, with z = 1 - r^2), so every one of the 2 n^2 bins spans
 * exactly 2 pi / n^2 steradians. Bins 0 .. n^2-1 hold z >= 0, the rest z < 0. */
#ifndef LV_DIRECTION_MAP_H
#define LV_DIRECTION_MAP_H

#include "../util/sampling.h"

/* Inverse of lv_square_to_disk: unit disk to [0,1]^2. */
inline float2 lv_disk_to_square(float2 d)
{
    float r = sqrt(d.x * d.x + d.y * d.y);
    if (r == 0.0f) return (float2)(0.5f, 0.5f);
    float phi = atan2(d.y, d.x); /* (-pi, pi] */
    if (phi < -LV_PI / 4.0f) phi += 2.0f * LV_PI;
    float a, b;
    if (phi < LV_PI / 4.0f) { /* right wedge */
        a = r;
        b = phi * a / (LV_PI / 4.0f);
    } else if (phi < 3.0f * LV_PI / 4.0f) { /* top */
        b = r;
        a = -(phi - LV_PI / 2.0f) * b / (LV_PI / 4.0f);
    } else if (phi < 5.0f * LV_PI / 4.0f) { /* left */
        a = -r;
        b = (phi - LV_PI) * a / (LV_PI / 4.0f);
    } else { /* bottom */
        b = -r;
        a = -(phi - 3.0f * LV_PI / 2.0f) * b / (LV_PI / 4.0f);
    }
    return (float2)(0.5f * (a + 1.0f), 0.5f * (b + 1.0f));
}

/* The bin of unit direction w with n x n bins per hemisphere. */
inline uint lv_direction_bin(float3 w, uint n)
{
    float z = fabs(w.z);
    float r = sqrt(fmax(0.0f, 1.0f - z));
    float xy = sqrt(w.x * w.x + w.y * w.y);
    float2 d = xy > 0.0f ? (float2)(w.x, w.y) * (r / xy) : (float2)(0.0f);
    float2 sq = lv_disk_to_square(d);
    uint i = min((uint)(sq.x * (float)n), n - 1u);
    uint j = min((uint)(sq.y * (float)n), n - 1u);
    return (w.z < 0.0f ? n * n : 0u) + j * n + i;
}

/* A direction inside bin `bin`, uniform in solid angle for uniform u. */
inline float3 lv_bin_direction(uint bin, uint n, float2 u)
{
    uint lower = bin >= n * n;
    uint cell = bin - (lower ? n * n : 0u);
    float2 sq = (float2)(((float)(cell % n) + u.x) / (float)n, ((float)(cell / n) + u.y) / (float)n);
    float2 d = lv_square_to_disk(sq);
    float r2 = d.x * d.x + d.y * d.y;
    float z = 1.0f - r2;
    float s = r2 > 0.0f ? sqrt(fmax(0.0f, 1.0f - z * z) / r2) : 0.0f;
    return (float3)(d.x * s, d.y * s, lower ? -z : z);
}

inline float lv_bin_solid_angle(uint n)
{
    return 2.0f * LV_PI / (float)(n * n);
}

#endif
