/* lvcl-bench rays: ray throughput of lvcl's traversal on three workloads
 * (primary, diffuse, shadow; see bench/RAYS.md in the shared notes), and
 * of Embree on the very same rays where Embree was found at build time.
 * Prints one JSON object per line: the set-up, then one per workload. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../host/render/session.h"
#include "bench.h"
#include "../host/util/timer.h"
#include "kernels/rays_args.h"
#include "rays.h"

typedef struct {
    const char *device;
    int width;
    int repeat;
    unsigned seed;
    const char *scene;
} options;

typedef struct {
    options opt;
    lvcl_session *s;
    lvcl_program program; /* bench/kernels/rays.cl, built beside the session's */
    cl_kernel primary, closest, any, secondary;
    bench_embree *embree;
    double embree_build_seconds;
    char device_json[300]; /* the device name as a JSON string */
} bench;

typedef struct {
    size_t hits;
    uint32_t checksum;
    double mean_distance;
} summary;

static void usage(void)
{
    fprintf(stderr,
            "usage: lvcl-bench rays [--device D] [--width W] [--repeat N] [--seed S] SCENE\n"
            "  SCENE: a .gltf/.glb path or an embedded scene name (cornell, furnace, kitchen)\n"
            "  --width W   primary-ray image width (default 1024; height from the camera's aspect)\n"
            "  --repeat N  timed runs per workload, the median is reported (default 5)\n");
}

static int parse_options(int argc, char **argv, options *o)
{
    *o = (options){NULL, 1024, 5, 0, NULL};
    if (argc < 2 || strcmp(argv[1], "rays")) return 0;
    for (int i = 2; i < argc; i++) {
        const char *a = argv[i];
        int has_value = i + 1 < argc;
        if (!strcmp(a, "--device") && has_value) o->device = argv[++i];
        else if (!strcmp(a, "--width") && has_value) o->width = atoi(argv[++i]);
        else if (!strcmp(a, "--repeat") && has_value) o->repeat = atoi(argv[++i]);
        else if (!strcmp(a, "--seed") && has_value) o->seed = (unsigned)strtoul(argv[++i], NULL, 10);
        else if (a[0] != '-' && !o->scene) o->scene = a;
        else return 0;
    }
    return o->scene && o->width > 0 && o->repeat > 0;
}

typedef LVCL_KERNEL_ARGS(LV_RAYS_PRIMARY_ARGS) rays_primary_args;
typedef LVCL_KERNEL_ARGS(LV_RAYS_TRACE_ARGS) rays_trace_args;
typedef LVCL_KERNEL_ARGS(LV_RAYS_SECONDARY_ARGS) rays_secondary_args;
/* clang-format off */
static LVCL_DEFINE_BINDER(lv_rays_primary, LV_RAYS_PRIMARY_ARGS, rays_primary_args)
static LVCL_DEFINE_BINDER(lv_rays_trace, LV_RAYS_TRACE_ARGS, rays_trace_args)
static LVCL_DEFINE_BINDER(lv_rays_secondary, LV_RAYS_SECONDARY_ARGS, rays_secondary_args)
    /* clang-format on */

    /* Times the trace kernel alone, after one untimed launch (PoCL compiles a
 * kernel's machine code on its first launch). */
    static lvcl_error
    time_lvcl(bench *b, cl_mem rays, cl_mem hits, size_t count, int any_hit, double *seconds, lvcl_status *st)
{
    cl_kernel k = any_hit ? b->any : b->closest;
    rays_trace_args a = {
        .scene = &lvcl_session_device_scene(b->s, 0)->buffers, .rays = rays, .count = (cl_uint)count, .hits = hits};
    lvcl_error e = lvcl_bind_lv_rays_trace(k, &a, st);
    if (!e) e = bench_launch(b->s, k, count, "tracing", st);
    for (int r = 0; r < b->opt.repeat && !e; r++) {
        double start = lvcl_seconds();
        e = bench_launch(b->s, k, count, "tracing", st);
        seconds[r] = lvcl_seconds() - start;
    }
    return e;
}

static void time_embree(bench *b, const bench_ray *rays, size_t count, int any_hit, bench_embree_api api,
                        bench_hit *hits, double *seconds)
{
    bench_embree_trace(b->embree, rays, count, any_hit, api, hits); /* warm caches and threads */
    for (int r = 0; r < b->opt.repeat; r++) {
        double start = lvcl_seconds();
        bench_embree_trace(b->embree, rays, count, any_hit, api, hits);
        seconds[r] = lvcl_seconds() - start;
    }
}

/* Closest hits: hit count, sum of prim_ids mod 2^32, mean hit distance.
 * Occlusion, which has no hit distance or well-defined occluder: occluded
 * count, sum of occluded rays' indices mod 2^32, their mean light distance. */
static summary summarize(const bench_ray *rays, const bench_hit *hits, size_t count, int any_hit)
{
    summary s = {0, 0, 0.0};
    for (size_t i = 0; i < count; i++) {
        if (hits[i].prim_id == BENCH_NO_HIT) continue;
        s.hits++;
        s.checksum += any_hit ? (uint32_t)i : hits[i].prim_id;
        s.mean_distance += any_hit ? rays[i].tmax / 0.999 : hits[i].t;
    }
    if (s.hits) s.mean_distance /= (double)s.hits;
    return s;
}

/* Rays on which the two tracers disagree: hit or miss, or which triangle. */
static size_t count_differences(const bench_hit *a, const bench_hit *b, size_t count, int any_hit)
{
    size_t d = 0;
    for (size_t i = 0; i < count; i++) {
        int ha = a[i].prim_id != BENCH_NO_HIT, hb = b[i].prim_id != BENCH_NO_HIT;
        d += ha != hb || (!any_hit && a[i].prim_id != b[i].prim_id);
    }
    return d;
}

static void print_embree(bench *b, const bench_ray *rays, const bench_hit *hits, size_t count, int any_hit,
                         double lvcl_seconds_median)
{
    if (!b->embree) {
        printf(", \"embree\": null");
        return;
    }
    bench_hit *eh = calloc(count ? count : 1, sizeof *eh);
    double *t = malloc((size_t)b->opt.repeat * sizeof *t);
    if (!eh || !t) {
        free(eh);
        free(t);
        printf(", \"embree\": null");
        return;
    }
    time_embree(b, rays, count, any_hit, BENCH_EMBREE_PACKETS, eh, t);
    double sec = bench_median(t, b->opt.repeat);
    summary s = summarize(rays, eh, count, any_hit);
    printf(", \"embree_mrays\": %.3f, \"embree_mrays_best\": %.3f, \"embree_seconds\": %.6f, \"embree_hits\": %zu, "
           "\"embree_checksum\": %u, \"embree_mean_distance\": %.7g, \"differing_rays\": %zu, \"ratio\": %.4f",
           count / sec * 1e-6, count / t[0] * 1e-6, sec, s.hits, s.checksum, s.mean_distance,
           count_differences(hits, eh, count, any_hit), sec / lvcl_seconds_median);
    /* The single-ray API on the same rays: the yardstick for primary and shadow rays. */
    time_embree(b, rays, count, any_hit, BENCH_EMBREE_SINGLE, eh, t);
    double single = bench_median(t, b->opt.repeat);
    printf(", \"embree_single_mrays\": %.3f, \"embree_single_hits\": %zu, \"ratio_single\": %.4f",
           count / single * 1e-6, summarize(rays, eh, count, any_hit).hits, single / lvcl_seconds_median);
    free(eh);
    free(t);
}

/* Traces `count` rays from the device buffer `rays` into `hits`, times lvcl
 * and Embree on them and prints the workload's line. The rays and hits
 * read back are returned in *rays_out and *hits_out (the caller frees). */
static lvcl_error run_workload(bench *b, const char *name, cl_mem rays, cl_mem hits, size_t count, int any_hit,
                               bench_ray **rays_out, bench_hit **hits_out, lvcl_status *st)
{
    double *t = malloc((size_t)b->opt.repeat * sizeof *t);
    bench_ray *hr = malloc((count ? count : 1) * sizeof *hr);
    bench_hit *hh = malloc((count ? count : 1) * sizeof *hh);
    lvcl_error e = !t || !hr || !hh ? lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory") : LVCL_OK;
    if (!e) e = time_lvcl(b, rays, hits, count, any_hit, t, st);
    if (!e) e = bench_read_back(b->s, rays, count * sizeof *hr, hr, st);
    if (!e) e = bench_read_back(b->s, hits, count * sizeof *hh, hh, st);
    if (e) {
        free(t);
        free(hr);
        free(hh);
        return e;
    }
    double sec = bench_median(t, b->opt.repeat);
    summary s = summarize(hr, hh, count, any_hit);
    printf("{\"workload\": \"%s\", \"device\": %s, \"triangles\": %zu, \"rays\": %zu, \"query\": \"%s\", "
           "\"mrays\": %.3f, \"mrays_best\": %.3f, \"seconds\": %.6f, \"hits\": %zu, \"checksum\": %u, "
           "\"mean_distance\": %.7g",
           name, b->device_json, lvcl_session_scene(b->s)->triangle_count, count, any_hit ? "any" : "closest",
           count / sec * 1e-6, count / t[0] * 1e-6, sec, s.hits, s.checksum, s.mean_distance);
    print_embree(b, hr, hh, count, any_hit, sec);
    printf("}\n");
    fflush(stdout);
    free(t);
    *rays_out = hr;
    *hits_out = hh;
    return LVCL_OK;
}

extern const unsigned char lvcl_bench_kernel_source[];
extern const size_t lvcl_bench_kernel_source_size;

/* The benchmark's own program, with the scene's features and fast math as
 * the renderer builds its own, so the traversal measured is the one lvcl
 * renders with. */
static lvcl_error create_kernels(bench *b, lvcl_status *st)
{
    lvcl_error e = bench_build_program(b->s, lvcl_bench_kernel_source, lvcl_bench_kernel_source_size, &b->program, st);
    if (e || (e = lvcl_kernel_create(&b->program, "lv_rays_primary", &b->primary, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_rays_trace_closest", &b->closest, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_rays_trace_any", &b->any, st)) ||
        (e = lvcl_kernel_create(&b->program, "lv_rays_secondary", &b->secondary, st)))
        return e;
    return LVCL_OK;
}

static lvcl_error generate_primary(bench *b, const lv_camera *cam, cl_mem rays, lvcl_status *st)
{
    rays_primary_args a = {.camera = *cam, .rays = rays};
    lvcl_error e = lvcl_bind_lv_rays_primary(b->primary, &a, st);
    return e ? e : bench_launch(b->s, b->primary, (size_t)cam->width * cam->height, "generating primary rays", st);
}

/* Emissive triangles lead the light table (host/device/packed_scene.c). */
static cl_uint emissive_count(const lvcl_packed_scene *p)
{
    cl_uint n = 0;
    while (n < p->light_count && p->lights[n].kind == LV_LIGHT_AREA) n++;
    return n;
}

static lvcl_error generate_secondary(bench *b, cl_mem primary, cl_mem primary_hits, cl_mem hit_pixels, size_t count,
                                     cl_uint emitters, cl_mem diffuse, cl_mem shadow, lvcl_status *st)
{
    const float *lo = lvcl_session_packed_scene(b->s)->bounds_min, *hi = lvcl_session_packed_scene(b->s)->bounds_max;
    float diag = sqrtf((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    rays_secondary_args a = {.scene = &lvcl_session_device_scene(b->s, 0)->buffers,
                             .primary = primary,
                             .primary_hits = primary_hits,
                             .hit_pixels = hit_pixels,
                             .count = (cl_uint)count,
                             .offset = 1e-5f * diag,
                             .emissive_count = emitters,
                             .diffuse = diffuse,
                             .shadow = shadow};
    cl_kernel k = b->secondary;
    lvcl_error e = lvcl_bind_lv_rays_secondary(k, &a, st);
    return e ? e : bench_launch(b->s, k, count, "generating secondary rays", st);
}

/* The pixels whose primary ray hit, in pixel order: the secondary rays'
 * sources. */
static uint32_t *hit_pixel_list(const bench_hit *hits, size_t count, size_t *n)
{
    uint32_t *list = malloc((count ? count : 1) * sizeof *list);
    *n = 0;
    for (size_t i = 0; list && i < count; i++)
        if (hits[i].prim_id != BENCH_NO_HIT) list[(*n)++] = (uint32_t)i;
    return list;
}

static void print_setup(bench *b, int width, int height)
{
    char scene[300];
    bench_json_string(scene, sizeof scene, b->opt.scene);
    printf("{\"bench\": \"rays\", \"scene\": %s, \"device\": %s, \"triangles\": %zu, \"bvh_triangles\": %zu, "
           "\"bvh_nodes\": %zu, \"bvh_width\": %d, \"bvh_build_seconds\": %.4f, \"kernel_build_seconds\": %.3f, "
           "\"kernel_from_cache\": %s, \"width\": %d, \"height\": %d, \"repeat\": %d",
           scene, b->device_json, lvcl_session_scene(b->s)->triangle_count, lvcl_session_accel(b->s)->triangle_count,
           lvcl_session_packed_scene(b->s)->node_count, lvcl_session_packed_scene(b->s)->bvh_width,
           lvcl_session_bvh_build_seconds(b->s), b->program.build_seconds, b->program.from_cache ? "true" : "false",
           width, height, b->opt.repeat);
    if (b->embree)
        printf(", \"embree\": \"%s\", \"embree_build_seconds\": %.4f", bench_embree_method(), b->embree_build_seconds);
    else printf(", \"embree\": null");
    printf("}\n");
    fflush(stdout);
}

/* Runs the three workloads; device buffers are released on the way out. */
static lvcl_error run(bench *b, lvcl_status *st)
{
    int w, h;
    lvcl_image_size(&lvcl_session_scene(b->s)->camera, b->opt.width, 0, &w, &h);
    lv_camera cam = lvcl_camera_make(&lvcl_session_scene(b->s)->camera, lvcl_session_packed_scene(b->s)->bounds_min,
                                     lvcl_session_packed_scene(b->s)->bounds_max, w, h);
    size_t pixels = (size_t)w * h, n_sec = 0;
    print_setup(b, w, h);

    cl_mem mem[6] = {0}; /* primary rays, primary hits, hit pixels, diffuse, shadow, secondary hits */
    bench_ray *pr = NULL, *dr = NULL, *sr = NULL;
    bench_hit *ph = NULL, *dh = NULL, *sh = NULL;
    uint32_t *pix = NULL;
    cl_uint emitters = emissive_count(lvcl_session_packed_scene(b->s));
    lvcl_error e = LVCL_OK;
    if (!(mem[0] = bench_device_buffer(b->s, pixels * sizeof(bench_ray), NULL, st)) ||
        !(mem[1] = bench_device_buffer(b->s, pixels * sizeof(bench_hit), NULL, st)))
        e = st->code;
    if (!e) e = generate_primary(b, &cam, mem[0], st);
    if (!e) e = run_workload(b, "primary", mem[0], mem[1], pixels, 0, &pr, &ph, st);
    if (!e && !(pix = hit_pixel_list(ph, pixels, &n_sec)))
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory");
    if (!e &&
        (!(mem[2] = bench_device_buffer(b->s, n_sec * sizeof *pix, pix, st)) ||
         !(mem[3] = bench_device_buffer(b->s, n_sec * sizeof(bench_ray), NULL, st)) ||
         !(mem[4] = bench_device_buffer(b->s, n_sec * sizeof(bench_ray), NULL, st)) ||
         !(mem[5] = bench_device_buffer(b->s, n_sec * sizeof(bench_hit), NULL, st))))
        e = st->code;
    if (!e) e = generate_secondary(b, mem[0], mem[1], mem[2], n_sec, emitters, mem[3], mem[4], st);
    if (!e) e = run_workload(b, "diffuse", mem[3], mem[5], n_sec, 0, &dr, &dh, st);
    if (!e && emitters == 0)
        printf("{\"workload\": \"shadow\", \"device\": %s, \"skipped\": \"the scene has no emissive triangles\"}\n",
               b->device_json);
    else if (!e) e = run_workload(b, "shadow", mem[4], mem[5], n_sec, 1, &sr, &sh, st);

    for (int i = 0; i < 6; i++)
        if (mem[i]) clReleaseMemObject(mem[i]);
    free(pr), free(ph), free(dr), free(dh), free(sr), free(sh), free(pix);
    return e;
}

static void release_kernels(bench *b)
{
    cl_kernel all[] = {b->primary, b->closest, b->any, b->secondary};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        if (all[i]) clReleaseKernel(all[i]);
}

int bench_rays(int argc, char **argv)
{
    bench b;
    memset(&b, 0, sizeof b);
    if (!parse_options(argc, argv, &b.opt)) {
        usage();
        return 2;
    }
    lvcl_status st = {0};
    lvcl_scene scene = {0};
    lvcl_error e = bench_open(b.opt.scene, b.opt.device, b.opt.seed, 1, &scene, &b.s, &st);
    if (!e) e = create_kernels(&b, &st);
    if (!e) {
        bench_json_string(b.device_json, sizeof b.device_json, lvcl_session_device(b.s, 0)->name);
        b.embree = bench_embree_create(lvcl_session_scene(b.s), &b.embree_build_seconds);
        e = run(&b, &st);
    }
    if (e) fprintf(stderr, "lvcl-bench: error: %s\n", st.message);
    bench_embree_destroy(b.embree);
    release_kernels(&b);
    lvcl_program_release(&b.program);
    lvcl_scene_free(&scene);
    lvcl_session_close(b.s);
    return e ? 1 : 0;
}
