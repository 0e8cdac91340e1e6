/* One time budget for a whole light-volume render (docs/light-volume.md,
 * "Passes and one time budget"). The particles are traced in passes into
 * one volume. After two passes, three pilot images at half the image's
 * width and height measure how the image's error depends on particles and
 * on samples:
 *
 *   relMSE ~ A / N + a (B0 + B1 / N) / S   (N particles, S samples per pixel),
 *
 * A from two images of the same camera samples over the volume of N1 and
 * of 2 N1 particles (their difference is the volume's noise alone), B over
 * each volume from two images of different samples (B0 and B1 through the
 * two: a jittered lookup reads noisy cells, so the gather's noise falls
 * with the volume's too), a the share of it that adaptive sampling leaves,
 * from how the noise spreads over the pixels. A pilot takes 16 samples per
 * pixel: with one, each lookup reads one jittered point and the volume's
 * noise is 13 times what many samples leave (Cornell box). With the
 * measured costs tp per particle and tg per sample, the trace goes on to
 * the N that leaves the least error in the time left, revised as the trace
 * measures tp, and the gather takes the rest. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "../io/metrics.h"
#include "adaptive_sampling.h"
#include "session_internal.h"
#include "../util/interrupt.h"
#include "../util/progress.h"
#include "../util/timer.h"

/* Particles of the first pass; the second doubles them. Small enough for
 * a budget of a few seconds, large enough that the volume's noise falls as
 * 1/N from there. */
#define FIRST_PASS (1u << 17)
/* The share of the time left the gather keeps whatever the measurements say. */
#define GATHER_SHARE_MIN 0.05
/* Samples per pixel of the two pilots that compare volumes, and of the one
 * that measures the gather's noise. */
#define PILOT_SPP 16
#define NOISE_PILOT_SPP 4
/* The pilots' width and height are the image's over this. */
#define PILOT_SCALE 2
/* Particles between revisions of the plan (trace_to_plan). */
#define REPLAN_BATCH (1u << 19)
/* A trace slower than measured stops this far past its planned time. */
#define PLAN_SLACK 1.1
/* After the warm-up's LVCL_WARM_UP_PARTICLES, a short launch, below that
 * size class, as a plan's last batch may be. */
#define WARM_UP_SHORT_BATCH 64u

/* The share of the budget the plan usually gives the trace (the Cornell box
 * in 30 s: 3 x 10^6 particles at 3.8 us), for the adaptive cells' decision
 * after the first pass, before there is a plan. */
#define TRACE_SHARE_GUESS 0.4

/* Runs the light volume's trace over [first, end) on the session's device
 * (one device: time limits are refused on several). */
static lvcl_error trace_range(lvcl_session *s, const lvcl_volume_settings *base, uint64_t first, uint64_t end,
                              double deadline, lvcl_status *st)
{
    session_device *sd = &s->devices[0];
    lvcl_volume_settings vs = *base;
    vs.first_particle = first;
    vs.particles = end;
    vs.deadline = deadline;
    return lvcl_volume_trace(sd->volume, &sd->program, &sd->device_scene, &vs, st);
}

/* After lvcl_volume_refine at `split` particles: those particles again,
 * into the slots that restarted alone (a retrace runs whole). */
static lvcl_error retrace_split(lvcl_session *s, const lvcl_volume_settings *base, uint64_t split, lvcl_status *st)
{
    lvcl_volume_settings vs = *base;
    vs.restarted_only = 1;
    return trace_range(s, &vs, 0, split, 0, st);
}

/* After a pass: lets the cells adapt (once, expecting `expected` particles
 * in all; 0: not now) and computes the lit volumes for the lookups. */
static lvcl_error finish_pass(lvcl_session *s, const lvcl_volume_settings *vs, double expected, lvcl_status *st)
{
    session_device *sd = &s->devices[0];
    lvcl_error e = lvcl_volume_adapt(sd->volume, expected, vs->merge_tolerance, st);
    return e ? e : lvcl_volume_finish(sd->volume, &sd->program, st);
}

/* The share of the gather's uniform noise B that adaptive sampling leaves
 * (adaptive_sampling.h): it gives pixel i samples in proportion to
 * s_i = w_i + LVCL_ADAPTIVE_SHARE_FLOOR mean(w), w_i the sampler's own
 * weight from the pixels around it, so that the gather's relMSE becomes
 * sum_i (r_i / s_i) sum_j s_j / N^2 per sample, r_i = v_i / g_i the
 * pixel's relative variance, against sum_i r_i / N uniform. The variances
 * v_i (a sample's, up to a common factor) and weights g_i come from the
 * noise pilot. The first epoch, uniform, is left out: it is a few of a
 * budget's samples. */
static double adaptive_share(const double *variance, const double *guard, int w, int h)
{
    size_t n = (size_t)w * h;
    double *weight = malloc(n * sizeof *weight);
    if (!weight) return 1.0;
    double mean = lvcl_adaptive_weights(variance, guard, (uint32_t)w, (uint32_t)h, weight) / (double)n;
    double spread = 0, total = 0, uniform = 0;
    for (size_t i = 0; i < n; i++) {
        double s_i = weight[i] + LVCL_ADAPTIVE_SHARE_FLOOR * mean, r_i = variance[i] / guard[i];
        total += s_i;
        uniform += r_i;
        if (s_i > 0) spread += r_i / s_i;
    }
    free(weight);
    double share = uniform > 0 && total > 0 ? spread * total / ((double)n * uniform) : 1.0;
    return share < 0.05 ? 0.05 : share > 1.0 ? 1.0 : share;
}

/* The particle count that leaves the least error when `left` seconds
 * remain after `traced` particles, within [traced, UINT32_MAX], keeping
 * the gather its minimum share: the least of A / N + a B(N) / S over N
 * (a: adaptive sampling's share, adaptive_share), with
 * S = (left - (N - traced) tp) / tg and B(N) = B0 + B1 / N (the gather's
 * noise falls with the volume's: a jittered lookup reads noisy cells),
 * scanned over 256 counts spaced evenly in log N (a deterministic 1% grid). */
static uint64_t best_particles(const lvcl_budget_report *b, uint64_t traced, double left)
{
    if (!(b->volume_noise > 0) || !(b->seconds_per_particle > 0) || left <= 0) return traced;
    double tp = b->seconds_per_particle, tg = b->seconds_per_sample;
    double lo = traced > 0 ? (double)traced : 1.0;
    double most = (double)traced + (1.0 - GATHER_SHARE_MIN) * left / tp;
    if (most > (double)UINT32_MAX) most = (double)UINT32_MAX;
    if (!(most > lo)) return traced;
    double best = lo, best_error = INFINITY;
    for (int i = 0; i <= 255; i++) {
        double n = lo * pow(most / lo, i / 255.0);
        double spp = (left - (n - (double)traced) * tp) / tg;
        if (!(spp > 0)) continue;
        double error =
            b->volume_noise / n + b->adaptive_share * (b->gather_noise + b->gather_noise_per_particle / n) / spp;
        if (error < best_error) best_error = error, best = n;
    }
    return best > (double)traced ? (uint64_t)best : traced;
}

/* Traces from `traced` particles on to the plan, revising it after every
 * REPLAN_BATCH from the cost per particle this trace measures: a particle
 * costs less once the subcell masks fill (Cornell box: 5.0 us each over
 * the first 2^17, 3.4 us each over 4 x 10^6), so the measuring passes'
 * cost made the plan trace too few. A batch slower than planned stops a
 * tenth past its time. `end` is when the budget ends. */
static lvcl_error trace_to_plan(lvcl_session *s, const lvcl_volume_settings *vs, lvcl_budget_report *b, uint64_t traced,
                                double end, lvcl_status *st)
{
    session_device *sd = &s->devices[0];
    lvcl_volume_settings batch = *vs;
    batch.progress = 0; /* one bar over the batches */
    lvcl_progress bar;
    lvcl_progress_start(&bar, "particles", vs->progress);
    uint64_t first = traced;
    double start = lvcl_seconds();
    lvcl_error e = LVCL_OK;
    while (traced < b->planned_particles && !e) {
        uint64_t to = b->planned_particles - traced > REPLAN_BATCH ? traced + REPLAN_BATCH : b->planned_particles;
        double deadline = lvcl_seconds() + (double)(to - traced) * b->seconds_per_particle * PLAN_SLACK;
        if ((e = trace_range(s, &batch, traced, to, deadline, st))) break;
        uint64_t now_traced = lvcl_volume_stats_of(sd->volume).particles;
        lvcl_progress_update(&bar, (double)now_traced, (double)b->planned_particles, "particles");
        if (now_traced < to || lvcl_interrupted()) break; /* a deadline or a signal cut the batch short */
        traced = now_traced;
        double now = lvcl_seconds();
        b->seconds_per_particle = (now - start) / (double)(traced - first);
        b->planned_particles = best_particles(b, traced, end - now);
    }
    lvcl_progress_finish(&bar);
    return e;
}

/* Launches the trace and the gather in both of PoCL's size classes, and
 * throws the work away (the next trace from particle 0 empties the volume).
 * PoCL compiles a kernel's machine code at its first launch of each size
 * class, up to 2 s a kernel on a cold cache: counted in the budget, that
 * time made the first pass and pilot look slow enough for a 15 s budget to
 * stop measuring at 1.3 x 10^5 particles, and the final gather lost samples
 * to it. On a warm cache this costs the trace of LVCL_WARM_UP_PARTICLES and one
 * sample of a 256 x 256 image. */
static lvcl_error warm_up(lvcl_session *s, const lvcl_render_request *req, const lvcl_volume_settings *vs,
                          lvcl_status *st)
{
    /* A launch of each size class (lvcl_session_warm_camera_pass): a plan's
     * last batch may be short. */
    lvcl_error e = trace_range(s, vs, 0, LVCL_WARM_UP_PARTICLES, 0, st);
    if (!e) e = trace_range(s, vs, LVCL_WARM_UP_PARTICLES, LVCL_WARM_UP_PARTICLES + WARM_UP_SHORT_BATCH, 0, st);
    if (!e) e = finish_pass(s, vs, 0, st);
    return e ? e : lvcl_session_warm_camera_pass(s, req, st);
}

/* Measures A, B and the costs after two passes (the header's recipe). */
static lvcl_error measure(lvcl_session *s, const lvcl_render_request *req, const lvcl_volume_settings *vs,
                          lvcl_budget_report *b, lvcl_status *st)
{
    lvcl_render_result img[4] = {{0}};
    double t = lvcl_seconds();
    lvcl_error e = trace_range(s, vs, 0, FIRST_PASS, 0, st);
    double expected = TRACE_SHARE_GUESS * req->pass.time_limit / ((lvcl_seconds() - t) / FIRST_PASS);
    if (expected < 2.0 * FIRST_PASS) expected = 2.0 * FIRST_PASS;
    if (!e) e = finish_pass(s, vs, expected, st);
    if (!e) e = lvcl_session_pilot(s, req, PILOT_SCALE, 0, PILOT_SPP, &img[0], st);
    double p = lvcl_seconds();
    /* A budget this short is better spent on the gather than on measuring. */
    if (!e && p - t > req->pass.time_limit / 4) {
        free(img[0].rgb);
        b->measure_seconds = p - t;
        return LVCL_OK;
    }
    /* The gather's noise over the first volume, for how it falls with N. */
    if (!e) e = lvcl_session_pilot(s, req, PILOT_SCALE, PILOT_SPP, NOISE_PILOT_SPP, &img[3], st);
    double p2 = lvcl_seconds();
    if (!e) e = trace_range(s, vs, FIRST_PASS, 2 * (uint64_t)FIRST_PASS, 0, st);
    if (!e) e = finish_pass(s, vs, 0, st);
    double q = lvcl_seconds();
    if (!e) e = lvcl_session_pilot(s, req, PILOT_SCALE, 0, PILOT_SPP, &img[1], st);
    if (!e) e = lvcl_session_pilot(s, req, PILOT_SCALE, PILOT_SPP, NOISE_PILOT_SPP, &img[2], st);
    double r = lvcl_seconds();
    float *den = e ? NULL : lvcl_pilot_denominators(img, 3);
    if (!e && !den) e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the pilot images");
    if (!e) {
        size_t n = (size_t)img[0].width * img[0].height * 3;
        /* Var(P1 - P2) = A / (2 N1); Var(Q - P2) = B / NOISE_PILOT_SPP + B / PILOT_SPP. */
        b->volume_noise = 2.0 * FIRST_PASS * lvcl_weighted_difference(img[0].rgb, img[1].rgb, den, n, NULL);
        /* Var(Q - P) = B / NOISE_PILOT_SPP + B / PILOT_SPP over either volume;
         * B(N) = B0 + B1 / N through the two (same samples, so their noise
         * differs less than they do). */
        double pilots = 1.0 / NOISE_PILOT_SPP + 1.0 / PILOT_SPP;
        double b2 = lvcl_weighted_difference(img[2].rgb, img[1].rgb, den, n, NULL) / pilots;
        double b1 = lvcl_weighted_difference(img[3].rgb, img[0].rgb, den, n, NULL) / pilots;
        double falls = 2.0 * FIRST_PASS * (b1 - b2); /* B1: 1/N1 - 1/N2 = 1 / (2 N1) */
        if (falls < 0) falls = 0;
        if (falls > 2.0 * FIRST_PASS * b2) falls = 2.0 * FIRST_PASS * b2; /* B0 >= 0 */
        b->gather_noise_per_particle = falls;
        b->gather_noise = b2 - falls / (2.0 * FIRST_PASS);
        if (req->pass.adaptive) {
            /* Per pixel, as the sampler sees it: the squared difference
             * of the two pilots' channel means, and its relMSE weight. */
            size_t pixels = n / 3;
            double *variance = malloc(pixels * sizeof *variance), *guard = malloc(pixels * sizeof *guard);
            if (!variance || !guard)
                e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the pilot images");
            for (size_t i = 0; !e && i < pixels; i++) {
                double d = 0, g = 0;
                for (int c = 0; c < 3; c++) {
                    d += ((double)img[2].rgb[3 * i + c] - img[1].rgb[3 * i + c]) / 3.0;
                    g += den[3 * i + c] / 3.0;
                }
                variance[i] = d * d;
                guard[i] = g;
            }
            if (!e) b->adaptive_share = adaptive_share(variance, guard, img[0].width, img[0].height);
            free(variance);
            free(guard);
        }
        b->seconds_per_particle = (q - p2) / FIRST_PASS;
        /* Per sample of the whole image: the pilots have 1 / PILOT_SCALE^2 of its pixels. */
        b->seconds_per_sample = (r - q) / (PILOT_SPP + NOISE_PILOT_SPP) * PILOT_SCALE * PILOT_SCALE;
        b->measure_seconds = r - t;
    }
    free(den);
    for (int i = 0; i < 4; i++) free(img[i].rgb);
    return e;
}

lvcl_error lvcl_session_render_budget(lvcl_session *s, const lvcl_render_request *req, lvcl_render_result *out,
                                      lvcl_status *st)
{
    double start = lvcl_seconds(), end = start + req->pass.time_limit;
    session_device *sd = &s->devices[0];
    lvcl_volume_settings vs = req->volume;
    vs.store_emitted = req->mode == LVCL_MODE_LV_ALL;
    vs.see_through = lvcl_session_volume_sees_through(s, req);
    vs.source = NULL;
    lvcl_error e = lvcl_session_new_volume(s, 0, &vs, st);
    if (e || (e = lvcl_session_view_start(s, vs.view_odds, st))) return e;
    lvcl_budget_report *b = &s->budget;
    b->used = 1;
    b->adaptive_share = 1.0;
    if (vs.particles) { /* --particles given: traced whole, the gather takes what is left */
        uint64_t split_at = lvcl_volume_split_point(&vs), first_part = lvcl_session_first_part(s, &vs);
        if (split_at > 0 &&
            ((e = trace_range(s, &vs, 0, split_at, 0, st)) ||
             (e = lvcl_volume_refine(sd->volume, (double)vs.particles, &vs, st)) ||
             (e = retrace_split(s, &vs, split_at, st))))
            return e;
        if (!split_at && first_part > 0 && (e = trace_range(s, &vs, 0, first_part, 0, st))) return e;
        if ((e = lvcl_session_view_decide(s, vs.store_emitted, st)) ||
            (e = trace_range(s, &vs, first_part, vs.particles, 0, st)) ||
            (e = finish_pass(s, &vs, (double)vs.particles, st)))
            return e;
        b->planned_particles = vs.particles;
    } else {
        int progress = vs.progress;
        vs.progress = 0;
        /* Kernel builds are not counted: the clock moves on by the warm-up. */
        double w = lvcl_seconds();
        if ((e = warm_up(s, req, &vs, st))) return e;
        b->warm_up_seconds = lvcl_seconds() - w;
        start += b->warm_up_seconds;
        end += b->warm_up_seconds;
        if ((e = measure(s, req, &vs, b, st))) return e;
        uint64_t traced = lvcl_volume_stats_of(sd->volume).particles;
        double now = lvcl_seconds();
        b->planned_particles = best_particles(b, traced, end - now);
        if (progress && !(b->seconds_per_particle > 0))
            fprintf(stderr, "lvcl: %.0f s budget: too short to measure, so %.3g particles, then the gather\n",
                    req->pass.time_limit, (double)b->planned_particles);
        else if (progress)
            fprintf(stderr,
                    "lvcl: %.0f s budget: %.3g particles, then the gather (measured: volume relMSE %.3g / N, "
                    "gather %.3g / spp, %.3g s per 10^6 particles, %.3g s per sample)\n",
                    req->pass.time_limit, (double)b->planned_particles, b->volume_noise,
                    b->gather_noise * b->adaptive_share, b->seconds_per_particle * 1e6, b->seconds_per_sample);
        vs.progress = progress;
        if (b->planned_particles > traced) {
            /* Refined cells split now, when the plan knows the particle count. */
            if ((e = lvcl_volume_refine(sd->volume, (double)b->planned_particles, &vs, st)) ||
                (e = retrace_split(s, &vs, traced, st)) || (e = lvcl_session_view_decide(s, vs.store_emitted, st)))
                return e;
            if ((e = trace_to_plan(s, &vs, b, traced, end, st)) || (e = finish_pass(s, &vs, 0, st))) return e;
        }
    }
    if ((e = lvcl_session_view_gather(s, st))) return e;
    lvcl_pass_settings pass = req->pass;
    pass.time_limit = end - lvcl_seconds();
    if (pass.time_limit < 1e-3) pass.time_limit = 1e-3; /* at least one sample is taken */
    e = lvcl_session_camera_pass(s, req, req->width, req->height, &pass, out, st);
    b->spent_seconds = lvcl_seconds() - start;
    return e;
}
