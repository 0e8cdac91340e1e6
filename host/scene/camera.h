/* The image camera: the glTF camera, or one framing the scene bounds. */
#ifndef LVCL_CAMERA_H
#define LVCL_CAMERA_H

#include "scene.h"

/* Image size from the user's --width/--height (0 = not given) and the
 * camera's aspect ratio: width defaults to 512. */
void lvcl_image_size(const lvcl_camera_desc *cam, int width, int height, int *out_w, int *out_h);

/* The kernels' camera for a width x height image. Without a glTF camera it
 * looks along -z at the centre of the bounds from far enough to see them. */
lv_camera lvcl_camera_make(const lvcl_camera_desc *cam, const float bmin[3], const float bmax[3], int width,
                           int height);

#endif
