/* lvcl: renders a glTF scene on an OpenCL device. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "bvh.h"
#include "camera.h"
#include "device_scene.h"
#include "embedded_scenes.h"
#include "image_io.h"
#include "materials.h"
#include "options.h"
#include "program.h"
#include "render_pt.h"
#include "stats.h"
#include "timer.h"

#define LVCL_VERSION "0.1.0"

/* Everything a run owns, released together at the end. */
typedef struct {
    lvcl_scene scene;
    lvcl_bvh bvh;
    lvcl_packed_scene packed;
    lvcl_device device;
    lvcl_device_scene device_scene;
    lvcl_program program;
    lvcl_render_result result;
} run_state;

static void run_release(run_state *r)
{
    free(r->result.rgb);
    lvcl_program_release(&r->program);
    lvcl_device_scene_release(&r->device_scene);
    lvcl_device_close(&r->device);
    lvcl_packed_scene_free(&r->packed);
    lvcl_bvh_free(&r->bvh);
    lvcl_scene_free(&r->scene);
}

static lvcl_error load_scene(const char *name, lvcl_scene *scene, lvcl_status *st)
{
    struct stat sb;
    if (stat(name, &sb) == 0) return lvcl_scene_load_gltf_file(name, scene, st);
    const lvcl_embedded_scene *e = lvcl_embedded_scene_find(name);
    if (e) return lvcl_scene_load_gltf_memory(e->data, e->size, "", scene, st);
    return lvcl_fail(st, LVCL_ERR_IO, "no such file or embedded scene '%s' (embedded: %s)", name,
                     lvcl_embedded_scene_names());
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

static lvcl_error run(const lvcl_options *o, run_state *r, lvcl_stats *stats, lvcl_status *st)
{
    lvcl_error e;
    if (strcmp(o->mode, "pt"))
        return lvcl_fail(st, LVCL_ERR_UNSUPPORTED, "mode '%s' is not implemented yet; use --mode pt", o->mode);

    double t = lvcl_seconds();
    if ((e = load_scene(o->scene, &r->scene, st))) return e;
    stats->scene_load_seconds = lvcl_seconds() - t;

    t = lvcl_seconds();
    if ((e = lvcl_bvh_build(r->scene.positions, r->scene.indices, r->scene.triangle_count, &r->bvh, st))) return e;
    stats->bvh_build_seconds = lvcl_seconds() - t;
    if (r->bvh.skipped) lvcl_warn("%zu triangles of zero area or with non-finite vertices left out", r->bvh.skipped);

    if ((e = lvcl_device_open(o->device, &r->device, st))) return e;
    if ((e = lvcl_pack_scene(&r->scene, &r->bvh, o->seed, (uint32_t)o->max_depth, &r->packed, st))) return e;
    if ((e = lvcl_device_scene_upload(&r->device, &r->scene, &r->packed, &r->device_scene, st))) return e;
    unsigned features = lvcl_scene_features(&r->scene);
    if ((e = lvcl_program_build(&r->device, features, o->fast_math, &r->program, st))) return e;

    int w, h;
    lvcl_image_size(&r->scene.camera, o->width, o->height, &w, &h);
    lv_camera cam = lvcl_camera_make(&r->scene.camera, r->packed.bounds_min, r->packed.bounds_max, w, h);
    lvcl_pt_settings ps = {o->spp, o->time_limit, !o->quiet};
    stats->startup_seconds = lvcl_seconds() - stats->process_start;
    if ((e = lvcl_render_pt(&r->device, &r->program, &r->device_scene, &cam, &ps, &r->result, st))) return e;
    if ((e = write_outputs(o, &r->result, st))) return e;

    stats->device = &r->device;
    stats->scene = &r->scene;
    stats->bvh = &r->bvh;
    stats->program = &r->program;
    stats->device_bytes = r->device_scene.device_bytes;
    stats->result = &r->result;
    stats->features = features;
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

    run_state r;
    memset(&r, 0, sizeof r);
    stats.options = &o;
    lvcl_error e = run(&o, &r, &stats, &st);
    if (!e && o.stats) e = lvcl_stats_write(o.stats, &stats, &st);
    if (e) fprintf(stderr, "lvcl: error: %s\n", st.message);
    run_release(&r);
    return e ? 1 : 0;
}
