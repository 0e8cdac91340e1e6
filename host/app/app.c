/* lvcl's run from the command line (app.h). */
#include "app.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../io/image_io.h"
#include "options.h"
#include "../render/adaptive_sampling.h"
#include "../render/session.h"
#include "stats.h"
#include "../util/interrupt.h"
#include "../util/timer.h"

#define LVCL_VERSION "0.1.0"

/* With a cluster, rank 0 speaks for all: it reports, checks and writes
 * what the job has one of. */
static int speaks_for_all(const lvcl_cluster *cluster)
{
    return !cluster || cluster->rank == 0;
}

/* The name of a scene for default output files: its file name without
 * directory and extension. */
static void scene_stem(const char *scene, char *out, size_t size)
{
    const char *base = strrchr(scene, '/');
    base = base ? base + 1 : scene;
    snprintf(out, size, "%s", base);
    char *dot = strrchr(out, '.');
    if (dot && dot != out) *dot = 0;
}

static lvcl_error write_outputs(const lvcl_options *o, const lvcl_render_result *res, lvcl_status *st)
{
    if (o->output) return lvcl_image_write(o->output, res->rgb, res->width, res->height, (float)o->exposure, st);
    if (mkdir("out", 0755) && errno != EEXIST)
        return lvcl_fail(st, LVCL_ERR_IO, "cannot create the output directory out/: %s", strerror(errno));
    char stem[256], path[300];
    scene_stem(o->scene, stem, sizeof stem);
    const char *ext[] = {"exr", "png"};
    for (int i = 0; i < 2; i++) {
        snprintf(path, sizeof path, "out/%s.%s", stem, ext[i]);
        lvcl_error e = lvcl_image_write(path, res->rgb, res->width, res->height, (float)o->exposure, st);
        if (e) return e;
        if (!o->quiet) fprintf(stderr, "lvcl: wrote %s\n", path);
    }
    return LVCL_OK;
}

/* Whether path can be written: an existing file writable, or a new one's
 * folder. Checked before rendering, so that a typo in -o or --stats costs
 * an error line, not the render. */
static lvcl_error check_writable(const char *path, const char *what, lvcl_status *st)
{
    if (!access(path, F_OK)) {
        if (access(path, W_OK))
            return lvcl_fail(st, LVCL_ERR_IO, "cannot write %s %s: %s", what, path, strerror(errno));
        return LVCL_OK;
    }
    char folder[4096];
    snprintf(folder, sizeof folder, "%s", path);
    char *slash = strrchr(folder, '/');
    if (!slash) snprintf(folder, sizeof folder, ".");
    else if (slash == folder) folder[1] = 0;
    else *slash = 0;
    if (access(folder, W_OK | X_OK))
        return lvcl_fail(st, LVCL_ERR_IO, "cannot write %s %s: %s: %s", what, path, folder, strerror(errno));
    return LVCL_OK;
}

/* The outputs' formats and folders, before any work that they would lose. */
static lvcl_error check_outputs(const lvcl_options *o, lvcl_status *st)
{
    lvcl_error e;
    if (o->output) {
        if ((e = lvcl_image_format_check(o->output, st)) || (e = check_writable(o->output, "the image", st))) return e;
    } else if (access("out", F_OK) ? access(".", W_OK | X_OK) : access("out", W_OK | X_OK)) {
        /* out/ itself is made once there is an image to put in it. */
        return lvcl_fail(st, LVCL_ERR_IO, "cannot write the image to out/: %s", strerror(errno));
    }
    return o->stats ? check_writable(o->stats, "stats to", st) : LVCL_OK;
}

/* This process's share of the render, and every rank's gathered into
 * stats->ranks (collective; lvcl-mpi only). */
static lvcl_error gather_shares(lvcl_cluster *c, const lvcl_session *s, lvcl_stats *stats, lvcl_status *st)
{
    lvcl_rank_share mine = {.devices = lvcl_session_device_count(s), .interrupted_by = stats->interrupted_by};
    if (gethostname(mine.host, sizeof mine.host - 1)) snprintf(mine.host, sizeof mine.host, "?");
    for (int d = 0; d < mine.devices; d++) {
        const lvcl_light_volume *v = lvcl_session_volume(s, d);
        lvcl_volume_stats w = v ? lvcl_volume_stats_of(v) : (lvcl_volume_stats){0};
        lvcl_pass_share pass = lvcl_session_pass_share(s, d);
        mine.particles += w.particles;
        mine.segments += w.segments;
        if (w.trace_seconds > mine.particle_trace_seconds) mine.particle_trace_seconds = w.trace_seconds;
        mine.bands += pass.bands;
        mine.pixels += pass.pixels;
        if (pass.busy_seconds > mine.render_busy_seconds) mine.render_busy_seconds = pass.busy_seconds;
    }
    memcpy(mine.comm_seconds, c->comm_seconds, sizeof mine.comm_seconds);
    memcpy(mine.reduce_seconds, c->reduce_seconds, sizeof mine.reduce_seconds);
    memcpy(mine.comm_bytes, c->comm_bytes, sizeof mine.comm_bytes);
    lvcl_rank_share *all = calloc((size_t)c->size, sizeof *all);
    if (!all) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the ranks' shares");
    lvcl_error e = c->gather(c, &mine, sizeof mine, all, st);
    if (e) {
        free(all);
        return e;
    }
    stats->ranks = all;
    stats->rank_count = c->size;
    /* A signal to any rank stopped the render for all: every rank says so. */
    for (int r = 0; r < c->size; r++)
        if (all[r].interrupted_by && !stats->interrupted_by) stats->interrupted_by = all[r].interrupted_by;
    return LVCL_OK;
}

/* Loads, opens the devices and renders; with a cluster every process does,
 * and each step's failure is every process's (lvcl_cluster_agree). Sets
 * *talked_out once no collective is left. */
static lvcl_error render(const lvcl_options *o, lvcl_cluster *cluster, lvcl_session **s, lvcl_render_result *res,
                         lvcl_stats *stats, int *talked_out, lvcl_status *st)
{
    lvcl_error e;
    if ((e = lvcl_cluster_agree(cluster, speaks_for_all(cluster) ? check_outputs(o, st) : LVCL_OK, st))) return e;
    lvcl_scene scene = {0};
    double t = lvcl_seconds();
    if ((e = lvcl_cluster_agree(cluster, lvcl_scene_load(o->scene, &scene, st), st))) {
        lvcl_scene_free(&scene);
        return e;
    }
    stats->scene_load_seconds = lvcl_seconds() - t;

    lvcl_session_config cfg = {.device = o->device,
                               .seed = o->seed,
                               .max_depth = o->max_depth,
                               .fast_math = o->fast_math,
                               /* To check the 32-bit-atomics fallback on devices with 64-bit ones. */
                               .build_flags =
                                   getenv("LVCL_EMULATE_INT64_ATOMICS") ? LVCL_BUILD_EMULATED_INT64_ATOMICS : 0,
                               .device_memory = (uint64_t)(o->device_memory_mib * 1048576.0),
                               .cluster = cluster,
                               .announce_builds = !o->quiet};
    if ((e = lvcl_cluster_agree(cluster, lvcl_session_open(&scene, &cfg, s, st), st))) return e;
    stats->session = *s;

    lvcl_render_request req = {
        .mode = !strcmp(o->mode, "lv")   ? LVCL_MODE_LV
            : !strcmp(o->mode, "lv-all") ? LVCL_MODE_LV_ALL
            : !strcmp(o->mode, "guided") ? LVCL_MODE_GUIDED
                                         : LVCL_MODE_PT,
        .width = o->width,
        .height = o->height,
        .pass = {.spp = o->spp,
                 .time_limit = o->time_limit,
                 .progress = !o->quiet,
                 .adaptive = !strcmp(o->adaptive, "on")},
        .volume = {.cells = o->cells,
                   .cell_size = o->cell_size,
                   .offset = o->grid_offset,
                   .dirs = o->dirs,
                   .subcells = o->subcells,
                   .visibility_rate = o->visibility_rate,
                   .merge_tolerance = o->merge_tolerance,
                   .refine_density = o->refine_density,
                   .refine_focus = o->refine_focus,
                   .refine_peak = o->refine_peak,
                   .refine_memory = (uint64_t)(o->refine_memory_mib * 1048576.0),
                   .particles = (uint64_t)o->particles,
                   .view_odds = !strcmp(o->view_odds, "on"),
                   .progress = !o->quiet},
        .integrate = !strcmp(o->gather, "integrate"),
        .see_through = !strcmp(o->see_through, "on"),
        .threshold = o->threshold,
    };
    stats->startup_seconds = lvcl_seconds() - stats->process_start;
    /* Until now a signal ends lvcl at once: there is nothing to save. */
    lvcl_interrupt_catch();
    if ((e = lvcl_session_render(*s, &req, res, st))) return e;
    stats->result = res;
    stats->interrupted_by = lvcl_interrupted();
    if (lvcl_cluster_shared(cluster) && (e = gather_shares(cluster, *s, stats, st))) return e;
    *talked_out = 1;
    if (stats->interrupted_by && speaks_for_all(cluster))
        fprintf(stderr, "lvcl: %s: sampling stopped after %d of %d samples per pixel; writing the image so far\n",
                stats->interrupted_by == SIGINT        ? "interrupted (SIGINT)"
                    : stats->interrupted_by == SIGTERM ? "terminated (SIGTERM)"
                                                       : "stopped (SIGUSR2)",
                res->samples, o->spp);
    int devices = lvcl_session_device_count(*s);
    if (req.pass.adaptive && !res->adaptive && res->samples > LVCL_EPOCH_SPP && !o->quiet &&
        (devices > 1 || lvcl_cluster_shared(cluster)))
        fprintf(stderr, "lvcl: adaptive sampling needs one device; the %d %s sampled uniformly\n",
                lvcl_cluster_shared(cluster) ? cluster->size : devices,
                lvcl_cluster_shared(cluster) ? "ranks" : "devices");
    if (o->spp_given && res->samples < o->spp && !o->quiet && !stats->interrupted_by)
        fprintf(stderr, "lvcl: time limit reached after %d of %d samples per pixel\n", res->samples, o->spp);
    return LVCL_OK;
}

/* The image and the closing line (rank 0 only, with a cluster). */
static lvcl_error finish(const lvcl_options *o, const lvcl_session *s, const lvcl_render_result *res,
                         const lvcl_stats *stats, lvcl_status *st)
{
    lvcl_error e = write_outputs(o, res, st);
    if (e) return e;
    if (!o->quiet) {
        double volume = lvcl_session_volume_seconds(s);
        fprintf(stderr, "lvcl: %s, %s, %dx%d, %d spp: %.1f s in all", o->scene, o->mode, res->width, res->height,
                res->samples, lvcl_seconds() - stats->process_start);
        if (volume > 0)
            fprintf(stderr, " (particle trace %.1f s, %s %.1f s)", volume,
                    strcmp(o->mode, "guided") ? "gather" : "paths", res->render_seconds);
        else fprintf(stderr, " (render %.1f s)", res->render_seconds);
        if (stats->rank_count > 1) fprintf(stderr, " over %d ranks", stats->rank_count);
        fputc('\n', stderr);
    }
    return o->stats ? lvcl_stats_write(o->stats, stats, st) : LVCL_OK;
}

int lvcl_app_main(int argc, char **argv, lvcl_cluster *cluster)
{
    lvcl_stats stats = {0};
    stats.process_start = lvcl_seconds();
    /* Bad input is reported once. */
    int speaks = speaks_for_all(cluster);
    lvcl_options o;
    lvcl_status st = {0};
    if (lvcl_options_parse(argc, argv, &o, &st)) {
        if (speaks) fprintf(stderr, "lvcl: error: %s\n", st.message);
        return 2;
    }
    if (o.help || o.version || o.list_devices) {
        if (!speaks) return 0;
        if (o.help) lvcl_options_print_help(argv[0]);
        else if (o.version) printf("lvcl %s\n", LVCL_VERSION);
    }
    if (o.help || o.version) return 0;
    lvcl_device_prepare_environment();
    if (o.list_devices) {
        if (!speaks) return 0;
        if (lvcl_device_list(stdout, &st)) {
            fprintf(stderr, "lvcl: error: %s\n", st.message);
            return 1;
        }
        return 0;
    }
    if (!speaks) {
        o.quiet = 1;
        lvcl_warn_mute(1);
    }

    lvcl_session *session = NULL;
    lvcl_render_result result = {0};
    stats.options = &o;
    int talked_out = 0;
    lvcl_error e = render(&o, cluster, &session, &result, &stats, &talked_out, &st);
    if (e && lvcl_cluster_shared(cluster) && !cluster->agreed_failure && !talked_out) {
        /* The others may wait for this process in a collective it will not reach. */
        fprintf(stderr, "lvcl: error: rank %d: %s\n", cluster->rank, st.message);
        cluster->abort(cluster, 1);
    }
    if (!e && speaks) e = finish(&o, session, &result, &stats, &st);
    if (e && speaks) fprintf(stderr, "lvcl: error: %s\n", st.message);
    free(result.rgb);
    free((void *)stats.ranks);
    lvcl_session_close(session);
    /* Stopped by a signal: the shell's status for death by it, 128 + its number. */
    return e == LVCL_ERR_USAGE ? 2 : e ? 1 : stats.interrupted_by ? 128 + stats.interrupted_by : 0;
}
