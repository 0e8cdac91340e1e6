#include "image_pass.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "../util/interrupt.h"
#include "../util/parallel.h"
#include "adaptive_sampling.h"
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
    int *owner; /* device that rendered each band, -1 for another process's or none */
    lvcl_cluster *cluster; /* shared: bands come from the cluster's counter; else NULL */
    int failed; /* a device failed: the others stop */
    lvcl_progress bar;
    long launches_done, launches_total;
    const char *unit; /* what the progress bar counts */
    double start, first_launch_seconds;
    int samples; /* samples per pixel taken, the fewest of any band (may stop at the time limit or a signal) */
} pass_state;

typedef struct {
    pass_state *ps;
    lvcl_pass_device *pd;
    int index;
    cl_mem sum, sum_sq, list; /* the image's sums; the pixels a launch samples */
    lvcl_error e;
    lvcl_status st;
} worker;

/* The pixels [*lo, *hi) of band b (the last band may be short). */
static void band_span(const pass_state *ps, size_t b, size_t *lo, size_t *hi)
{
    *lo = b * ps->band_pixels;
    *hi = *lo + ps->band_pixels < ps->pixels ? *lo + ps->band_pixels : ps->pixels;
}

/* A device failed: the others stop at their next band. */
static void *fail_pass(pass_state *ps)
{
    pthread_mutex_lock(&ps->lock);
    ps->failed = 1;
    pthread_mutex_unlock(&ps->lock);
    return NULL;
}

/* One launch: a sample of each of the `count` pixels of the worker's list
 * from `first` on. */
static lvcl_error launch(worker *w, cl_uint first, cl_uint count)
{
    cl_kernel k = w->pd->kernel;
    const lvcl_pixel_arg_indices *a = &w->pd->pixel_args;
    if ((w->e = lvcl_kernel_arg(k, a->first_pixel, sizeof first, &first, "the launch's first pixel", &w->st)) ||
        (w->e = lvcl_kernel_arg(k, a->pixel_count, sizeof count, &count, "the launch's pixel count", &w->st)) ||
        (w->e = lvcl_kernel_enqueue(w->pd->device, k, count, "launching the camera pass", &w->st)))
        return w->e;
    return w->e = lvcl_cl_check(clFinish(w->pd->device->queue), "running the camera pass", &w->st);
}

/* After a launch: the time so far, and the progress bar at `done` of
 * `total` (launches, or samples per pixel). */
static double launched(pass_state *ps, double done, double total)
{
    pthread_mutex_lock(&ps->lock);
    double elapsed = lvcl_seconds() - ps->start;
    if (ps->first_launch_seconds == 0) ps->first_launch_seconds = elapsed;
    /* Under a time limit the bar shows the time spent, of the limit. */
    if (ps->settings->time_limit > 0)
        lvcl_progress_update(&ps->bar, elapsed < ps->settings->time_limit ? elapsed : ps->settings->time_limit,
                             ps->settings->time_limit, "s");
    else lvcl_progress_update(&ps->bar, done, total, ps->unit);
    pthread_mutex_unlock(&ps->lock);
    return elapsed;
}

/* Binds the arguments every launch of the worker shares. */
static lvcl_error bind_shared(worker *w)
{
    pass_state *ps = w->ps;
    cl_kernel k = w->pd->kernel;
    const lvcl_pixel_arg_indices *a = &w->pd->pixel_args;
    cl_uint first_sample = (cl_uint)ps->settings->first_sample;
    if ((w->e = lvcl_kernel_arg(k, a->camera, sizeof *ps->camera, ps->camera, "the camera", &w->st)) ||
        (w->e = lvcl_kernel_arg(k, a->pixel_list, sizeof(cl_mem), &w->list, "the pixel list", &w->st)) ||
        (w->e = lvcl_kernel_arg(k, a->first_sample, sizeof first_sample, &first_sample, "the first sample", &w->st)) ||
        (w->e = lvcl_kernel_arg(k, a->sum, sizeof(cl_mem), &w->sum, "the image sum", &w->st)) ||
        (w->e = lvcl_kernel_arg(k, a->sum_sq, sizeof(cl_mem), &w->sum_sq, "the image's squares", &w->st)))
        return w->e;
    return LVCL_OK;
}

/* Renders bands until none is left: all samples of one band per turn. */
static void *render_bands(void *arg)
{
    worker *w = arg;
    pass_state *ps = w->ps;
    if (bind_shared(w)) return fail_pass(ps);
    for (;;) {
        pthread_mutex_lock(&ps->lock);
        /* Bands not started when a signal asks to stop stay black (over a
         * cluster, unless another rank takes them: share_image counts them). */
        int band = ps->failed || (ps->cluster && lvcl_interrupted()) ? ps->bands : ps->next_band++;
        if (ps->cluster && band < ps->bands) {
            uint64_t taken = 0;
            w->e = ps->cluster->take(ps->cluster, 1, &taken, &w->st);
            band = w->e || taken > (uint64_t)ps->bands ? ps->bands : (int)taken;
        }
        if (!ps->cluster && band < ps->bands && lvcl_interrupted()) ps->samples = 0;
        pthread_mutex_unlock(&ps->lock);
        if (w->e) return fail_pass(ps);
        if (band >= ps->bands || lvcl_interrupted()) break;
        double band_start = lvcl_seconds();
        size_t lo, hi;
        band_span(ps, (size_t)band, &lo, &hi);
        cl_uint first = (cl_uint)lo, count = (cl_uint)(hi - lo);
        int s = 0;
        while (s < ps->settings->spp) {
            if (launch(w, first, count)) return fail_pass(ps);
            s++;
            pthread_mutex_lock(&ps->lock);
            long done = ++ps->launches_done;
            pthread_mutex_unlock(&ps->lock);
            /* With other processes, the band's place in the shared counter
             * stands for their launches too. */
            double shown = ps->cluster ? (double)band * ps->settings->spp + s : (double)done;
            double elapsed = launched(ps, shown, (double)ps->launches_total);
            /* The time limit applies to one device, whose one band is the whole image. */
            if ((ps->settings->time_limit > 0 && elapsed >= ps->settings->time_limit) || lvcl_interrupted()) break;
        }
        pthread_mutex_lock(&ps->lock);
        ps->owner[band] = w->index;
        if (s < ps->samples) ps->samples = s;
        pthread_mutex_unlock(&ps->lock);
        w->pd->bands++;
        w->pd->pixels += count;
        w->pd->busy_seconds += lvcl_seconds() - band_start;
    }
    return NULL;
}

/* Reads (write 0) or writes (write 1) the worker's image sums and squares. */
static lvcl_error move_sums(worker *w, int write, float *sum, float *sum_sq)
{
    cl_command_queue q = w->pd->device->queue;
    size_t n = w->ps->pixels;
    const char *what = write ? "storing the ranks' image for adaptive sampling" : "reading the image for adaptive sampling";
    cl_int err = write ? clEnqueueWriteBuffer(q, w->sum, CL_TRUE, 0, n * 4 * sizeof *sum, sum, 0, NULL, NULL)
                       : clEnqueueReadBuffer(q, w->sum, CL_TRUE, 0, n * 4 * sizeof *sum, sum, 0, NULL, NULL);
    if (err == CL_SUCCESS)
        err = write ? clEnqueueWriteBuffer(q, w->sum_sq, CL_TRUE, 0, n * sizeof *sum_sq, sum_sq, 0, NULL, NULL)
                    : clEnqueueReadBuffer(q, w->sum_sq, CL_TRUE, 0, n * sizeof *sum_sq, sum_sq, 0, NULL, NULL);
    return w->e = lvcl_cl_check(err, what, &w->st);
}

/* An adaptive pass is done: the worker's device holds the whole image, of
 * `taken` samples per pixel. */
static void adaptive_finished(worker *w, int taken, double start)
{
    for (int b = 0; b < w->ps->bands; b++) w->ps->owner[b] = w->index;
    w->ps->samples = taken;
    w->pd->pixels = w->ps->pixels;
    w->pd->busy_seconds = lvcl_seconds() - start;
}

/* One device, adaptive sampling: a first epoch of uniform samples (as a
 * band), then epochs of LVCL_EPOCH_SPP samples per pixel on average that
 * lvcl_adaptive_plan shares out. Under a time limit an epoch runs only as
 * far as the time measured so far says it fits, in whole samples per pixel,
 * so that --spp of the count reached repeats the image exactly. */
static void *render_adaptive(void *arg)
{
    worker *w = arg;
    pass_state *ps = w->ps;
    const lvcl_pass_settings *set = ps->settings;
    double start = lvcl_seconds();
    size_t n = ps->pixels;
    float *sum = malloc(n * 4 * sizeof *sum), *sum_sq = malloc(n * sizeof *sum_sq);
    uint32_t *list = malloc(n * sizeof *list), rounds[LVCL_EPOCH_MAX_SHARE * LVCL_EPOCH_SPP];
    if (!sum || !sum_sq || !list) {
        w->e = lvcl_fail(&w->st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for adaptive sampling");
        goto done;
    }
    if (bind_shared(w)) goto done;
    int taken = 0;
    double elapsed = 0;
    while (taken < set->spp && taken < LVCL_EPOCH_SPP) {
        if (launch(w, 0, (cl_uint)n)) goto done;
        elapsed = launched(ps, ++taken, set->spp);
        if ((set->time_limit > 0 && elapsed >= set->time_limit) || lvcl_interrupted()) break;
    }
    int last = set->time_limit > 0 && elapsed >= set->time_limit;
    /* A signal stops sampling after the epoch it came in. */
    for (uint32_t epoch = 1; taken < set->spp && !last && !lvcl_interrupted(); epoch++) {
        int spp = set->spp - taken < LVCL_EPOCH_SPP ? set->spp - taken : LVCL_EPOCH_SPP;
        if (set->time_limit > 0) {
            /* An epoch cut short is the last, as a fixed count's is. */
            int fit = (int)floor((set->time_limit - elapsed) / (elapsed / taken));
            if (fit < spp) spp = fit, last = 1;
            if (spp <= 0) break;
        }
        cl_command_queue q = w->pd->device->queue;
        if (move_sums(w, 0, sum, sum_sq)) goto done;
        int count = lvcl_adaptive_plan(sum, sum_sq, ps->camera->width, ps->camera->height, (size_t)spp * n, epoch, list,
                                       rounds);
        if (count < 0) {
            w->e = lvcl_fail(&w->st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for adaptive sampling");
            goto done;
        }
        if (count > 0 &&
            (w->e = lvcl_cl_check(
                 clEnqueueWriteBuffer(q, w->list, CL_TRUE, 0, rounds[0] * sizeof *list, list, 0, NULL, NULL),
                 "uploading the pixel list", &w->st)))
            goto done;
        for (int j = 0; j < count; j++) {
            if (launch(w, 0, rounds[j])) goto done;
            elapsed = launched(ps, taken + spp * (j + 1.0) / count, set->spp);
        }
        taken += spp;
    }
    w->pd->bands = 1;
    adaptive_finished(w, taken, start);
done:
    free(sum);
    free(sum_sq);
    free(list);
    if (w->e) fail_pass(ps);
    return NULL;
}

/* The pixels of `list` that lie in [lo, hi), in list order, into sub, and
 * how many of them each of the `count` rounds takes (round j takes
 * list[0, rounds[j]); rounds do not grow). */
static void band_rounds(const uint32_t *list, const uint32_t *rounds, int count, uint32_t lo, uint32_t hi,
                        uint32_t *sub, uint32_t *sub_rounds)
{
    uint32_t taken = 0, i = 0;
    for (int j = count - 1; j >= 0; j--) {
        for (; i < rounds[j]; i++)
            if (list[i] >= lo && list[i] < hi) sub[taken++] = list[i];
        sub_rounds[j] = taken;
    }
}

/* One epoch's bands on this process: the plan's samples of each band it
 * takes from the cluster's counter, after storing the epoch's starting
 * sums on the device (not for the first); then this process's sums back,
 * +0 in the bands it did not render. */
static lvcl_error epoch_bands(worker *w, uint32_t epoch, const uint32_t *list, const uint32_t *rounds, int count,
                              double done_spp, int spp, float *sum, float *sum_sq, uint32_t *sub, uint8_t *mine)
{
    pass_state *ps = w->ps;
    lvcl_cluster *c = ps->cluster;
    uint32_t sub_rounds[LVCL_EPOCH_MAX_SHARE * LVCL_EPOCH_SPP];
    if (epoch > 0 && move_sums(w, 1, sum, sum_sq)) return w->e;
    memset(mine, 0, (size_t)ps->bands);
    for (;;) {
        uint64_t band;
        if ((w->e = c->take(c, 1, &band, &w->st))) return w->e;
        if (band >= (uint64_t)ps->bands) break;
        size_t lo, hi;
        band_span(ps, band, &lo, &hi);
        band_rounds(list, rounds, count, (uint32_t)lo, (uint32_t)hi, sub, sub_rounds);
        if (count > 0 && sub_rounds[0] > 0 &&
            (w->e = lvcl_cl_check(clEnqueueWriteBuffer(w->pd->device->queue, w->list, CL_TRUE, 0,
                                                       sub_rounds[0] * sizeof *sub, sub, 0, NULL, NULL),
                                  "uploading the pixel list", &w->st)))
            return w->e;
        for (int j = 0; j < count && sub_rounds[j] > 0; j++)
            if (launch(w, 0, sub_rounds[j])) return w->e;
        mine[band] = 1;
        w->pd->bands++;
        launched(ps, done_spp + spp * (band + 1.0) / ps->bands, ps->settings->spp);
    }
    if (move_sums(w, 0, sum, sum_sq)) return w->e;
    for (int b = 0; b < ps->bands; b++) {
        if (mine[b]) continue;
        size_t lo, hi;
        band_span(ps, (size_t)b, &lo, &hi);
        memset(&sum[4 * lo], 0, (hi - lo) * 4 * sizeof *sum);
        memset(&sum_sq[lo], 0, (hi - lo) * sizeof *sum_sq);
    }
    return LVCL_OK;
}

/* Adaptive sampling over a cluster, one device a process: each epoch's
 * plan is made by every process from the same sums, the bands are handed
 * out by the cluster's counter, each band's pixels take their samples of
 * the plan in the plan's order, and the sums of the bands each process
 * rendered (+0 elsewhere) are added into every process's. A pixel thus
 * takes the same samples, added in the same order, as on one device: the
 * image is the one-device image bit for bit. A fixed sample count only
 * (lvcl_session_render refuses time limits over a cluster). Every process
 * meets the others at each epoch's end, failed or not, so that a failure
 * ends all of them there. */
static void *render_adaptive_shared(void *arg)
{
    worker *w = arg;
    pass_state *ps = w->ps;
    lvcl_cluster *c = ps->cluster;
    const lvcl_pass_settings *set = ps->settings;
    size_t n = ps->pixels;
    double start = lvcl_seconds();
    float *sum = calloc(n * 4, sizeof *sum), *sum_sq = calloc(n, sizeof *sum_sq);
    uint32_t *list = malloc(n * sizeof *list), *sub = malloc(n * sizeof *sub);
    uint8_t *mine = malloc((size_t)ps->bands);
    uint32_t rounds[LVCL_EPOCH_MAX_SHARE * LVCL_EPOCH_SPP];
    if (!sum || !sum_sq || !list || !sub || !mine)
        w->e = lvcl_fail(&w->st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for adaptive sampling");
    else bind_shared(w);
    int taken = 0;
    if ((w->e = lvcl_cluster_agree(c, w->e, &w->st))) goto done;
    for (uint32_t epoch = 0; taken < set->spp; epoch++) {
        int spp = set->spp - taken < LVCL_EPOCH_SPP ? set->spp - taken : LVCL_EPOCH_SPP, count;
        if ((w->e = c->restart(c, LVCL_PHASE_IMAGE, &w->st))) goto done;
        if (epoch == 0) { /* uniform: every pixel, once a round */
            for (size_t i = 0; i < n; i++) list[i] = (uint32_t)i;
            for (count = 0; count < spp; count++) rounds[count] = (uint32_t)n;
        } else count = lvcl_adaptive_plan(sum, sum_sq, ps->camera->width, ps->camera->height, (size_t)spp * n,
                                          epoch, list, rounds);
        lvcl_error e = count < 0 ? lvcl_fail(&w->st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for adaptive sampling")
                                 : epoch_bands(w, epoch, list, rounds, count, taken, spp, sum, sum_sq, sub, mine);
        /* A signal on any rank stops every rank after the epoch it came in. */
        uint32_t stop = lvcl_interrupted() != 0;
        if ((w->e = lvcl_cluster_agree(c, e, &w->st)) ||
            (w->e = c->reduce(c, sum, n * 4, LVCL_REDUCE_SUM_F32, &w->st)) ||
            (w->e = c->reduce(c, sum_sq, n, LVCL_REDUCE_SUM_F32, &w->st)) ||
            (w->e = c->reduce(c, &stop, 1, LVCL_REDUCE_MAX_U32, &w->st)))
            goto done;
        taken += spp;
        if (stop) break;
    }
    /* Every process holds the whole image now; the pass reads it from the device. */
    if (move_sums(w, 1, sum, sum_sq)) goto done;
    adaptive_finished(w, taken, start);
done:
    free(sum);
    free(sum_sq);
    free(list);
    free(sub);
    free(mine);
    if (w->e) fail_pass(ps);
    return NULL;
}

lvcl_error lvcl_image_pass_check_size(const lvcl_device *dev, int width, int height, lvcl_status *st)
{
    double pixels = (double)width * (double)height;
    double largest = pixels * 4 * sizeof(float), total = pixels * LVCL_PIXEL_DEVICE_BYTES;
    if (largest <= (double)dev->max_alloc && total <= (double)dev->global_mem) return LVCL_OK;
    char need[32], one[32], all[32];
    return lvcl_fail(st, LVCL_ERR_TOO_LARGE,
                     "a %d x %d image needs %s of device memory (%zu bytes a pixel, %s in its largest buffer), but "
                     "%s allows %s in one buffer; render a smaller image",
                     width, height, lvcl_bytes_text(total, need), (size_t)LVCL_PIXEL_DEVICE_BYTES,
                     lvcl_bytes_text(largest, one), dev->name, lvcl_bytes_text((double)dev->max_alloc, all));
}

/* The worker's image sums (cleared) and its pixel list, every pixel in
 * order (bands launch ranges of it; adaptive epochs overwrite it). */
static lvcl_error create_buffers(worker *w, size_t pixels, lvcl_status *st)
{
    const lvcl_device *dev = w->pd->device;
    cl_int err;
    float zero = 0.0f;
    uint32_t *order = malloc(pixels * sizeof *order);
    if (!order) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the pixel list");
    for (size_t i = 0; i < pixels; i++) order[i] = (uint32_t)i;
    lvcl_error e = LVCL_OK;
    w->sum = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, pixels * 4 * sizeof(float), NULL, &err);
    if (!(e = lvcl_cl_check(err, "allocating the image", st)))
        w->sum_sq = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, pixels * sizeof(float), NULL, &err);
    if (!e && !(e = lvcl_cl_check(err, "allocating the image", st)))
        w->list = lvcl_buffer_create(dev, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, pixels * sizeof *order, order, &err);
    if (!e) e = lvcl_cl_check(err, "allocating the pixel list", st);
    if (!e)
        e = lvcl_cl_check(
            clEnqueueFillBuffer(dev->queue, w->sum, &zero, sizeof zero, 0, pixels * 4 * sizeof(float), 0, NULL, NULL),
            "clearing the image", st);
    if (!e)
        e = lvcl_cl_check(
            clEnqueueFillBuffer(dev->queue, w->sum_sq, &zero, sizeof zero, 0, pixels * sizeof(float), 0, NULL, NULL),
            "clearing the image", st);
    free(order);
    return e;
}

/* Reads each device's sums and takes from each the bands it rendered. */
static lvcl_error gather_image(worker *workers, int n, const pass_state *ps, float *acc, lvcl_render_result *out,
                               lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    for (int d = 0; d < n && !e; d++) {
        e = lvcl_cl_check(clEnqueueReadBuffer(workers[d].pd->device->queue, workers[d].sum, CL_TRUE, 0,
                                              ps->pixels * 4 * sizeof(float), acc, 0, NULL, NULL),
                          "reading the image", st);
        for (int b = 0; !e && b < ps->bands; b++) {
            if (ps->owner[b] != d) continue;
            size_t lo, hi;
            band_span(ps, (size_t)b, &lo, &hi);
            for (size_t i = lo; i < hi; i++) {
                float w = acc[4 * i + 3];
                for (int c = 0; c < 3; c++) out->rgb[3 * i + c] = w > 0 ? acc[4 * i + c] / w : 0.0f;
            }
        }
    }
    return e;
}

/* With a cluster: the shared band counter restarted, and the devices of
 * every process counted (so every process cuts the same bands). */
static lvcl_error share_bands(lvcl_cluster *cluster, int n, uint32_t *devices, lvcl_status *st)
{
    *devices = (uint32_t)n;
    if (!cluster) return LVCL_OK;
    lvcl_error e = cluster->restart(cluster, LVCL_PHASE_IMAGE, st);
    return e ? e : cluster->reduce(cluster, devices, 1, LVCL_REDUCE_SUM_U32, st);
}

/* With a cluster: each process's pixels (+0 where another rendered them)
 * and its fewest samples made every process's; 0 samples where a signal
 * left bands that no process rendered. */
static lvcl_error share_image(lvcl_cluster *cluster, const pass_state *ps, lvcl_render_result *out, lvcl_status *st)
{
    int32_t samples = out->samples;
    uint32_t rendered = 0;
    for (int b = 0; b < ps->bands; b++) rendered += ps->owner[b] >= 0;
    lvcl_error e = cluster->reduce(cluster, out->rgb, ps->pixels * 3, LVCL_REDUCE_SUM_F32, st);
    if (!e) e = cluster->reduce(cluster, &samples, 1, LVCL_REDUCE_MIN_I32, st);
    if (!e) e = cluster->reduce(cluster, &rendered, 1, LVCL_REDUCE_SUM_U32, st);
    out->samples = rendered < (uint32_t)ps->bands ? 0 : samples;
    return e;
}

lvcl_error lvcl_image_pass(lvcl_pass_device *devices, int n, const lv_camera *camera, lvcl_cluster *cluster,
                           const lvcl_pass_settings *settings, lvcl_render_result *out, lvcl_status *st)
{
    memset(out, 0, sizeof *out);
    pass_state ps = {.camera = camera, .settings = settings, .samples = settings->spp};
    ps.cluster = lvcl_cluster_shared(cluster) ? cluster : NULL;
    uint32_t all_devices;
    lvcl_error e = share_bands(ps.cluster, n, &all_devices, st);
    if (e) return e;
    ps.pixels = (size_t)camera->width * camera->height;
    ps.bands = all_devices == 1 ? 1 : (int)all_devices * BANDS_PER_DEVICE;
    if ((size_t)ps.bands > camera->height) ps.bands = (int)camera->height;
    size_t rows = (camera->height + (size_t)ps.bands - 1) / (size_t)ps.bands;
    ps.band_pixels = rows * camera->width;
    ps.bands = (int)((ps.pixels + ps.band_pixels - 1) / ps.band_pixels);
    ps.launches_total = (long)ps.bands * settings->spp;
    ps.owner = calloc((size_t)ps.bands, sizeof *ps.owner);
    worker *workers = calloc((size_t)n, sizeof *workers);
    if (!ps.owner || !workers) {
        free(ps.owner);
        free(workers);
        return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the pass");
    }
    pthread_mutex_init(&ps.lock, NULL);

    for (int b = 0; b < ps.bands; b++) ps.owner[b] = -1;
    /* The host's copy of the sums and the image, taken before any work so
     * that a shortage cannot lose the render; pixels no band of this
     * process reached stay +0 (black). */
    float *acc = malloc(ps.pixels * 4 * sizeof(float));
    out->rgb = calloc(ps.pixels * 3, sizeof(float));
    char need[32];
    if (!acc || !out->rgb)
        e = lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the image (%s)",
                      lvcl_bytes_text((double)ps.pixels * 7 * sizeof(float), need));
    for (int d = 0; d < n && !e; d++) {
        workers[d] = (worker){.ps = &ps, .pd = &devices[d], .index = d};
        devices[d].bands = 0;
        devices[d].pixels = 0;
        devices[d].busy_seconds = 0;
        e = create_buffers(&workers[d], ps.pixels, st);
    }
    /* Adaptive sampling needs the whole image on one device (of each
     * process, over a cluster), and epochs to share. */
    int one_each = all_devices == 1 || (ps.cluster && all_devices == (uint32_t)ps.cluster->size);
    int adaptive = one_each && settings->adaptive && (settings->spp > LVCL_EPOCH_SPP || settings->time_limit > 0);
    ps.unit = all_devices == 1 || adaptive ? "spp" : "band samples";
    if (!e) {
        lvcl_progress_start(&ps.bar, "render", settings->progress);
        ps.start = lvcl_seconds();
        lvcl_status thread_st = {0};
        void *(*render)(void *) = !adaptive ? render_bands : ps.cluster ? render_adaptive_shared : render_adaptive;
        lvcl_error threads_failed = lvcl_run_parallel(render, workers, sizeof workers[0], n, &thread_st);
        lvcl_progress_finish(&ps.bar);
        out->render_seconds = lvcl_seconds() - ps.start;
        out->first_launch_seconds = ps.first_launch_seconds;
        out->samples = ps.samples;
        out->adaptive = adaptive;
        for (int d = 0; d < n && !e; d++)
            if (workers[d].e) {
                *st = workers[d].st;
                e = workers[d].e;
            }
        if (!e && threads_failed) {
            *st = thread_st;
            e = threads_failed;
        }
        if (!e) e = gather_image(workers, n, &ps, acc, out, st);
    }
    /* A process whose pass failed still meets the others here; after
     * adaptive sampling each holds the whole image already. */
    if (ps.cluster && !(e = lvcl_cluster_agree(ps.cluster, e, st)) && !adaptive)
        e = share_image(ps.cluster, &ps, out, st);
    if (!e) {
        out->width = (int)camera->width;
        out->height = (int)camera->height;
    } else {
        free(out->rgb);
        out->rgb = NULL;
    }
    for (int d = 0; d < n; d++) {
        if (workers[d].sum) clReleaseMemObject(workers[d].sum);
        if (workers[d].sum_sq) clReleaseMemObject(workers[d].sum_sq);
        if (workers[d].list) clReleaseMemObject(workers[d].list);
    }
    pthread_mutex_destroy(&ps.lock);
    free(acc);
    free(ps.owner);
    free(workers);
    return e;
}
