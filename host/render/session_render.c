/* The session's camera passes: each device's kernel bound by the contract
 * (kernels/shared_types.h) and handed to the image pass. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "session_internal.h"

/* Whether the pass's light samples go on through glass: as asked for pt
 * and guided paths; for the gather, as the volume left that light out,
 * whatever the request says. */
static int pass_sees_through(const lvcl_session *s, const session_device *sd, const lvcl_render_request *req)
{
    if (req->mode == LVCL_MODE_PT || req->mode == LVCL_MODE_GUIDED) return lvcl_session_sees_through(s, req);
    return lvcl_volume_stats_of(sd->volume).see_through;
}

/* Binds a camera pass kernel's arguments: the scene's (and the light
 * volume's, for the gather) and the camera; the pass binds the pixel range,
 * the sample and the sum (pd->pixel_args says where). */
static lvcl_error bind_pass_args(const lvcl_session *s, session_device *sd, lvcl_pass_device *pd,
                                 const lvcl_render_request *req, const lv_camera *camera, lvcl_status *st)
{
    if (req->mode == LVCL_MODE_PT) {
        pd->pixel_args = LVCL_PIXEL_ARG_INDICES(lv_pt_pass);
        lvcl_pt_pass_args a = {
            .scene = &sd->device_scene.buffers, .see_through = pass_sees_through(s, sd, req), .camera = *camera};
        return lvcl_bind_lv_pt_pass(pd->kernel, &a, st);
    }
    const lvcl_light_volume *v = sd->volume;
    if (req->mode == LVCL_MODE_GUIDED) {
        pd->pixel_args = LVCL_PIXEL_ARG_INDICES(lv_guided_pass);
        lvcl_guided_pass_args a = {
            .scene = &sd->device_scene.buffers,
            .volume = lvcl_volume_kernel_buffers(v),
            .bin_table = lvcl_volume_bin_table(v),
            .fine_bin_table = lvcl_volume_fine_bin_table(v),
            .guide_table = lvcl_volume_guide_table(v),
            .see_through = pass_sees_through(s, sd, req),
            .camera = *camera,
        };
        return lvcl_bind_lv_guided_pass(pd->kernel, &a, st);
    }
    pd->pixel_args = LVCL_PIXEL_ARG_INDICES(lv_gather_pass);
    cl_mem axis_sums;
    lvcl_error e = lvcl_volume_axis_sums(sd->volume, &sd->program, &axis_sums, st);
    if (e) return e;
    lvcl_gather_pass_args a = {
        .scene = &sd->device_scene.buffers,
        .volume = lvcl_volume_kernel_buffers(v),
        .bin_table = lvcl_volume_bin_table(v),
        .fine_bin_table = lvcl_volume_fine_bin_table(v),
        .axis_sums = axis_sums,
        .flags = (req->mode == LVCL_MODE_LV_ALL ? LV_GATHER_ALL : 0u) | (req->integrate ? LV_GATHER_INTEGRATE : 0u) |
                 (pass_sees_through(s, sd, req) ? LV_GATHER_SEE_THROUGH : 0u),
        .threshold = (float)(req->threshold > 0 ? req->threshold : 0.5 * sqrt(3.0) * lvcl_volume_grid(v)->cell_size),
        .camera = *camera,
    };
    return lvcl_bind_lv_gather_pass(pd->kernel, &a, st);
}

static const char *pass_kernel_name(lvcl_mode mode)
{
    switch (mode) {
    case LVCL_MODE_PT:
        return "lv_pt_pass";
    case LVCL_MODE_GUIDED:
        return "lv_guided_pass";
    default:
        return "lv_gather_pass";
    }
}

lvcl_error lvcl_session_camera_pass(lvcl_session *s, const lvcl_render_request *req, int width, int height,
                                    const lvcl_pass_settings *pass, lvcl_render_result *out, lvcl_status *st)
{
    int w, h;
    lvcl_image_size(&s->scene.camera, width, height, &w, &h);
    lv_camera cam = lvcl_camera_make(&s->scene.camera, s->packed.bounds_min, s->packed.bounds_max, w, h);
    lvcl_pass_device passes[LVCL_MAX_DEVICES];
    memset(passes, 0, sizeof passes);
    lvcl_error e = LVCL_OK;
    for (int d = 0; d < s->device_count && !e; d++) {
        session_device *sd = &s->devices[d];
        passes[d].device = &sd->device;
        if ((e = lvcl_kernel_create(&sd->program, pass_kernel_name(req->mode), &passes[d].kernel, st))) break;
        e = bind_pass_args(s, sd, &passes[d], req, &cam, st);
    }
    if (!e) e = lvcl_image_pass(passes, s->device_count, &cam, s->cluster, pass, out, st);
    if (!e) out->see_through = pass_sees_through(s, &s->devices[0], req);
    if (!e) out->view_odds = s->view_odds && req->mode != LVCL_MODE_PT && req->mode != LVCL_MODE_GUIDED;
    for (int d = 0; d < s->device_count; d++) {
        if (passes[d].kernel) clReleaseKernel(passes[d].kernel);
        passes[d].kernel = NULL;
        s->devices[d].pass = (lvcl_pass_share){
            .bands = passes[d].bands, .pixels = passes[d].pixels, .busy_seconds = passes[d].busy_seconds};
    }
    return e;
}

/* PoCL compiles a kernel's machine code per local size and per size class
 * (under 65,536 work-items or not) at its first launch; a pass of one
 * device launches over every pixel (the first samples, the pilots) and
 * over the pixels adaptive sampling picks, so it meets both classes. The
 * warm-up renders one sample of an image of each. */
static const int warm_up_sides[2] = {256, 8};

lvcl_error lvcl_session_warm_camera_pass(lvcl_session *s, const lvcl_render_request *req, lvcl_status *st)
{
    lvcl_pass_settings warm = {.spp = 1};
    lvcl_error e = LVCL_OK;
    for (int i = 0; i < 2 && !e; i++) {
        lvcl_render_result img = {0};
        e = lvcl_session_camera_pass(s, req, warm_up_sides[i], warm_up_sides[i], &warm, &img, st);
        free(img.rgb);
    }
    return e;
}

lvcl_error lvcl_session_render(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                               lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    s->budget = (lvcl_budget_report){0};
    s->guided = (lvcl_guided_report){0};
    if (req->pass.time_limit > 0 && lvcl_cluster_shared(s->cluster))
        e = lvcl_fail(st, LVCL_ERR_USAGE, "--time-limit works in one process only, not over %d ranks",
                      s->cluster->size);
    else if (req->pass.time_limit > 0 && s->device_count > 1)
        e = lvcl_fail(st, LVCL_ERR_USAGE, "--time-limit works on one device only, not on %d", s->device_count);
    for (int d = 0; d < s->device_count && !e; d++)
        e = lvcl_image_pass_check_size(&s->devices[d].device, req->width, req->height, st);
    /* Refusals every process meets are reported once, as themselves. */
    if ((e = lvcl_cluster_agree(s->cluster, e, st))) return e;
    /* Every render starts from the packed light odds; an lv trace may
     * then make them follow the view (session_view.c). */
    if ((e = lvcl_session_view_start(s, 0, st))) return e;
    if (req->mode == LVCL_MODE_PT) {
        if (req->pass.time_limit > 0 && (e = lvcl_session_warm_camera_pass(s, req, st))) return e;
        return lvcl_session_camera_pass(s, req, req->width, req->height, &req->pass, out, st);
    }
    if (req->mode == LVCL_MODE_GUIDED) return lvcl_session_render_guided(s, req, out, st);
    /* Under a time limit the whole render keeps to it. */
    if (req->pass.time_limit > 0) return lvcl_session_render_budget(s, req, out, st);
    lvcl_volume_settings vs = req->volume;
    vs.store_emitted = req->mode == LVCL_MODE_LV_ALL;
    vs.see_through = lvcl_session_volume_sees_through(s, req);
    if ((e = lvcl_session_trace_volume(s, &vs, st))) return e;
    return lvcl_session_camera_pass(s, req, req->width, req->height, &req->pass, out, st);
}

lvcl_error lvcl_session_render_pt(lvcl_session *s, int width, int height, const lvcl_pass_settings *settings,
                                  lvcl_render_result *out, lvcl_status *st)
{
    lvcl_render_request req = {.mode = LVCL_MODE_PT, .width = width, .height = height, .pass = *settings};
    return lvcl_session_render(s, &req, out, st);
}
