/* The camera passes (path tracing, final gather): one sample per pixel per
 * launch, added to a running sum, until the sample count or the time limit
 * is reached. */
#ifndef LVCL_IMAGE_PASS_H
#define LVCL_IMAGE_PASS_H

#include "device.h"
#include "../kernels/shared_types.h"

typedef struct {
    int spp;
    double time_limit; /* seconds, 0 = none */
    int progress;      /* draw a progress bar on stderr */
} lvcl_pass_settings;

typedef struct {
    float *rgb;  /* width x height x 3, malloc'ed; the caller frees it */
    int width, height;
    int samples;        /* samples per pixel actually taken */
    double first_launch_seconds; /* first launch, which may compile machine code */
    double render_seconds;
} lvcl_render_result;

/* Runs `kernel`, whose last three arguments, from index `camera_arg`, are
 * (lv_camera, uint sample index, __global float4 *sum); the caller has set
 * all the others. */
lvcl_error lvcl_image_pass(const lvcl_device *dev, cl_kernel kernel, cl_uint camera_arg, const lv_camera *camera,
                           const lvcl_pass_settings *settings, lvcl_render_result *out, lvcl_status *st);

#endif
