#include "session_internal.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../scene/materials.h"
#include "../util/timer.h"

/* Opens one device and makes the packed scene ready on it. */
static lvcl_error open_device(lvcl_session *s, const char *spec, const lvcl_session_config *cfg, session_device *sd,
                              lvcl_status *st)
{
    lvcl_error e;
    if ((e = lvcl_device_open(spec, &sd->device, st))) return e;
    if (cfg->device_memory) lvcl_device_limit_memory(&sd->device, cfg->device_memory);
    if ((e = lvcl_device_scene_upload(&sd->device, &s->scene, &s->packed, &sd->device_scene, st))) return e;
    return lvcl_program_build(&sd->device, s->features | cfg->build_flags, cfg->fast_math, cfg->announce_builds,
                              &sd->program, st);
}

static lvcl_error open_devices(lvcl_session *s, const lvcl_session_config *cfg, lvcl_status *st)
{
    int indices[LVCL_MAX_DEVICES], n;
    lvcl_error e = lvcl_device_list_parse(cfg->device, indices, &n, st);
    if (e) return e;
    double t = lvcl_seconds();
    if ((e = lvcl_accel_build(&s->scene, &s->accel, st))) return e;
    s->bvh_build_seconds = lvcl_seconds() - t;
    if (s->accel.skipped)
        lvcl_warn("%zu triangles of zero area or with non-finite vertices left out", s->accel.skipped);
    if ((e = lvcl_pack_scene(&s->scene, &s->accel, cfg->seed, (uint32_t)cfg->max_depth, &s->packed, st))) return e;
    s->features = lvcl_scene_features(&s->scene);
    if (n == 0) {
        s->device_count = 1;
        return open_device(s, cfg->device, cfg, &s->devices[0], st);
    }
    for (int d = 0; d < n; d++) {
        char spec[16];
        snprintf(spec, sizeof spec, "%d", indices[d]);
        s->device_count = d + 1;
        if ((e = open_device(s, spec, cfg, &s->devices[d], st))) return e;
    }
    return LVCL_OK;
}

lvcl_error lvcl_session_open(lvcl_scene *scene, const lvcl_session_config *cfg, lvcl_session **out, lvcl_status *st)
{
    *out = NULL;
    lvcl_session *s = calloc(1, sizeof *s);
    if (!s) {
        lvcl_scene_free(scene);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for a session");
    }
    s->scene = *scene;
    s->cluster = cfg->cluster;
    memset(scene, 0, sizeof *scene);
    lvcl_error e = open_devices(s, cfg, st);
    if (e) {
        lvcl_session_close(s);
        return e;
    }
    *out = s;
    return LVCL_OK;
}

void lvcl_session_close(lvcl_session *s)
{
    if (!s) return;
    for (int d = 0; d < s->device_count; d++) {
        session_device *sd = &s->devices[d];
        lvcl_volume_release(sd->volume);
        lvcl_program_release(&sd->program);
        lvcl_device_scene_release(&sd->device_scene);
        lvcl_device_close(&sd->device);
    }
    free(s->gather_odds);
    lvcl_packed_scene_free(&s->packed);
    lvcl_accel_free(&s->accel);
    lvcl_scene_free(&s->scene);
    free(s);
}

int lvcl_session_device_count(const lvcl_session *s)
{
    return s->device_count;
}

const lvcl_device *lvcl_session_device(const lvcl_session *s, int d)
{
    return &s->devices[d].device;
}

const lvcl_device_scene *lvcl_session_device_scene(const lvcl_session *s, int d)
{
    return &s->devices[d].device_scene;
}

const lvcl_program *lvcl_session_program(const lvcl_session *s, int d)
{
    return &s->devices[d].program;
}

const lvcl_light_volume *lvcl_session_volume(const lvcl_session *s, int d)
{
    return s->devices[d].volume;
}

lvcl_pass_share lvcl_session_pass_share(const lvcl_session *s, int d)
{
    return s->devices[d].pass;
}

const lvcl_scene *lvcl_session_scene(const lvcl_session *s)
{
    return &s->scene;
}

int lvcl_session_sees_through(const lvcl_session *s, const lvcl_render_request *req)
{
    return req->mode != LVCL_MODE_LV_ALL && req->see_through && (s->features & LVCL_FEATURE_GLASS);
}

int lvcl_session_volume_sees_through(const lvcl_session *s, const lvcl_render_request *req)
{
    return req->mode == LVCL_MODE_LV && lvcl_session_sees_through(s, req);
}

unsigned lvcl_session_features(const lvcl_session *s)
{
    return s->features;
}

const lvcl_accel *lvcl_session_accel(const lvcl_session *s)
{
    return &s->accel;
}

const lvcl_packed_scene *lvcl_session_packed_scene(const lvcl_session *s)
{
    return &s->packed;
}

double lvcl_session_bvh_build_seconds(const lvcl_session *s)
{
    return s->bvh_build_seconds;
}

double lvcl_session_volume_seconds(const lvcl_session *s)
{
    double slowest = 0;
    for (int d = 0; d < s->device_count; d++) {
        const lvcl_light_volume *v = lvcl_session_volume(s, d);
        double t = v ? lvcl_volume_stats_of(v).trace_seconds : 0;
        if (t > slowest) slowest = t;
    }
    return slowest > 0 ? slowest + s->merge_seconds : 0;
}

const lvcl_budget_report *lvcl_session_budget(const lvcl_session *s)
{
    return &s->budget;
}

const lvcl_guided_report *lvcl_session_guided(const lvcl_session *s)
{
    return &s->guided;
}
