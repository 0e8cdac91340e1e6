/* Primary rays from the pinhole camera (see lv_camera in shared_types.h). */
#ifndef LV_CAMERA_H
#define LV_CAMERA_H

#include "../bvh/traverse.h"
#include "../util/rng.h"

/* The ray through image position (x + jitter.x, y + jitter.y) in pixels. */
inline lv_ray lv_camera_ray(lv_camera c, uint x, uint y, float2 jitter)
{
    float sx = 2.0f * ((float)x + jitter.x) / (float)c.width - 1.0f;
    float sy = 1.0f - 2.0f * ((float)y + jitter.y) / (float)c.height;
    return lv_ray_make(LV_F3(c.origin), normalize(LV_F3(c.forward) + sx * LV_F3(c.right) + sy * LV_F3(c.up)), LV_FAR,
                       LV_NO_HIT, LV_NO_HIT);
}

/* A camera pass's work-item (LV_PIXEL_ARGS in shared_types.h): its pixel,
 * the random stream of that pixel's next sample, and the ray through it. */
typedef struct {
    uint pixel;
    lv_rng rng;
    lv_ray ray;
} lv_camera_sample;

inline lv_camera_sample lv_camera_sample_next(lv_camera c, uint seed, __global const uint *pixel_list, uint first_pixel,
                                              uint first_sample, __global const float4 *sum)
{
    lv_camera_sample s;
    s.pixel = pixel_list[first_pixel + (uint)get_global_id(0)];
    s.rng = lv_rng_make_lattice(seed, s.pixel, first_sample + (uint)sum[s.pixel].w);
    s.ray = lv_camera_ray(c, s.pixel % c.width, s.pixel / c.width, lv_rng_next2(&s.rng));
    return s;
}

/* Adds radiance l to the pixel's sum (the count in w) and the square of
 * its channel mean to sum_sq. */
inline void lv_camera_sample_add(__global float4 *sum, __global float *sum_sq, uint pixel, float3 l)
{
    sum[pixel] += (float4)(l, 1.0f);
    float y = (l.x + l.y + l.z) * (1.0f / 3.0f);
    sum_sq[pixel] += y * y;
}

#endif
