/* --stats: what a run did and how long each part took, as JSON. */
#ifndef LVCL_STATS_H
#define LVCL_STATS_H

#include "bvh.h"
#include "options.h"
#include "program.h"
#include "render_pt.h"
#include "scene.h"

typedef struct {
    const lvcl_options *options;
    const lvcl_device *device;
    const lvcl_scene *scene;
    const lvcl_bvh *bvh;
    const lvcl_program *program;
    const lvcl_render_result *result;
    unsigned features;
    size_t device_bytes;
    double process_start;
    double scene_load_seconds;
    double bvh_build_seconds;
    double startup_seconds; /* process start to the first kernel launch */
} lvcl_stats;

lvcl_error lvcl_stats_write(const char *path, const lvcl_stats *s, lvcl_status *st);

#endif
