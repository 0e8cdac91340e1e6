/* lvcl-bench wavefront: the path tracer as a megakernel (lv_pt_pass, one
 * path per work-item from camera to end, as lvcl renders) against the same
 * path tracer split into wavefront kernels over queues of paths
 * (bench/kernels/wavefront.cl: generate, then per bounce intersect, shade
 * and shadow, then finish). Same scene, pixels, samples and random
 * streams, so the two images agree up to rounding; prints one JSON line
 * with both times, the wavefront's time per stage and the images'
 * difference. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../host/io/metrics.h"
#include "../host/util/timer.h"
#include "bench.h"
#include "kernels/wavefront_args.h"

typedef struct {
    const char *device;
    int width;
    int spp;
    int batch; /* paths in flight at once; 0 = every pixel */
    unsigned seed;
    const char *scene;
} options;

enum { STAGE_GENERATE, STAGE_INTERSECT, STAGE_SHADE, STAGE_SHADOW, STAGE_FINISH, STAGE_COUNT };
static const char *const stage_names[STAGE_COUNT] = {"generate", "intersect", "shade", "shadow", "finish"};

/* The path state, shadow rays and queues of one wavefront, a buffer each. */
enum {
    WF_RAY_ORIGIN,
    WF_RAY_DIR,
    WF_RAY_SKIP_INST,
    WF_BETA,
    WF_RADIANCE,
    WF_DEPTH,
    WF_RNG,
    WF_PIXEL,
    WF_CHAIN_FROM,
    WF_CHAIN_DIR,
    WF_HIT,
    WF_HIT_INST,
    WF_SHADOW_ORIGIN,
    WF_SHADOW_DIR,
    WF_SHADOW_LI,
    WF_SHADOW_CHAIN,
    WF_QUEUE_A,
    WF_QUEUE_B,
    WF_SHADOW_QUEUE,
    WF_COUNTERS,
    WF_BUFFER_COUNT
};
/* Bytes per path of each buffer (the counters: two in all). */
static const size_t wf_entry_bytes[WF_BUFFER_COUNT] = {16, 16, 4,  16, 16, 8,  16, 4, 16, 16,
                                                       16, 4,  16, 16, 16, 16, 4,  4, 4,  0};

typedef struct {
    options opt;
    lvcl_session *s;
    lvcl_program program;
    cl_kernel mega, generate, intersect, shade, shadow, finish;
    lv_camera camera;
    size_t pixels;
    cl_uint see_through; /* as lvcl's default: light samples go on through the scene's glass, if any */
    cl_mem pixel_list, sum, sum_sq;
    cl_mem wf[WF_BUFFER_COUNT];
    double stage_seconds[STAGE_COUNT];
    uint64_t launches, path_vertices, shadow_rays;
} bench_wf;

typedef LVCL_KERNEL_ARGS(LV_WF_GENERATE_ARGS) wf_generate_args;
typedef LVCL_KERNEL_ARGS(LV_WF_INTERSECT_ARGS) wf_intersect_args;
typedef LVCL_KERNEL_ARGS(LV_WF_SHADE_ARGS) wf_shade_args;
typedef LVCL_KERNEL_ARGS(LV_WF_SHADOW_PASS_ARGS) wf_shadow_args;
typedef LVCL_KERNEL_ARGS(LV_WF_FINISH_ARGS) wf_finish_args;
/* clang-format off */
static LVCL_DEFINE_BINDER(lv_wf_generate, LV_WF_GENERATE_ARGS, wf_generate_args)
static LVCL_DEFINE_BINDER(lv_wf_intersect, LV_WF_INTERSECT_ARGS, wf_intersect_args)
static LVCL_DEFINE_BINDER(lv_wf_shade, LV_WF_SHADE_ARGS, wf_shade_args)
static LVCL_DEFINE_BINDER(lv_wf_shadow, LV_WF_SHADOW_PASS_ARGS, wf_shadow_args)
static LVCL_DEFINE_BINDER(lv_wf_finish, LV_WF_FINISH_ARGS, wf_finish_args)
    /* clang-format on */

    static void usage(void)
{
    fprintf(stderr,
            "usage: lvcl-bench wavefront [--device D] [--width W] [--spp N] [--seed S] SCENE\n"
            "  SCENE: a .gltf/.glb path or an embedded scene name (cornell, furnace, kitchen)\n"
            "  --width W  image width (default 256; height from the camera's aspect)\n"
            "  --spp N    samples per pixel, each way (default 16)\n"
            "  --batch B  wavefront: paths in flight at once, pixels taken B at a time (default: all)\n");
}

static int parse_options(int argc, char **argv, options *o)
{
    *o = (options){NULL, 256, 16, 0, 0, NULL};
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if (!strcmp(a, "--device") && has_value) o->device = argv[++i];
        else if (!strcmp(a, "--width") && has_value) o->width = atoi(argv[++i]);
        else if (!strcmp(a, "--spp") && has_value) o->spp = atoi(argv[++i]);
        else if (!strcmp(a, "--batch") && has_value) o->batch = atoi(argv[++i]);
        else if (!strcmp(a, "--seed") && has_value) o->seed = (unsigned)strtoul(argv[++i], NULL, 10);
        else if (a[0] != '-' && !o->scene) o->scene = a;
        else return 0;
    }
    return o->scene && o->width > 0 && o->spp > 0 && o->batch >= 0;
}

extern const unsigned char lvcl_wavefront_kernel_source[];
extern const size_t lvcl_wavefront_kernel_source_size;

/* The wavefront's program, built as the renderer builds its own; the
 * megakernel is the renderer's own lv_pt_pass. (Built into this program
 * beside lv_wf_shade, Intel's compiler no longer inlined the shared
 * lv_path_shade into lv_pt_pass, which then ran 4x slower.) */
static lvcl_error create_kernels(bench_wf *b, lvcl_status *st)
{
    lvcl_error e =
        bench_build_program(b->s, lvcl_wavefront_kernel_source, lvcl_wavefront_kernel_source_size, &b->program, st);
    if (e || (e = lvcl_kernel_create(lvcl_session_program(b->s, 0), "lv_pt_pass", &b->mega, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_wf_generate", &b->generate, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_wf_intersect", &b->intersect, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_wf_shade", &b->shade, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_wf_shadow", &b->shadow, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_wf_finish", &b->finish, st)))
        return e;
    return LVCL_OK;
}

static lvcl_error create_buffers(bench_wf *b, lvcl_status *st)
{
    uint32_t *list = malloc(b->pixels * sizeof *list);
    if (!list) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory");
    for (size_t i = 0; i < b->pixels; i++) list[i] = (uint32_t)i;
    b->pixel_list = bench_device_buffer(b->s, b->pixels * sizeof *list, list, st);
    free(list);
    if (!b->pixel_list || !(b->sum = bench_device_buffer(b->s, b->pixels * 4 * sizeof(float), NULL, st)) ||
        !(b->sum_sq = bench_device_buffer(b->s, b->pixels * sizeof(float), NULL, st)))
        return st->code;
    for (int i = 0; i < WF_BUFFER_COUNT; i++) {
        size_t bytes = i == WF_COUNTERS ? 2 * sizeof(cl_uint) : b->pixels * wf_entry_bytes[i];
        if (!(b->wf[i] = bench_device_buffer(b->s, bytes, NULL, st))) return st->code;
    }
    return LVCL_OK;
}

static lvcl_error clear_sums(bench_wf *b, lvcl_status *st)
{
    const lvcl_device *dev = lvcl_session_device(b->s, 0);
    float zero = 0.0f;
    lvcl_error e = lvcl_cl_check(
        clEnqueueFillBuffer(dev->queue, b->sum, &zero, sizeof zero, 0, b->pixels * 4 * sizeof(float), 0, NULL, NULL),
        "clearing the sums", st);
    if (!e)
        e = lvcl_cl_check(
            clEnqueueFillBuffer(dev->queue, b->sum_sq, &zero, sizeof zero, 0, b->pixels * sizeof(float), 0, NULL, NULL),
            "clearing the sums", st);
    return e ? e : lvcl_cl_check(clFinish(dev->queue), "clearing the sums", st);
}

static lvcl_error megakernel_samples(bench_wf *b, int spp, lvcl_status *st)
{
    lvcl_pt_pass_args a = {.scene = &lvcl_session_device_scene(b->s, 0)->buffers,
                           .see_through = b->see_through,
                           .camera = b->camera,
                           .pixel_list = b->pixel_list,
                           .first_pixel = 0,
                           .pixel_count = (cl_uint)b->pixels,
                           .first_sample = 0,
                           .sum = b->sum,
                           .sum_sq = b->sum_sq};
    lvcl_error e = lvcl_bind_lv_pt_pass(b->mega, &a, st);
    for (int i = 0; i < spp && !e; i++) e = bench_launch(b->s, b->mega, b->pixels, "path tracing", st);
    return e;
}

/* Launches one stage and adds its time. */
static lvcl_error stage(bench_wf *b, int which, cl_kernel k, size_t count, lvcl_status *st)
{
    double start = lvcl_seconds();
    lvcl_error e = bench_launch(b->s, k, count, stage_names[which], st);
    b->stage_seconds[which] += lvcl_seconds() - start;
    b->launches++;
    return e;
}

/* One sample of pixels first .. first + n - 1 through the wavefront:
 * paths advance a vertex per round until none is left. */
static lvcl_error wavefront_batch(bench_wf *b, size_t first, size_t n, lvcl_status *st)
{
    const lvcl_scene_buffers *scene = &lvcl_session_device_scene(b->s, 0)->buffers;
    cl_mem *w = b->wf;
#define WF_PATH(...)                                                                                              \
    .ray_origin = w[WF_RAY_ORIGIN], .ray_dir = w[WF_RAY_DIR], .ray_skip_inst = w[WF_RAY_SKIP_INST],               \
    .beta = w[WF_BETA], .radiance = w[WF_RADIANCE], .depth = w[WF_DEPTH], .rng = w[WF_RNG], .pixel = w[WF_PIXEL], \
    .chain_from = w[WF_CHAIN_FROM], .chain_dir = w[WF_CHAIN_DIR]
    wf_generate_args g = {.scene = scene,
                          .camera = b->camera,
                          .pixel_list = b->pixel_list,
                          .first_pixel = (cl_uint)first,
                          .pixel_count = (cl_uint)n,
                          .first_sample = 0,
                          .sum = b->sum,
                          .sum_sq = b->sum_sq,
                          WF_PATH(),
                          .queue = w[WF_QUEUE_A]};
    lvcl_error e = lvcl_bind_lv_wf_generate(b->generate, &g, st);
    if (!e) e = stage(b, STAGE_GENERATE, b->generate, n, st);
    cl_mem queue = w[WF_QUEUE_A], next = w[WF_QUEUE_B];
    cl_uint count = (cl_uint)n;
    const lvcl_device *dev = lvcl_session_device(b->s, 0);
    while (!e && count) {
        wf_intersect_args in = {.scene = scene,
                                .queue = queue,
                                .count = count,
                                .ray_origin = w[WF_RAY_ORIGIN],
                                .ray_dir = w[WF_RAY_DIR],
                                .ray_skip_inst = w[WF_RAY_SKIP_INST],
                                .hit = w[WF_HIT],
                                .hit_inst = w[WF_HIT_INST]};
        if (!(e = lvcl_bind_lv_wf_intersect(b->intersect, &in, st)))
            e = stage(b, STAGE_INTERSECT, b->intersect, count, st);
        cl_uint counters[2] = {0, 0};
        if (!e)
            e = lvcl_cl_check(
                clEnqueueWriteBuffer(dev->queue, w[WF_COUNTERS], CL_TRUE, 0, sizeof counters, counters, 0, NULL, NULL),
                "clearing the queue counters", st);
        wf_shade_args sh = {.scene = scene,
                            .queue = queue,
                            .count = count,
                            .see_through = b->see_through,
                            WF_PATH(),
                            .hit = w[WF_HIT],
                            .hit_inst = w[WF_HIT_INST],
                            .shadow_origin = w[WF_SHADOW_ORIGIN],
                            .shadow_dir = w[WF_SHADOW_DIR],
                            .shadow_li = w[WF_SHADOW_LI],
                            .shadow_chain = w[WF_SHADOW_CHAIN],
                            .next_queue = next,
                            .shadow_queue = w[WF_SHADOW_QUEUE],
                            .counters = w[WF_COUNTERS]};
        if (!e && !(e = lvcl_bind_lv_wf_shade(b->shade, &sh, st))) e = stage(b, STAGE_SHADE, b->shade, count, st);
        if (!e) e = bench_read_back(b->s, w[WF_COUNTERS], sizeof counters, counters, st);
        b->path_vertices += count;
        b->shadow_rays += counters[1];
        wf_shadow_args sr = {.scene = scene,
                             .shadow_queue = w[WF_SHADOW_QUEUE],
                             .count = counters[1],
                             .shadow_origin = w[WF_SHADOW_ORIGIN],
                             .shadow_dir = w[WF_SHADOW_DIR],
                             .shadow_li = w[WF_SHADOW_LI],
                             .shadow_chain = w[WF_SHADOW_CHAIN],
                             .radiance = w[WF_RADIANCE]};
        if (!e && counters[1] && !(e = lvcl_bind_lv_wf_shadow(b->shadow, &sr, st)))
            e = stage(b, STAGE_SHADOW, b->shadow, counters[1], st);
        count = counters[0];
        cl_mem t = queue;
        queue = next;
        next = t;
    }
    wf_finish_args f = {
        .count = (cl_uint)n, .pixel = w[WF_PIXEL], .radiance = w[WF_RADIANCE], .sum = b->sum, .sum_sq = b->sum_sq};
    if (!e && !(e = lvcl_bind_lv_wf_finish(b->finish, &f, st))) e = stage(b, STAGE_FINISH, b->finish, n, st);
#undef WF_PATH
    return e;
}

static lvcl_error wavefront_sample(bench_wf *b, lvcl_status *st)
{
    size_t batch = b->opt.batch ? (size_t)b->opt.batch : b->pixels;
    lvcl_error e = LVCL_OK;
    for (size_t first = 0; first < b->pixels && !e; first += batch)
        e = wavefront_batch(b, first, first + batch < b->pixels ? batch : b->pixels - first, st);
    return e;
}

static lvcl_error wavefront_samples(bench_wf *b, int spp, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    for (int i = 0; i < spp && !e; i++) e = wavefront_sample(b, st);
    return e;
}

/* The pixel means of the sums, RGB. */
static lvcl_error read_image(bench_wf *b, float *rgb, lvcl_status *st)
{
    float *sum = malloc(b->pixels * 4 * sizeof *sum);
    if (!sum) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory");
    lvcl_error e = bench_read_back(b->s, b->sum, b->pixels * 4 * sizeof *sum, sum, st);
    for (size_t i = 0; !e && i < b->pixels; i++)
        for (int c = 0; c < 3; c++) rgb[3 * i + c] = sum[4 * i + 3] > 0.0f ? sum[4 * i + c] / sum[4 * i + 3] : 0.0f;
    free(sum);
    return e;
}

/* Times `spp` samples one way into a cleared image, after one untimed
 * sample (PoCL compiles machine code on a kernel's first launch). */
static lvcl_error time_way(bench_wf *b, lvcl_error (*way)(bench_wf *, int, lvcl_status *), float *rgb, double *seconds,
                           lvcl_status *st)
{
    lvcl_error e = way(b, 1, st);
    if (!e) e = clear_sums(b, st);
    memset(b->stage_seconds, 0, sizeof b->stage_seconds);
    b->launches = b->path_vertices = b->shadow_rays = 0;
    double start = lvcl_seconds();
    if (!e) e = way(b, b->opt.spp, st);
    *seconds = lvcl_seconds() - start;
    return e ? e : read_image(b, rgb, st);
}

static lvcl_error run(bench_wf *b, lvcl_status *st)
{
    int w, h;
    lvcl_image_size(&lvcl_session_scene(b->s)->camera, b->opt.width, 0, &w, &h);
    const lvcl_packed_scene *p = lvcl_session_packed_scene(b->s);
    b->camera = lvcl_camera_make(&lvcl_session_scene(b->s)->camera, p->bounds_min, p->bounds_max, w, h);
    b->pixels = (size_t)w * h;
    lvcl_render_request as_lvcl = {.mode = LVCL_MODE_PT, .see_through = 1};
    b->see_through = lvcl_session_sees_through(b->s, &as_lvcl) != 0;
    float *mega = malloc(b->pixels * 3 * sizeof *mega), *wave = malloc(b->pixels * 3 * sizeof *wave);
    lvcl_error e = !mega || !wave ? lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory") : LVCL_OK;
    double mega_seconds = 0.0, wave_seconds = 0.0;
    if (!e) e = create_buffers(b, st);
    if (!e) e = time_way(b, megakernel_samples, mega, &mega_seconds, st);
    if (!e) e = time_way(b, wavefront_samples, wave, &wave_seconds, st);
    if (!e) {
        char scene[300], device[300];
        bench_json_string(scene, sizeof scene, b->opt.scene);
        bench_json_string(device, sizeof device, lvcl_session_device(b->s, 0)->name);
        printf("{\"bench\": \"wavefront\", \"scene\": %s, \"device\": %s, \"width\": %d, \"height\": %d, \"spp\": %d, "
               "\"batch\": %zu, \"see_through\": %s, "
               "\"kernel_build_seconds\": %.3f, \"megakernel_seconds\": %.4f, \"wavefront_seconds\": %.4f, "
               "\"wavefront_over_megakernel\": %.4f, \"megakernel_paths_per_second\": %.1f, "
               "\"wavefront_paths_per_second\": %.1f, \"path_vertices\": %llu, \"shadow_rays\": %llu, "
               "\"launches\": %llu, \"relmse_between\": %.3g",
               scene, device, w, h, b->opt.spp, b->opt.batch ? (size_t)b->opt.batch : b->pixels,
               b->see_through ? "true" : "false", b->program.build_seconds, mega_seconds, wave_seconds,
               wave_seconds / mega_seconds, b->pixels * b->opt.spp / mega_seconds,
               b->pixels * b->opt.spp / wave_seconds, (unsigned long long)b->path_vertices,
               (unsigned long long)b->shadow_rays, (unsigned long long)b->launches,
               lvcl_relmse(wave, mega, b->pixels * 3));
        for (int i = 0; i < STAGE_COUNT; i++) printf(", \"%s_seconds\": %.4f", stage_names[i], b->stage_seconds[i]);
        printf("}\n");
    }
    free(mega);
    free(wave);
    return e;
}

static void release(bench_wf *b)
{
    cl_kernel k[] = {b->mega, b->generate, b->intersect, b->shade, b->shadow, b->finish};
    for (size_t i = 0; i < sizeof k / sizeof k[0]; i++)
        if (k[i]) clReleaseKernel(k[i]);
    cl_mem m[] = {b->pixel_list, b->sum, b->sum_sq};
    for (size_t i = 0; i < sizeof m / sizeof m[0]; i++)
        if (m[i]) clReleaseMemObject(m[i]);
    for (int i = 0; i < WF_BUFFER_COUNT; i++)
        if (b->wf[i]) clReleaseMemObject(b->wf[i]);
    lvcl_program_release(&b->program);
}

int bench_wavefront(int argc, char **argv)
{
    bench_wf b;
    memset(&b, 0, sizeof b);
    if (!parse_options(argc, argv, &b.opt)) {
        usage();
        return 2;
    }
    lvcl_status st = {0};
    lvcl_scene scene = {0};
    /* Paths of up to 64 segments, the renderer's default. */
    lvcl_error e = bench_open(b.opt.scene, b.opt.device, b.opt.seed, 64, &scene, &b.s, &st);
    if (!e) e = create_kernels(&b, &st);
    if (!e) e = run(&b, &st);
    if (e) fprintf(stderr, "lvcl-bench: error: %s\n", st.message);
    release(&b);
    lvcl_scene_free(&scene);
    lvcl_session_close(b.s);
    return e ? 1 : 0;
}
