/* The particle trace into a light volume (paper section 4.1): the bins'
 * directions, the batches of particles launched (shared between devices),
 * and the lit volumes computed once the trace is done. */
#include <stdlib.h>
#include <string.h>

#include "light_volume_internal.h"
#include "../util/interrupt.h"
#include "../util/progress.h"
#include "../util/timer.h"

/* Particles per launch: big enough to keep a device busy, small enough for
 * progress and for --time-limit to be checked often. */
#define BATCH (1u << 18)
/* Over a cluster, smaller: ranks share the particles evenly at 10^6 (at
 * 2^18, four batches left one rank of three with twice the others' work). */
#define CLUSTER_BATCH (1u << 16)

/* Runs lv_bin_table: the directions of n x n bins per hemisphere, for the
 * integrating gather. */
static lvcl_error fill_bin_table(lvcl_light_volume *vol, const lvcl_program *prog, uint32_t n, cl_mem table,
                                 lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    cl_kernel k;
    lvcl_error e = lvcl_kernel_create(prog, "lv_bin_table", &k, st);
    if (e) return e;
    lvcl_bin_table_args args = {.n = n, .table = table};
    if (!(e = lvcl_bind_lv_bin_table(k, &args, st)))
        e = lvcl_kernel_enqueue(dev, k, (size_t)LV_BIN_GROUPS(2 * n * n) * LV_BIN_GROUP, "computing the bin table", st);
    clReleaseKernel(k);
    return e;
}

/* The table of the fine bins, once slots have them: the trace reads it
 * for concentrated light, the gather for every bin. */
static lvcl_error make_fine_bin_table(lvcl_light_volume *vol, const lvcl_program *prog, lvcl_status *st)
{
    if (!vol->fine_slots || vol->fine_bin_table_buf) return LVCL_OK;
    uint32_t n = 2 * vol->buf.info.dirs;
    cl_int err;
    vol->fine_bin_table_buf = lvcl_buffer_create(vol->dev, CL_MEM_READ_WRITE,
                                                 (size_t)LV_BIN_TABLE_FLOATS(2 * n * n) * sizeof(float), NULL, &err);
    lvcl_error e = lvcl_cl_check(err, "allocating the fine bins' table", st);
    if (!e) e = fill_bin_table(vol, prog, n, vol->fine_bin_table_buf, st);
    if (e && vol->fine_bin_table_buf) { /* a later call makes it afresh */
        clReleaseMemObject(vol->fine_bin_table_buf);
        vol->fine_bin_table_buf = NULL;
    }
    return e;
}

lvcl_error lvcl_volume_finish(lvcl_light_volume *vol, const lvcl_program *prog, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    cl_kernel k;
    lvcl_error e;
    if ((e = make_fine_bin_table(vol, prog, st))) return e;
    vol->axis_sums_current = 0;
    e = lvcl_kernel_create(prog, "lv_lit_volumes", &k, st);
    if (e) return e;
    lvcl_lit_volumes_args args = {.volume = &vol->buf};
    if (!(e = lvcl_bind_lv_lit_volumes(k, &args, st)) &&
        !(e = lvcl_kernel_enqueue(dev, k, vol->buf.info.slot_count, "computing the lit volumes", st)))
        e = lvcl_cl_check(clFinish(dev->queue), "computing the lit volumes", st);
    clReleaseKernel(k);
    if (!e) e = lvcl_volume_share_lit(vol, st);
    return e ? e : lvcl_volume_scale_split(vol, st);
}

void lvcl_particle_source_init(lvcl_particle_source *src, uint64_t first, uint64_t end, lvcl_cluster *cluster)
{
    pthread_mutex_init(&src->lock, NULL);
    src->next = first;
    src->end = end;
    src->cluster = lvcl_cluster_shared(cluster) ? cluster : NULL;
    src->e = LVCL_OK;
}

void lvcl_particle_source_destroy(lvcl_particle_source *src)
{
    pthread_mutex_destroy(&src->lock);
}

/* The next batch of particle indices: from the cluster's counter or the
 * shared source, or else the next slice of the settings' range (cursor).
 * Returns 0 when none is left or the deadline has passed, or a signal asked
 * lvcl to stop, or the cluster failed (src->e says so). */
static int next_batch(const lvcl_volume_settings *s, uint64_t *cursor, uint64_t *first, cl_uint *count)
{
    /* A retrace runs whole: the restarted slots must get every particle back. */
    if (!s->restarted_only && ((s->deadline > 0 && lvcl_seconds() >= s->deadline) || lvcl_interrupted())) return 0;
    uint64_t end = s->particles;
    lvcl_particle_source *src = s->source;
    if (src) {
        pthread_mutex_lock(&src->lock);
        cursor = &src->next;
        end = src->end;
    }
    if (src && src->cluster) {
        /* The counter numbers batches from the source's first particle on. */
        uint64_t taken = 0;
        if (!src->e) src->e = src->cluster->take(src->cluster, CLUSTER_BATCH, &taken, &src->st);
        *first = src->e ? end : src->next + taken;
        *count = (cl_uint)(*first >= end ? 0 : end - *first < CLUSTER_BATCH ? end - *first : CLUSTER_BATCH);
    } else {
        *first = *cursor;
        *count = (cl_uint)(end - *cursor < BATCH ? end - *cursor : BATCH);
        *cursor += *count;
    }
    if (src) pthread_mutex_unlock(&src->lock);
    return *count > 0;
}

lvcl_error lvcl_volume_empty(lvcl_light_volume *vol, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    lvcl_error e = LVCL_OK;
    cl_long zero = 0;
    for (int i = 0; i < vol->tally_parts && !e; i++)
        e = lvcl_cl_check(clEnqueueFillBuffer(dev->queue, vol->buf.tallies[i], &zero, sizeof zero, 0,
                                              lvcl_volume_part_bytes(vol, i), 0, NULL, NULL),
                          "clearing the light volume", st);
    cl_uint none = 0;
    size_t bytes[3];
    lvcl_volume_record_sections(vol, bytes);
    cl_mem records[3];
    lvcl_volume_record_buffers(vol, records);
    for (int i = 0; i < 3 && !e; i++)
        if (bytes[i])
            e = lvcl_cl_check(
                clEnqueueFillBuffer(dev->queue, records[i], &none, sizeof none, 0, bytes[i], 0, NULL, NULL),
                "clearing the subcells", st);
    return e;
}

/* Zeroes the view probe's sums. */
static lvcl_error clear_view_probe(lvcl_light_volume *vol, lvcl_status *st)
{
    cl_long zero = 0;
    return lvcl_cl_check(clEnqueueFillBuffer(vol->dev->queue, vol->view_light_buf, &zero, sizeof zero, 0,
                                             lvcl_volume_view_sums(vol) * sizeof zero, 0, NULL, NULL),
                         "clearing the view probe", st);
}

/* Empties the volume, its counters and view probe too, and fills the bins' directions. */
static lvcl_error clear_volume(lvcl_light_volume *vol, const lvcl_program *prog, lvcl_status *st)
{
    lvcl_error e;
    if ((e = fill_bin_table(vol, prog, vol->buf.info.dirs, vol->bin_table_buf, st)) || (e = lvcl_volume_empty(vol, st)))
        return e;
    if (vol->view_light_buf && (e = clear_view_probe(vol, st))) return e;
    vol->segments = vol->visibility_rays = vol->particles = 0;
    vol->trace_seconds = 0;
    vol->buf.info.particles = 0;
    vol->split_from = 0; /* split cells, if any, hold every particle from here on */
    return LVCL_OK;
}

lvcl_error lvcl_volume_view_probe(lvcl_light_volume *vol, const uint32_t *seen, size_t count, size_t groups,
                                  lvcl_status *st)
{
    if (vol->view_slots_buf) clReleaseMemObject(vol->view_slots_buf);
    if (vol->view_light_buf) clReleaseMemObject(vol->view_light_buf);
    vol->view_slots_buf = vol->view_light_buf = NULL;
    vol->view_seen = vol->view_groups = 0;
    if (!seen || !count || !groups) return LVCL_OK;
    cl_int err, err2;
    size_t sums = count * groups * 2;
    vol->view_slots_buf =
        lvcl_buffer_create(vol->dev, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR,
                           ((size_t)vol->buf.info.slot_count + 1) * sizeof(cl_uint), (void *)seen, &err);
    vol->view_light_buf = lvcl_buffer_create(vol->dev, CL_MEM_READ_WRITE, sums * sizeof(cl_long), NULL, &err2);
    lvcl_error e = lvcl_cl_check(err != CL_SUCCESS ? err : err2, "allocating the view probe", st);
    vol->view_seen = count;
    vol->view_groups = groups;
    if (!e) e = clear_view_probe(vol, st);
    if (e) lvcl_volume_view_probe(vol, NULL, 0, 0, NULL);
    return e;
}

int lvcl_volume_view_probing(const lvcl_light_volume *vol)
{
    return vol->view_slots_buf != NULL;
}

size_t lvcl_volume_view_sums(const lvcl_light_volume *vol)
{
    return vol->view_seen * vol->view_groups * 2;
}

lvcl_error lvcl_volume_view_light(const lvcl_light_volume *vol, int64_t *units, lvcl_status *st)
{
    if (!vol->view_light_buf) return LVCL_OK;
    return lvcl_cl_check(clEnqueueReadBuffer(vol->dev->queue, vol->view_light_buf, CL_TRUE, 0,
                                             lvcl_volume_view_sums(vol) * sizeof(cl_long), units, 0, NULL, NULL),
                         "reading the view probe", st);
}

/* Copies every slot's subcell marks into `seen`, which the next batch
 * reads to skip marks already made. */
static lvcl_error snapshot_masks(const lvcl_light_volume *vol, cl_mem seen, lvcl_status *st)
{
    if (!vol->buf.info.subcells) return LVCL_OK;
    size_t bytes = ((size_t)vol->buf.info.slot_count + 1) * LV_MARK_WORDS * sizeof(cl_uint);
    return lvcl_cl_check(clEnqueueCopyBuffer(vol->dev->queue, vol->buf.subcell_marks, seen, 0, 0, bytes, 0, NULL, NULL),
                         "copying the subcell masks", st);
}

lvcl_error lvcl_volume_trace(lvcl_light_volume *vol, const lvcl_program *prog, const lvcl_device_scene *ds,
                             const lvcl_volume_settings *s, lvcl_status *st)
{
    const lvcl_device *dev = vol->dev;
    lvcl_error e;
    if (s->particles == 0 || s->particles > UINT32_MAX)
        return lvcl_fail(st, LVCL_ERR_USAGE, "--particles must be from 1 to %u", UINT32_MAX);
    if (s->first_particle >= s->particles)
        return lvcl_fail(st, LVCL_ERR_USAGE, "no particles to trace from %llu to %llu",
                         (unsigned long long)s->first_particle, (unsigned long long)s->particles);
    /* A pass adds to the volume: it must leave out what the first did. */
    if ((s->first_particle > 0 || s->restarted_only) && !s->see_through != !vol->see_through)
        return lvcl_fail(st, LVCL_ERR_USAGE, "a pass of the light volume cannot change whether it sees through glass");
    if (s->restarted_only && vol->split_from == 0) return LVCL_OK; /* nothing restarted, or retraced already */
    if (s->restarted_only && !(s->particles <= vol->split_from))
        return lvcl_fail(st, LVCL_ERR_USAGE, "a retrace covers the particles before the volume was refined, %.0f",
                         vol->split_from);
    if ((s->first_particle == 0 && !s->restarted_only && (e = clear_volume(vol, prog, st))) ||
        (e = make_fine_bin_table(vol, prog, st)))
        return e;
    vol->see_through = s->see_through != 0;
    cl_int err;
    /* Per batch: segments traced, visibility rays cast. */
    cl_mem counter = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, 2 * sizeof(cl_uint), NULL, &err);
    if ((e = lvcl_cl_check(err, "allocating the ray counters", st))) return e;
    size_t seen_bytes =
        vol->buf.info.subcells ? ((size_t)vol->buf.info.slot_count + 1) * LV_MARK_WORDS * sizeof(cl_uint) : 8;
    cl_mem seen = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, seen_bytes, NULL, &err);
    if ((e = lvcl_cl_check(err, "allocating the copy of the subcell masks", st))) {
        clReleaseMemObject(counter);
        return e;
    }
    /* Without a view probe the kernel gets a buffer it does not read. */
    int probe = vol->view_slots_buf && !s->restarted_only;
    cl_mem unused = NULL;
    if (!probe) unused = lvcl_buffer_create(dev, CL_MEM_READ_WRITE, 8, NULL, &err);
    if (!probe && (e = lvcl_cl_check(err, "allocating the view probe's stand-in", st))) {
        clReleaseMemObject(seen);
        clReleaseMemObject(counter);
        return e;
    }
    cl_kernel k = NULL;
    lvcl_particle_trace_args args = {.scene = &ds->buffers,
                                     .volume = &vol->buf,
                                     .store_emitted = s->store_emitted ? 1u : 0u,
                                     .see_through = s->see_through ? 1u : 0u,
                                     .restarted_only = s->restarted_only ? 1u : 0u,
                                     .subcells_seen = seen,
                                     .bin_table = lvcl_volume_bin_table(vol),
                                     .fine_bin_table = lvcl_volume_fine_bin_table(vol),
                                     .view_groups = probe ? (cl_uint)vol->view_groups : 0u,
                                     .view_slots = probe ? vol->view_slots_buf : unused,
                                     .view_light = probe ? vol->view_light_buf : unused,
                                     .ray_counts = counter};
    if ((e = lvcl_kernel_create(prog, "lv_particle_trace", &k, st)) ||
        (e = lvcl_bind_lv_particle_trace(k, &args, st))) {
        if (k) clReleaseKernel(k);
        if (unused) clReleaseMemObject(unused);
        clReleaseMemObject(seen);
        clReleaseMemObject(counter);
        return e;
    }
    lvcl_progress bar;
    lvcl_progress_start(&bar, s->restarted_only ? "retrace" : "particles", s->progress);
    double start = lvcl_seconds();
    uint64_t cursor = s->first_particle, first;
    cl_uint count;
    while (next_batch(s, &cursor, &first, &count)) {
        /* 32-bit counts per batch cannot overflow; the totals are 64-bit. */
        cl_uint counts[2] = {0, 0};
        cl_uint f = (cl_uint)first;
        if ((e = lvcl_kernel_arg(k, LV_ARG(lv_particle_trace, first), sizeof f, &f, "the batch's first particle",
                                 st)) ||
            (e = lvcl_kernel_arg(k, LV_ARG(lv_particle_trace, count), sizeof count, &count, "the batch's size", st)) ||
            (e = lvcl_cl_check(
                 clEnqueueWriteBuffer(dev->queue, counter, CL_FALSE, 0, sizeof counts, counts, 0, NULL, NULL),
                 "clearing the ray counters", st)) ||
            (e = snapshot_masks(vol, seen, st)) ||
            (e = lvcl_kernel_enqueue(dev, k, count, "launching the particle trace", st)) ||
            (e = lvcl_cl_check(
                 clEnqueueReadBuffer(dev->queue, counter, CL_TRUE, 0, sizeof counts, counts, 0, NULL, NULL),
                 "running the particle trace", st)))
            break;
        if (!s->restarted_only) { /* a retrace adds no particles */
            vol->segments += counts[0];
            vol->visibility_rays += counts[1];
            vol->particles += count;
            vol->buf.info.particles = (float)vol->particles;
        }
        lvcl_progress_update(&bar, (double)(first + count), (double)s->particles, "particles");
    }
    lvcl_progress_finish(&bar);
    clReleaseKernel(k);
    if (unused) clReleaseMemObject(unused);
    clReleaseMemObject(seen);
    clReleaseMemObject(counter);
    vol->trace_seconds += lvcl_seconds() - start;
    if (!e && s->restarted_only) vol->split_from = 0; /* the restarted slots hold every particle again */
    return e;
}
