/* The camera passes (path tracing, final gather): one sample per pixel per
 * launch, added to a running sum, until the sample count or the time limit
 * is reached. On several devices the image is cut into bands of rows that
 * the devices take one at a time as they finish (dynamic load balancing). */
#ifndef LVCL_IMAGE_PASS_H
#define LVCL_IMAGE_PASS_H

#include "../device/kernel_args.h"
#include "cluster.h"
#include "../../kernels/shared_types.h"

typedef struct {
    int spp;
    int first_sample;  /* sample indices first_sample .. first_sample + spp - 1 (0 for an image) */
    double time_limit; /* seconds, 0 = none; one device only (lvcl_session_render refuses it on more) */
    int progress;      /* draw a progress bar on stderr */
    int adaptive;      /* adaptive sampling (adaptive_sampling.h); one device only, uniform on several or over a cluster */
} lvcl_pass_settings;

typedef struct {
    float *rgb; /* width x height x 3, malloc'ed; the caller frees it */
    int width, height;
    int samples;                 /* samples per pixel actually taken */
    int adaptive;                /* the samples were placed by adaptive sampling (one device, past one epoch) */
    int see_through;             /* light samples went on through glass (kernels/integrator/see_through.h) */
    int view_odds;               /* lv: the lights' odds followed the camera's view (host/render/session_view.c) */
    double first_launch_seconds; /* first launch, which may compile machine code */
    double render_seconds;
} lvcl_render_result;

/* One device's share of a pass. The caller has bound the kernel's
 * arguments but its pixel arguments (LV_PIXEL_ARGS: camera, pixel list and
 * range, first sample, sums), which the pass binds at the indices pixel_args names.
 * The pass fills in the work the device did. */
typedef struct {
    const lvcl_device *device;
    cl_kernel kernel;
    lvcl_pixel_arg_indices pixel_args;
    int bands;           /* bands rendered */
    size_t pixels;       /* pixels rendered */
    double busy_seconds; /* time spent rendering them */
} lvcl_pass_device;

/* Device memory a pass holds per pixel: the RGBA sums, the squared sums
 * (adaptive sampling's variance) and the pixel list. */
#define LVCL_PIXEL_DEVICE_BYTES (4 * sizeof(float) + sizeof(float) + sizeof(uint32_t))

/* Whether a width x height pass fits `dev` (its largest buffer and all of
 * its memory); else LVCL_ERR_TOO_LARGE naming what it would need. Checked
 * before any work, so a long particle trace is not lost to it. */
lvcl_error lvcl_image_pass_check_size(const lvcl_device *dev, int width, int height, lvcl_status *st);

/* Renders the image over the devices and, with a cluster, the devices of
 * every process (bands handed out by the cluster's counter; each process
 * ends with the whole image). */
lvcl_error lvcl_image_pass(lvcl_pass_device *devices, int device_count, const lv_camera *camera, lvcl_cluster *cluster,
                           const lvcl_pass_settings *settings, lvcl_render_result *out, lvcl_status *st);

#endif
