#include "camera.h"

#include <math.h>

void lvcl_image_size(const lvcl_camera_desc *cam, int width, int height, int *out_w, int *out_h)
{
    float aspect = cam->present && cam->aspect > 0.0f ? cam->aspect : 1.0f;
    if (width <= 0 && height <= 0) width = 512;
    if (width <= 0) width = (int)lroundf((float)height * aspect);
    if (height <= 0) height = (int)lroundf((float)width / aspect);
    *out_w = width > 0 ? width : 1;
    *out_h = height > 0 ? height : 1;
}

lv_camera lvcl_camera_make(const lvcl_camera_desc *cam, const float bmin[3], const float bmax[3], int width, int height)
{
    lv_camera c = {0};
    c.width = (lv_u32)width;
    c.height = (lv_u32)height;
    float yfov = cam->present ? cam->yfov : 0.6981317f; /* 40 degrees */
    float right[3] = {1, 0, 0}, up[3] = {0, 1, 0}, back[3] = {0, 0, 1};
    if (cam->present) {
        for (int k = 0; k < 3; k++) {
            c.origin[k] = cam->position[k];
            right[k] = cam->right[k];
            up[k] = cam->up[k];
            back[k] = cam->back[k];
        }
    } else {
        /* Back off along +z until a sphere around the bounds fills the view. */
        float radius = 0.0f;
        for (int k = 0; k < 3; k++) radius += (bmax[k] - bmin[k]) * (bmax[k] - bmin[k]);
        radius = 0.5f * sqrtf(radius);
        float dist = radius / sinf(0.5f * yfov);
        for (int k = 0; k < 3; k++) c.origin[k] = 0.5f * (bmin[k] + bmax[k]);
        c.origin[2] += dist;
    }
    float half_h = tanf(0.5f * yfov);
    float half_w = half_h * (float)width / (float)height;
    for (int k = 0; k < 3; k++) {
        c.forward[k] = -back[k];
        c.right[k] = right[k] * half_w;
        c.up[k] = up[k] * half_h;
    }
    return c;
}
