#include "image_pass.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "../util/parallel.h"
#include "../device/program.h"
#include "../util/progress.h"
#include "../util/timer.h"

/* Bands per device: enough for a device that runs ahead to take more. */
#define BANDS_PER_DEVICE 8

/* What the devices' threads share. */
typedef struct {
    pthread_mutex_t lock;
    const lv_camera *camera;
    const lvcl_pass_settings *settings;
    size_t pixels, band_pixels;
    int bands, next_band;
    int *owner; /* device that rendered each band */
    int failed; /* a device failed: the others stop */
    lvcl_progress bar;
    long launches_done, launches_total;
    const char *unit; /* what the progress bar counts */
    double start, first_launch_seconds;
    int samples; /* samples per pixel taken (one device: may stop at the time limit) */
} pass_state;

typedef struct {
    pass_state *ps;
    lvcl_pass_device *pd;
    int index;
    cl_mem sum;
    lvcl_error e;
    lvcl_status st;
} worker;

/* A device failed: the others stop at their next band. */
static void *fail_pass(pass_state *ps)
{
    pthread_mutex_lock(&ps->lock);
    ps->failed = 1;
    pthread_mutex_unlock(&ps->lock);
    return NULL;
}

/* Renders bands until none is left: all samples of one band per turn. */
static void *render_bands(void *arg)
{
    worker *w = arg;
    pass_state *ps = w->ps;
    const lvcl_device *dev = w->pd->device;
    cl_kernel k = w->pd->kernel;
    const lvcl_pixel_arg_indices *a = &w->pd->pixel_args;
    if ((w->e = lvcl_kernel_arg(k, a->camera, sizeof *ps->camera, ps->camera, "the camera", &w->st)) ||
        (w->e = lvcl_kernel_arg(k, a->sum, sizeof(cl_mem), &w->sum, "the image sum", &w->st)))
        return fail_pass(ps);
    for (;;) {
        pthread_mutex_lock(&ps->lock);
        int band = ps->failed ? ps->bands : ps->next_band++;
        pthread_mutex_unlock(&ps->lock);
        if (band >= ps->bands) break;
        double band_start = lvcl_seconds();
        cl_uint first = (cl_uint)((size_t)band * ps->band_pixels);
        cl_uint count = (cl_uint)(ps->pixels - first < ps->band_pixels ? ps->pixels - first : ps->band_pixels);
        if ((w->e = lvcl_kernel_arg(k, a->first_pixel, sizeof first, &first, "the band's first pixel", &w->st)) ||
            (w->e = lvcl_kernel_arg(k, a->pixel_count, sizeof count, &count, "the band's pixel count", &w->st)))
            return fail_pass(ps);
        int s = 0;
        while (s < ps->settings->spp) {
            cl_uint index = (cl_uint)(ps->settings->first_sample + s);
            if ((w->e = lvcl_kernel_arg(k, a->sample_index, sizeof index, &index, "the sample index", &w->st)) ||
                (w->e = lvcl_kernel_enqueue(dev, k, count, "launching the camera pass", &w->st)) ||
                (w->e = lvcl_cl_check(clFinish(dev->queue), "running the camera pass", &w->st)))
                return fail_pass(ps);
            s++;
            pthread_mutex_lock(&ps->lock);
            double elapsed = lvcl_seconds() - ps->start;
            if (ps->first_launch_seconds == 0) ps->first_launch_seconds = elapsed;
            ps->launches_done++;
            /* Under a time limit the bar shows the time spent, of the limit. */
            if (ps->settings->time_limit > 0)
                lvcl_progress_update(&ps->bar, elapsed < ps->settings->time_limit ? elapsed : ps->settings->time_limit,
                                     ps->settings->time_limit, "s");
            else lvcl_progress_update(&ps->bar, (double)ps->launches_done, (double)ps->launches_total, ps->unit);
            pthread_mutex_unlock(&ps->lock);
            /* The time limit applies to one device, whose one band is the whole image. */
            if (ps->settings->time_limit > 0 && elapsed >= ps->settings->time_limit) break;
        }
        pthread_mutex_lock(&ps->lock);
        ps->owner[band] = w->index;
        ps->samples = s;
        pthread_mutex_unlock(&ps->lock);
        w->pd->bands++;
        w->pd->pixels += count;
        w->pd->busy_seconds += lvcl_seconds() - band_start;
    }
    return NULL;
}

/* Reads each device's sums and takes from each the bands it rendered. */
static lvcl_error gather_image(worker *workers, int n, const pass_state *ps, lvcl_render_result *out, lvcl_status *st)
{
    float *acc = malloc(ps->pixels * 4 * sizeof(float));
    out->rgb = malloc(ps->pixels * 3 * sizeof(float));
    if (!acc || !out->rgb) {
        free(acc);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the image");
    }
    lvcl_error e = LVCL_OK;
    for (int d = 0; d < n && !e; d++) {
        e = lvcl_cl_check(clEnqueueReadBuffer(workers[d].pd->device->queue, workers[d].sum, CL_TRUE, 0,
                                              ps->pixels * 4 * sizeof(float), acc, 0, NULL, NULL),
                          "reading the image", st);
        for (int b = 0; !e && b < ps->bands; b++) {
            if (ps->owner[b] != d) continue;
            size_t end = (size_t)(b + 1) * ps->band_pixels;
            for (size_t i = (size_t)b * ps->band_pixels; i < end && i < ps->pixels; i++) {
                float w = acc[4 * i + 3];
                for (int c = 0; c < 3; c++) out->rgb[3 * i + c] = w > 0 ? acc[4 * i + c] / w : 0.0f;
            }
        }
    }
    free(acc);
    return e;
}

lvcl_error lvcl_image_pass(lvcl_pass_device *devices, int n, const lv_camera *camera,
                           const lvcl_pass_settings *settings, lvcl_render_result *out, lvcl_status *st)
{
    memset(out, 0, sizeof *out);
    pass_state ps = {.camera = camera, .settings = settings};
    ps.pixels = (size_t)camera->width * camera->height;
    ps.bands = n == 1 ? 1 : n * BANDS_PER_DEVICE;
    if ((size_t)ps.bands > camera->height) ps.bands = (int)camera->height;
    size_t rows = (camera->height + (size_t)ps.bands - 1) / (size_t)ps.bands;
    ps.band_pixels = rows * camera->width;
    ps.bands = (int)((ps.pixels + ps.band_pixels - 1) / ps.band_pixels);
    ps.launches_total = (long)ps.bands * settings->spp;
    ps.unit = n == 1 ? "spp" : "band samples";
    ps.owner = calloc((size_t)ps.bands, sizeof *ps.owner);
    worker *workers = calloc((size_t)n, sizeof *workers);
    if (!ps.owner || !workers) {
        free(ps.owner);
        free(workers);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the pass");
    }
    pthread_mutex_init(&ps.lock, NULL);

    lvcl_error e = LVCL_OK;
    float zero = 0.0f;
    for (int d = 0; d < n && !e; d++) {
        cl_int err;
        workers[d] = (worker){.ps = &ps, .pd = &devices[d], .index = d};
        devices[d].bands = 0;
        devices[d].pixels = 0;
        devices[d].busy_seconds = 0;
        workers[d].sum =
            clCreateBuffer(devices[d].device->context, CL_MEM_READ_WRITE, ps.pixels * 4 * sizeof(float), NULL, &err);
        if (!(e = lvcl_cl_check(err, "allocating the image", st)))
            e = lvcl_cl_check(clEnqueueFillBuffer(devices[d].device->queue, workers[d].sum, &zero, sizeof zero, 0,
                                                  ps.pixels * 4 * sizeof(float), 0, NULL, NULL),
                              "clearing the image", st);
    }
    if (!e) {
        lvcl_progress_start(&ps.bar, "render", settings->progress);
        ps.start = lvcl_seconds();
        lvcl_status thread_st = {0};
        lvcl_error threads_failed = lvcl_run_parallel(render_bands, workers, sizeof workers[0], n, &thread_st);
        lvcl_progress_finish(&ps.bar);
        out->render_seconds = lvcl_seconds() - ps.start;
        out->first_launch_seconds = ps.first_launch_seconds;
        out->samples = ps.samples;
        for (int d = 0; d < n && !e; d++)
            if (workers[d].e) {
                *st = workers[d].st;
                e = workers[d].e;
            }
        if (!e && threads_failed) {
            *st = thread_st;
            e = threads_failed;
        }
        if (!e) e = gather_image(workers, n, &ps, out, st);
    }
    if (!e) {
        out->width = (int)camera->width;
        out->height = (int)camera->height;
    } else {
        free(out->rgb);
        out->rgb = NULL;
    }
    for (int d = 0; d < n; d++)
        if (workers[d].sum) clReleaseMemObject(workers[d].sum);
    pthread_mutex_destroy(&ps.lock);
    free(ps.owner);
    free(workers);
    return e;
}
