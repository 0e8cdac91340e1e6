/* The path-tracing pass (--mode pt): one sample per pixel per launch,
 * until the sample count or the time limit is reached. */
#ifndef LVCL_RENDER_PT_H
#define LVCL_RENDER_PT_H

#include "device_scene.h"
#include "program.h"

typedef struct {
    int spp;
    double time_limit; /* seconds, 0 = none */
    int progress;      /* draw a progress bar on stderr */
} lvcl_pt_settings;

typedef struct {
    float *rgb;  /* width x height x 3, malloc'ed; the caller frees it */
    int width, height;
    int samples;        /* samples per pixel actually taken */
    double first_launch_seconds; /* first launch, which may compile machine code */
    double render_seconds;
} lvcl_render_result;

lvcl_error lvcl_render_pt(const lvcl_device *dev, const lvcl_program *prog, const lvcl_device_scene *ds,
                          const lv_camera *camera, const lvcl_pt_settings *settings, lvcl_render_result *out,
                          lvcl_status *st);

#endif
