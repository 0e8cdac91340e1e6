/* Guided path tracing (docs/guided.md): the light volume, traced as lv
 * mode traces it (indirect light only: light samples find the direct),
 * guides the camera paths' scattering (kernels/volume/guide.h). */
#include <math.h>
#include <stdlib.h>

#include "session_internal.h"
#include "../util/timer.h"

/* Under a time limit, the most of it the trace may take (it stops at the
 * first batch past it); the paths take the rest. A first choice, not
 * measured against others (docs/guided.md, "Open"). */
#define GUIDE_TIME_SHARE 0.1
/* Particles a time-limited trace stops at if its share of the time has not
 * ended it first. */
#define GUIDE_PARTICLES_MAX (1u << 24)
/* Under a time limit the trace stops first at this part of its share; the
 * pilots then choose guided or plain paths on that guide, and only guided
 * paths have the trace go on to the rest. */
#define CHOICE_TRACE_PART 0.25
/* The pilots that choose between guided and plain paths: samples per
 * pixel of each, at the image's width and height over CHOICE_PILOT_SCALE. */
#define CHOICE_PILOT_SPP 8
#define CHOICE_PILOT_SCALE 2

/* Traces the volume vs asks for on every device and fills each device's
 * guide table from it. */
static lvcl_error trace_guide(lvcl_session *s, const lvcl_volume_settings *vs, lvcl_status *st)
{
    lvcl_error e = lvcl_session_trace_volume(s, vs, st);
    for (int d = 0; d < s->device_count && !e; d++)
        e = lvcl_volume_fill_guide(s->devices[d].volume, &s->devices[d].program, st);
    return e;
}

/* Before a timed render: a small trace, its guide table and the warm-up
 * images (lvcl_session_warm_camera_pass) of guided and of plain paths,
 * thrown away (the timed trace starts a new volume), so that neither the
 * budget nor the pilots pay for PoCL's first-launch compiles. */
static lvcl_error warm_up(lvcl_session *s, const lvcl_render_request *req, const lvcl_render_request *plain,
                          const lvcl_volume_settings *vs, lvcl_status *st)
{
    lvcl_volume_settings warm = *vs;
    warm.particles = LVCL_WARM_UP_PARTICLES;
    warm.progress = 0;
    lvcl_error e = trace_guide(s, &warm, st);
    if (!e) e = lvcl_session_warm_camera_pass(s, req, st);
    return e ? e : lvcl_session_warm_camera_pass(s, plain, st);
}

/* Under a time limit, once the guide is traced: two pilots of guided
 * paths and two of plain ones, of different samples. Each kind's cost is
 * its noise per sample times its time per sample (the relMSE between its
 * two pilots times their seconds, up to a factor the kinds share), and
 * the cheaper kind renders the image: where the guide buys less than it
 * costs (even light, caustics finer than a bin), the time goes to the
 * path tracer. Both are unbiased, so the choice only moves the noise. */
static lvcl_error choose_paths(lvcl_session *s, const lvcl_render_request *req, const lvcl_render_request *plain,
                               lvcl_guided_report *g, lvcl_status *st)
{
    const lvcl_render_request *kinds[2] = {req, plain};
    lvcl_render_result img[4] = {{0}};
    double seconds[2] = {0}, start = lvcl_seconds();
    lvcl_error e = LVCL_OK;
    for (int k = 0; k < 2 && !e; k++) {
        double t = lvcl_seconds();
        e = lvcl_session_pilot(s, kinds[k], CHOICE_PILOT_SCALE, 0, CHOICE_PILOT_SPP, &img[2 * k], st);
        if (!e)
            e = lvcl_session_pilot(s, kinds[k], CHOICE_PILOT_SCALE, CHOICE_PILOT_SPP, CHOICE_PILOT_SPP,
                                   &img[2 * k + 1], st);
        seconds[k] = lvcl_seconds() - t;
    }
    float *den = e ? NULL : lvcl_pilot_denominators(img, 4);
    if (!e && !den) e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the pilot images");
    if (!e) {
        size_t n = (size_t)img[0].width * img[0].height * 3;
        g->guided_cost = lvcl_weighted_difference(img[0].rgb, img[1].rgb, den, n) * seconds[0];
        g->plain_cost = lvcl_weighted_difference(img[2].rgb, img[3].rgb, den, n) * seconds[1];
        g->plain = g->plain_cost < g->guided_cost;
        g->pilot_seconds = lvcl_seconds() - start;
        g->used = 1;
    }
    free(den);
    for (int i = 0; i < 4; i++) free(img[i].rgb);
    return e;
}

/* Goes on with the trace on the one device a time limit runs on, up to
 * vs->particles or the deadline, then refills the guide table. */
static lvcl_error trace_more(lvcl_session *s, const lvcl_volume_settings *vs, double deadline, lvcl_status *st)
{
    session_device *sd = &s->devices[0];
    lvcl_volume_settings more = *vs;
    more.first_particle = lvcl_volume_stats_of(sd->volume).particles;
    more.deadline = deadline;
    if (more.first_particle >= more.particles || lvcl_seconds() >= deadline) return LVCL_OK;
    lvcl_error e = lvcl_volume_trace(sd->volume, &sd->program, &sd->device_scene, &more, st);
    if (!e) e = lvcl_volume_adapt(sd->volume, 0, more.merge_tolerance, st);
    if (!e) e = lvcl_volume_finish(sd->volume, &sd->program, st);
    return e ? e : lvcl_volume_fill_guide(sd->volume, &sd->program, st);
}

lvcl_error lvcl_session_render_guided(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                                      lvcl_status *st)
{
    lvcl_volume_settings vs = req->volume;
    vs.store_emitted = 0;
    vs.see_through = 0; /* the guide keeps all light; the paths' light samples see through glass */
    /* The guide reads bins only: no subcells, so no lit points or
     * visibility rays (a quarter of the trace's time). */
    vs.subcells = 0;
    lvcl_pass_settings pass = req->pass;
    lvcl_render_request plain = *req;
    plain.mode = LVCL_MODE_PT;
    lvcl_error e = pass.time_limit > 0 ? warm_up(s, req, &plain, &vs, st) : LVCL_OK;
    if (e) return e;
    double start = lvcl_seconds();
    if (pass.time_limit > 0) {
        if (!vs.particles) vs.particles = GUIDE_PARTICLES_MAX;
        vs.deadline = start + CHOICE_TRACE_PART * GUIDE_TIME_SHARE * pass.time_limit;
    }
    e = trace_guide(s, &vs, st);
    if (e == LVCL_ERR_CLUSTER || (e = lvcl_cluster_agree(s->cluster, e, st))) return e;
    if (pass.time_limit > 0) {
        e = choose_paths(s, req, &plain, &s->guided, st);
        if (!e && !s->guided.plain) e = trace_more(s, &vs, start + GUIDE_TIME_SHARE * pass.time_limit, st);
        if (e) return e;
    }
    /* At least one sample is taken, however long the trace and pilots took. */
    if (pass.time_limit > 0) pass.time_limit = fmax(pass.time_limit - (lvcl_seconds() - start), 1e-3);
    return lvcl_session_camera_pass(s, s->guided.plain ? &plain : req, req->width, req->height, &pass, out, st);
}
