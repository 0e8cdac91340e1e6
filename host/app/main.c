/* lvcl: renders a glTF scene on an OpenCL device. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "../io/image_io.h"
#include "options.h"
#include "../render/adaptive_sampling.h"
#include "../render/session.h"
#include "stats.h"
#include "../util/interrupt.h"
#include "../util/timer.h"

#define LVCL_VERSION "0.1.0"

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

static lvcl_error run(const lvcl_options *o, lvcl_session **s, lvcl_render_result *res, lvcl_stats *stats,
                      lvcl_status *st)
{
    lvcl_error e;
    lvcl_scene scene = {0};
    double t = lvcl_seconds();
    if ((e = lvcl_scene_load(o->scene, &scene, st))) return e;
    stats->scene_load_seconds = lvcl_seconds() - t;

    lvcl_session_config cfg = {.device = o->device,
                               .seed = o->seed,
                               .max_depth = o->max_depth,
                               .fast_math = o->fast_math,
                               /* To check the 32-bit-atomics fallback on devices with 64-bit ones. */
                               .build_flags =
                                   getenv("LVCL_EMULATE_INT64_ATOMICS") ? LVCL_BUILD_EMULATED_INT64_ATOMICS : 0,
                               .device_memory = (uint64_t)(o->device_memory_mib * 1048576.0)};
    if ((e = lvcl_session_open(&scene, &cfg, s, st))) return e;
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
                   .refine_peak = o->refine_peak,
                   .refine_memory = (uint64_t)(o->refine_memory_mib * 1048576.0),
                   .particles = (uint64_t)o->particles,
                   .progress = !o->quiet},
        .integrate = !strcmp(o->gather, "integrate"),
        .threshold = o->threshold,
    };
    stats->startup_seconds = lvcl_seconds() - stats->process_start;
    /* Until now a signal ends lvcl at once: there is nothing to save. */
    lvcl_interrupt_catch();
    if ((e = lvcl_session_render(*s, &req, res, st))) return e;
    stats->result = res;
    stats->interrupted_by = lvcl_interrupted();
    if (stats->interrupted_by)
        fprintf(stderr, "lvcl: %s: sampling stopped after %d of %d samples per pixel; writing the image so far\n",
                stats->interrupted_by == SIGINT ? "interrupted (SIGINT)" : "terminated (SIGTERM)", res->samples,
                o->spp);
    if (req.pass.adaptive && !res->adaptive && lvcl_session_device_count(*s) > 1 && res->samples > LVCL_EPOCH_SPP &&
        !o->quiet)
        fprintf(stderr, "lvcl: adaptive sampling needs one device; the %d devices sampled uniformly\n",
                lvcl_session_device_count(*s));
    if (o->spp_given && res->samples < o->spp && !o->quiet && !stats->interrupted_by)
        fprintf(stderr, "lvcl: time limit reached after %d of %d samples per pixel\n", res->samples, o->spp);
    if ((e = write_outputs(o, res, st))) return e;
    if (!o->quiet) {
        double volume = lvcl_session_volume_seconds(*s);
        fprintf(stderr, "lvcl: %s, %s, %dx%d, %d spp: %.1f s in all", o->scene, o->mode, res->width, res->height,
                res->samples, lvcl_seconds() - stats->process_start);
        if (volume > 0)
            fprintf(stderr, " (particle trace %.1f s, %s %.1f s)", volume,
                    strcmp(o->mode, "guided") ? "gather" : "paths", res->render_seconds);
        else fprintf(stderr, " (render %.1f s)", res->render_seconds);
        fputc('\n', stderr);
    }
    return LVCL_OK;
}

int main(int argc, char **argv)
{
    lvcl_stats stats = {0};
    stats.process_start = lvcl_seconds();
    lvcl_options o;
    lvcl_status st = {0};
    if (lvcl_options_parse(argc, argv, &o, &st)) {
        fprintf(stderr, "lvcl: error: %s\n", st.message);
        return 2;
    }
    if (o.help) {
        lvcl_options_print_help(argv[0]);
        return 0;
    }
    if (o.version) {
        printf("lvcl %s\n", LVCL_VERSION);
        return 0;
    }
    lvcl_device_prepare_environment();
    if (o.list_devices) {
        if (lvcl_device_list(stdout, &st)) {
            fprintf(stderr, "lvcl: error: %s\n", st.message);
            return 1;
        }
        return 0;
    }

    lvcl_session *session = NULL;
    lvcl_render_result result = {0};
    stats.options = &o;
    lvcl_error e = run(&o, &session, &result, &stats, &st);
    if (!e && o.stats) e = lvcl_stats_write(o.stats, &stats, &st);
    if (e) fprintf(stderr, "lvcl: error: %s\n", st.message);
    free(result.rgb);
    lvcl_session_close(session);
    /* Stopped by a signal: the shell's status for death by it, 128 + its number. */
    return e == LVCL_ERR_USAGE ? 2 : e ? 1 : stats.interrupted_by ? 128 + stats.interrupted_by : 0;
}
