/* Guided path tracing (docs/guided.md): the light volume, traced as lv
 * mode traces it (indirect light only: light samples find the direct),
 * guides the camera paths' scattering (kernels/volume/guide.h).
 *
 * Under a time limit the guide is traced in two passes, of FIRST_PASS
 * particles and as many again, and measured after each: pilots measure a
 * kind of paths' cost, its noise per sample times its time per sample (the
 * relMSE between two pilots of different samples times their seconds),
 * guided paths' over each guide from the same samples (so the two differ
 * less than their noise), fitted as C0 + C1 / N, plain paths' once. The
 * plan (guide_plan.h) then traces the guide on to the count that leaves
 * guided paths the least error in the time left, and renders with guided
 * paths only where that beats plain paths: where the guide buys less than
 * it costs (even light, caustics finer than a bin) the time goes to the
 * path tracer. Both kinds are unbiased, so the plan moves only the noise. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "guide_plan.h"
#include "session_internal.h"
#include "../util/timer.h"

/* Particles of the first measured pass; the second doubles them. */
#define FIRST_PASS (1u << 17)
/* A trace slower than measured stops this far past its planned time. */
#define PLAN_SLACK 1.1
/* Samples per pixel of each pilot, at the image's own size (half-size
 * pilots favoured the guide by 10-25% against whole renders, their pixels
 * averaging over more of what it does not help with): as many as the six
 * pilot images can take in PILOT_SHARE of the budget, from PILOT_SPP_MIN
 * to PILOT_SPP_MAX. Few samples miss the rare long paths whose weight
 * roulette raised, most of plain paths' noise where light comes through a
 * doorway: 2 samples measured guided paths' cost there at 0.85 of plain
 * paths', 8 at 0.6 (docs/guided.md). */
#define PILOT_SPP_MIN 2
#define PILOT_SPP_MAX 8
#define PILOT_SHARE 0.05

/* Traces the volume vs asks for on every device and fills each device's
 * guide table from it. */
static lvcl_error trace_guide(lvcl_session *s, const lvcl_volume_settings *vs, lvcl_status *st)
{
    /* Guided paths keep the packed light odds (--view-odds is lv's). */
    lvcl_volume_settings packed_odds = *vs;
    packed_odds.view_odds = 0;
    lvcl_error e = lvcl_session_trace_volume(s, &packed_odds, st);
    for (int d = 0; d < s->device_count && !e; d++)
        e = lvcl_volume_fill_guide(s->devices[d].volume, &s->devices[d].program, st);
    return e;
}

/* Before a timed render: a small trace, its guide table and the warm-up
 * images (lvcl_session_warm_camera_pass) of guided and of plain paths,
 * thrown away (the timed trace starts a new volume), so that neither the
 * budget nor the pilots pay for PoCL's first-launch compiles; then one
 * guided sample of the image, whose seconds go to *sample_seconds. */
static lvcl_error warm_up(lvcl_session *s, const lvcl_render_request *req, const lvcl_render_request *plain,
                          const lvcl_volume_settings *vs, double *sample_seconds, lvcl_status *st)
{
    lvcl_volume_settings warm = *vs;
    warm.particles = LVCL_WARM_UP_PARTICLES;
    warm.progress = 0;
    lvcl_error e = trace_guide(s, &warm, st);
    if (!e) e = lvcl_session_warm_camera_pass(s, req, st);
    if (!e) e = lvcl_session_warm_camera_pass(s, plain, st);
    lvcl_render_result img = {0};
    double t = lvcl_seconds();
    if (!e) e = lvcl_session_pilot(s, req, 1, 0, 1, &img, st);
    *sample_seconds = lvcl_seconds() - t;
    free(img.rgb);
    return e;
}

/* Pilot samples per pixel for a budget of `budget` seconds where one
 * sample of the image takes sample_seconds (the header's PILOT_SHARE). */
static int pilot_spp(double budget, double sample_seconds)
{
    double spp = PILOT_SHARE * budget / (6.0 * fmax(sample_seconds, 1e-6));
    return spp >= PILOT_SPP_MAX ? PILOT_SPP_MAX : spp <= PILOT_SPP_MIN ? PILOT_SPP_MIN : (int)spp;
}

/* Two pilots of req's paths, of samples [0, spp) and [spp, 2 spp)
 * whatever the guide, as pair *pairs: into img[2 *pairs] and
 * img[2 *pairs + 1], their seconds into seconds[*pairs] and added to
 * *spent; counts the pair. */
static lvcl_error pilot_pair(lvcl_session *s, const lvcl_render_request *req, int spp, lvcl_render_result *img,
                             double *seconds, int *pairs, double *spent, lvcl_status *st)
{
    lvcl_render_result *pair = &img[2 * *pairs];
    double t = lvcl_seconds();
    lvcl_error e = lvcl_session_pilot(s, req, 1, 0, spp, &pair[0], st);
    if (!e) e = lvcl_session_pilot(s, req, 1, spp, spp, &pair[1], st);
    seconds[*pairs] = lvcl_seconds() - t;
    *spent += seconds[*pairs];
    ++*pairs;
    return e;
}

/* Pair k's cost (the header's) and its standard error, weighed by den. */
static double pair_cost(const lvcl_render_result *img, const double *seconds, int k, const float *den, double *error)
{
    const lvcl_render_result *pair = &img[2 * k];
    double cost =
        lvcl_weighted_difference(pair[0].rgb, pair[1].rgb, den, (size_t)pair[0].width * pair[0].height * 3, error);
    *error *= seconds[k];
    return cost * seconds[k];
}

/* Goes on with the trace on the one device a time limit runs on, to
 * `particles` or the deadline (0: none), then refills the guide table. */
static lvcl_error trace_more(lvcl_session *s, const lvcl_volume_settings *vs, uint64_t particles, double deadline,
                             lvcl_status *st)
{
    session_device *sd = &s->devices[0];
    lvcl_volume_settings more = *vs;
    more.first_particle = lvcl_volume_stats_of(sd->volume).particles;
    more.particles = particles;
    more.deadline = deadline;
    if (more.first_particle >= more.particles) return LVCL_OK;
    lvcl_error e = lvcl_volume_trace(sd->volume, &sd->program, &sd->device_scene, &more, st);
    if (!e) e = lvcl_volume_adapt(sd->volume, 0, more.merge_tolerance, st);
    if (!e) e = lvcl_volume_finish(sd->volume, &sd->program, st);
    return e ? e : lvcl_volume_fill_guide(sd->volume, &sd->program, st);
}

/* Under a time limit ending at `end`: the two measured passes, the plan
 * (the header's) and the trace it asks for. With --particles the trace is
 * those particles, whole, and the costs only choose the paths. */
static lvcl_error plan_guide(lvcl_session *s, const lvcl_render_request *req, const lvcl_render_request *plain,
                             const lvcl_volume_settings *vs, double end, int spp, lvcl_guided_report *g,
                             lvcl_status *st)
{
    double start = lvcl_seconds();
    lvcl_volume_settings pass = *vs;
    pass.progress = 0;
    uint64_t fixed = vs->particles, first = fixed ? fixed : FIRST_PASS, traced = first;
    pass.particles = first;
    /* Pilot pairs, one after another in img: guided paths over each guide
     * measured (the first and the second, or the one), then plain paths. */
    lvcl_render_result img[6] = {{0}};
    double seconds[3] = {0};
    int pairs = 0;
    lvcl_error e = trace_guide(s, &pass, st);
    if (!e && !fixed) e = pilot_pair(s, req, spp, img, seconds, &pairs, &g->pilot_seconds, st);
    /* Unless that took a quarter of the budget already, which is better
     * spent on paths than on measuring: the guide doubles. */
    int second = !e && !fixed && lvcl_seconds() - start < (end - start) / 4;
    if (!e && second) {
        double t = lvcl_seconds();
        e = trace_more(s, &pass, 2 * (uint64_t)first, 0, st);
        g->seconds_per_particle = (lvcl_seconds() - t) / first;
        traced = 2 * (uint64_t)first;
    }
    if (!e && (second || fixed)) e = pilot_pair(s, req, spp, img, seconds, &pairs, &g->pilot_seconds, st);
    if (!e) e = pilot_pair(s, plain, spp, img, seconds, &pairs, &g->pilot_seconds, st);
    /* Every kind's error is weighed by the same denominators, from all
     * the pilots. */
    float *den = e ? NULL : lvcl_pilot_denominators(img, 2 * pairs);
    if (!e && !den) e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the pilot images");
    lvcl_guide_costs costs = {.seconds_per_particle = g->seconds_per_particle};
    if (!e) {
        double first_cost = 0, first_error = 0, error;
        if (second) first_cost = pair_cost(img, seconds, 0, den, &first_error);
        g->guided_cost = pair_cost(img, seconds, pairs - 2, den, &error);
        if (second) lvcl_fit_guide_costs(first_cost, first_error, g->guided_cost, error, first, &costs);
        else costs.guide_noise = g->guided_cost, costs.guided_cost_error = error;
        costs.plain_cost = g->plain_cost = pair_cost(img, seconds, pairs - 1, den, &costs.plain_cost_error);
        g->guide_noise = costs.guide_noise;
        g->guide_noise_per_particle = costs.guide_noise_per_particle;
        g->guided_cost_error = costs.guided_cost_error;
        g->plain_cost_error = costs.plain_cost_error;
    }
    free(den);
    for (int i = 0; i < 6; i++) free(img[i].rgb);
    if (e) return e;
    double now = lvcl_seconds();
    lvcl_guide_plan plan = lvcl_plan_guide(&costs, traced, end - now);
    g->planned_particles = plan.particles;
    g->plain = plan.plain;
    g->measure_seconds = now - start;
    g->used = 1;
    if (vs->progress) {
        char paths[64];
        snprintf(paths, sizeof paths, g->plain ? "plain paths" : "guided paths, a guide of %.3g particles",
                 (double)g->planned_particles);
        fprintf(stderr,
                "lvcl: %.0f s budget: %s (measured cost: guided %.3g + %.3g / N, plain %.3g; %.3g s per 10^6 "
                "particles)\n",
                req->pass.time_limit, paths, g->guide_noise, g->guide_noise_per_particle, g->plain_cost,
                g->seconds_per_particle * 1e6);
    }
    if (g->plain || g->planned_particles <= traced) return LVCL_OK;
    double deadline = now + (double)(g->planned_particles - traced) * g->seconds_per_particle * PLAN_SLACK;
    pass.progress = vs->progress;
    return trace_more(s, &pass, g->planned_particles, deadline, st);
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
    if (pass.time_limit <= 0) {
        lvcl_error e = trace_guide(s, &vs, st);
        if (e == LVCL_ERR_CLUSTER || (e = lvcl_cluster_agree(s->cluster, e, st))) return e;
        return lvcl_session_camera_pass(s, req, req->width, req->height, &pass, out, st);
    }
    lvcl_render_request plain = *req;
    plain.mode = LVCL_MODE_PT;
    double sample_seconds;
    lvcl_error e = warm_up(s, req, &plain, &vs, &sample_seconds, st);
    if (e) return e;
    double start = lvcl_seconds();
    s->guided.pilot_spp = pilot_spp(pass.time_limit, sample_seconds);
    if ((e = plan_guide(s, req, &plain, &vs, start + pass.time_limit, s->guided.pilot_spp, &s->guided, st))) return e;
    /* At least one sample is taken, however long the trace and pilots took. */
    pass.time_limit = fmax(pass.time_limit - (lvcl_seconds() - start), 1e-3);
    return lvcl_session_camera_pass(s, s->guided.plain ? &plain : req, req->width, req->height, &pass, out, st);
}
