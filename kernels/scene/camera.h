/* Primary rays from the pinhole camera (see lv_camera in shared_types.h). */
#ifndef LV_CAMERA_H
#define LV_CAMERA_H

#include "../bvh/traverse.h"

/* The ray through image position (x + jitter.x, y + jitter.y) in pixels. */
inline lv_ray lv_camera_ray(lv_camera c, uint x, uint y, float2 jitter)
{
    float sx = 2.0f * ((float)x + jitter.x) / (float)c.width - 1.0f;
    float sy = 1.0f - 2.0f * ((float)y + jitter.y) / (float)c.height;
    return lv_ray_make(LV_F3(c.origin), normalize(LV_F3(c.forward) + sx * LV_F3(c.right) + sy * LV_F3(c.up)), LV_FAR,
                       LV_NO_HIT, LV_NO_HIT);
}

#endif
