#include "session.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../scene/embedded_scenes.h"
#include "../scene/materials.h"
#include "../util/parallel.h"
#include "../util/timer.h"

lvcl_error lvcl_scene_load(const char *name, lvcl_scene *scene, lvcl_status *st)
{
    struct stat sb;
    if (stat(name, &sb) == 0) return lvcl_scene_load_gltf_file(name, scene, st);
    const lvcl_embedded_scene *e = lvcl_embedded_scene_find(name);
    if (e) return lvcl_scene_load_gltf_memory(e->data, e->size, "", scene, st);
    return lvcl_fail(st, LVCL_ERR_IO, "no such file or embedded scene '%s' (embedded: %s)", name,
                     lvcl_embedded_scene_names());
}

/* The device indices that spec names ("all", or a comma-separated list),
 * or 0 if it names a single device for lvcl_device_open. */
static int device_list(const char *spec, int *indices, lvcl_status *st, lvcl_error *e)
{
    *e = LVCL_OK;
    if (!spec || (strcmp(spec, "all") && !strchr(spec, ','))) return 0;
    int n = 0;
    if (!strcmp(spec, "all")) {
        int count = lvcl_device_count();
        if (count == 0) *e = lvcl_fail(st, LVCL_ERR_DEVICE, "no OpenCL device found");
        for (; n < count && n < LVCL_MAX_DEVICES; n++) indices[n] = n;
        return n;
    }
    for (const char *p = spec; *p;) {
        char *end;
        long v = strtol(p, &end, 10);
        if (end == p || v < 0 || (*end && *end != ',')) {
            *e = lvcl_fail(st, LVCL_ERR_USAGE, "bad device list '%s' (expected indices like 0,2, or all)", spec);
            return 0;
        }
        for (int k = 0; k < n; k++)
            if (indices[k] == v) *e = lvcl_fail(st, LVCL_ERR_USAGE, "device %ld is listed twice in '%s'", v, spec);
        if (n == LVCL_MAX_DEVICES) *e = lvcl_fail(st, LVCL_ERR_USAGE, "more than %d devices in '%s'", LVCL_MAX_DEVICES, spec);
        if (*e) return 0;
        indices[n++] = (int)v;
        p = *end ? end + 1 : end;
    }
    return n;
}

/* Opens one device and makes the packed scene ready on it. */
static lvcl_error open_device(lvcl_session *s, const char *spec, const lvcl_session_config *cfg,
                              lvcl_session_device *sd, lvcl_status *st)
{
    lvcl_error e;
    if ((e = lvcl_device_open(spec, &sd->device, st))) return e;
    if (cfg->device_memory) {
        /* As a device of that size would be: OpenCL promises a quarter of
         * its memory in one buffer, and GPUs often allow no more. */
        if (sd->device.global_mem > cfg->device_memory) sd->device.global_mem = cfg->device_memory;
        if (sd->device.max_alloc > cfg->device_memory / 4) sd->device.max_alloc = cfg->device_memory / 4;
    }
    if ((e = lvcl_device_scene_upload(&sd->device, &s->scene, &s->packed, &sd->device_scene, st))) return e;
    return lvcl_program_build(&sd->device, s->features, cfg->fast_math, &sd->program, st);
}

lvcl_error lvcl_session_open(lvcl_session *s, lvcl_scene *scene, const lvcl_session_config *cfg, lvcl_status *st)
{
    memset(s, 0, sizeof *s);
    s->scene = *scene;
    memset(scene, 0, sizeof *scene);

    lvcl_error e;
    int indices[LVCL_MAX_DEVICES];
    int n = device_list(cfg->device, indices, st, &e);
    if (e) goto fail;
    double t = lvcl_seconds();
    if ((e = lvcl_accel_build(&s->scene, &s->accel, st))) goto fail;
    s->bvh_build_seconds = lvcl_seconds() - t;
    if (s->accel.skipped) lvcl_warn("%zu triangles of zero area or with non-finite vertices left out", s->accel.skipped);
    if ((e = lvcl_pack_scene(&s->scene, &s->accel, cfg->seed, (uint32_t)cfg->max_depth, &s->packed, st))) goto fail;
    s->features = lvcl_scene_features(&s->scene);
    if (n == 0) {
        s->device_count = 1;
        if ((e = open_device(s, cfg->device, cfg, &s->devices[0], st))) goto fail;
        return LVCL_OK;
    }
    for (int d = 0; d < n; d++) {
        char spec[16];
        snprintf(spec, sizeof spec, "%d", indices[d]);
        s->device_count = d + 1;
        if ((e = open_device(s, spec, cfg, &s->devices[d], st))) goto fail;
    }
    return LVCL_OK;
fail:
    lvcl_session_close(s);
    return e;
}

/* Binds a camera pass kernel's arguments: the scene's (and the light
 * volume's, for the gather) and the camera; the pass binds the pixel range,
 * the sample and the sum (pd->pixel_args says where). */
static lvcl_error bind_pass_args(lvcl_session_device *sd, lvcl_pass_device *pd, const lvcl_render_request *req,
                                 const lv_camera *camera, lvcl_status *st)
{
    if (req->mode == LVCL_MODE_PT) {
        pd->pixel_args = LVCL_PIXEL_ARG_INDICES(lv_pt_pass);
        lvcl_pt_pass_args a = {.scene = &sd->device_scene.buffers, .camera = *camera};
        return lvcl_bind_lv_pt_pass(pd->kernel, &a, st);
    }
    const lvcl_light_volume *v = &sd->volume;
    pd->pixel_args = LVCL_PIXEL_ARG_INDICES(lv_gather_pass);
    lvcl_gather_pass_args a = {
        .scene = &sd->device_scene.buffers,
        .volume = &v->buf,
        .bin_directions = v->bin_directions_buf,
        .flags = (req->mode == LVCL_MODE_LV_ALL ? LV_GATHER_ALL : 0u) | (req->integrate ? LV_GATHER_INTEGRATE : 0u),
        .threshold = (float)(req->threshold > 0 ? req->threshold : sqrt(3.0) * v->buf.info.cell_size),
        .camera = *camera,
    };
    return lvcl_bind_lv_gather_pass(pd->kernel, &a, st);
}

typedef struct {
    lvcl_session_device *sd;
    lvcl_volume_settings vs;
    lvcl_error e;
    lvcl_status st;
} trace_job;

static void *trace_part(void *arg)
{
    trace_job *j = arg;
    lvcl_session_device *sd = j->sd;
    j->e = lvcl_volume_trace(&sd->device, &sd->program, &sd->device_scene, &j->vs, &sd->volume, &j->st);
    return NULL;
}

/* The light volume on every device: each takes batches of particles until
 * none is left (a faster device takes more), then the tallies are added and
 * stored on each. */
static lvcl_error build_volume(lvcl_session *s, const lvcl_volume_settings *settings, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    int n = s->device_count;
    for (int d = 0; d < n && !e; d++) {
        lvcl_volume_release(&s->devices[d].volume);
        e = lvcl_volume_create(&s->devices[d].device, &s->packed, settings, &s->devices[d].volume, st);
    }
    if (e) return e;
    trace_job jobs[LVCL_MAX_DEVICES];
    lvcl_particle_source source;
    lvcl_particle_source_init(&source, settings->particles);
    for (int d = 0; d < n; d++) {
        jobs[d] = (trace_job){.sd = &s->devices[d], .vs = *settings};
        jobs[d].vs.source = n > 1 ? &source : NULL;
        jobs[d].vs.progress = settings->progress && d == 0;
    }
    int threads_failed = lvcl_run_parallel(trace_part, jobs, sizeof jobs[0], n);
    lvcl_particle_source_destroy(&source);
    if (threads_failed) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "cannot start a thread per device");
    for (int d = 0; d < n; d++)
        if (jobs[d].e) {
            *st = jobs[d].st;
            return jobs[d].e;
        }
    if (n > 1) {
        const lvcl_device *devs[LVCL_MAX_DEVICES];
        lvcl_light_volume *vols[LVCL_MAX_DEVICES];
        for (int d = 0; d < n; d++) {
            devs[d] = &s->devices[d].device;
            vols[d] = &s->devices[d].volume;
        }
        double t = lvcl_seconds();
        if ((e = lvcl_volume_merge(devs, vols, n, st))) return e;
        s->merge_seconds = lvcl_seconds() - t;
    }
    for (int d = 0; d < n && !e; d++)
        e = lvcl_volume_finish(&s->devices[d].device, &s->devices[d].program, &s->devices[d].volume, st);
    return e;
}

lvcl_error lvcl_session_render(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                               lvcl_status *st)
{
    lvcl_error e;
    if (req->mode != LVCL_MODE_PT) {
        lvcl_volume_settings vs = req->volume;
        vs.store_emitted = req->mode == LVCL_MODE_LV_ALL;
        if ((e = build_volume(s, &vs, st))) return e;
    }
    int w, h;
    lvcl_image_size(&s->scene.camera, req->width, req->height, &w, &h);
    lv_camera cam = lvcl_camera_make(&s->scene.camera, s->packed.bounds_min, s->packed.bounds_max, w, h);
    lvcl_pass_device passes[LVCL_MAX_DEVICES];
    memset(passes, 0, sizeof passes);
    e = LVCL_OK;
    for (int d = 0; d < s->device_count && !e; d++) {
        lvcl_session_device *sd = &s->devices[d];
        passes[d].device = &sd->device;
        if ((e = lvcl_kernel_create(&sd->program, req->mode == LVCL_MODE_PT ? "lv_pt_pass" : "lv_gather_pass",
                                    &passes[d].kernel, st)))
            break;
        e = bind_pass_args(sd, &passes[d], req, &cam, st);
    }
    if (!e) e = lvcl_image_pass(passes, s->device_count, &cam, &req->pass, out, st);
    for (int d = 0; d < s->device_count; d++) {
        if (passes[d].kernel) clReleaseKernel(passes[d].kernel);
        passes[d].kernel = NULL;
        s->devices[d].pass = passes[d];
    }
    return e;
}

lvcl_error lvcl_session_render_pt(lvcl_session *s, int width, int height, const lvcl_pass_settings *settings,
                                  lvcl_render_result *out, lvcl_status *st)
{
    lvcl_render_request req = {0};
    req.mode = LVCL_MODE_PT;
    req.width = width;
    req.height = height;
    req.pass = *settings;
    return lvcl_session_render(s, &req, out, st);
}

void lvcl_session_close(lvcl_session *s)
{
    for (int d = 0; d < s->device_count; d++) {
        lvcl_session_device *sd = &s->devices[d];
        lvcl_volume_release(&sd->volume);
        lvcl_program_release(&sd->program);
        lvcl_device_scene_release(&sd->device_scene);
        lvcl_device_close(&sd->device);
    }
    lvcl_packed_scene_free(&s->packed);
    lvcl_accel_free(&s->accel);
    lvcl_scene_free(&s->scene);
    memset(s, 0, sizeof *s);
}
