/* The light volume of a session over every device: each device takes
 * batches of particles until none is left (a faster device takes more),
 * then the tallies are added and stored on each, and each computes its lit
 * volumes. With a cluster the batches come from a counter every process
 * shares, and each process's sum is added to the others'. */
#include <string.h>

#include "session_internal.h"
#include "../util/parallel.h"
#include "../util/timer.h"

typedef struct {
    session_device *sd;
    lvcl_volume_settings vs;
    lvcl_error e;
    lvcl_status st;
} trace_job;

static void *trace_part(void *arg)
{
    trace_job *j = arg;
    session_device *sd = j->sd;
    j->e = lvcl_volume_trace(sd->volume, &sd->program, &sd->device_scene, &j->vs, &j->st);
    return NULL;
}

lvcl_error lvcl_session_new_volume(lvcl_session *s, int d, const lvcl_volume_settings *settings, lvcl_status *st)
{
    session_device *sd = &s->devices[d];
    lvcl_volume_release(sd->volume);
    sd->volume = NULL;
    return lvcl_volume_create(&sd->device, &s->packed, settings, &sd->volume, st);
}

/* Traces the particles [first, end) over every device (a faster device
 * takes more batches) and, on several and if `add`, adds their volumes;
 * with a cluster, over every process's devices, adding every process's
 * volume. (Each volume holds its own particles until they are added, so
 * passes may run before one addition.) */
static lvcl_error trace_devices(lvcl_session *s, const lvcl_volume_settings *settings, uint64_t first, uint64_t end,
                                int add, lvcl_status *st)
{
    int n = s->device_count, shared = lvcl_cluster_shared(s->cluster);
    lvcl_error e = shared ? s->cluster->restart(s->cluster, LVCL_PHASE_PARTICLES, st) : LVCL_OK;
    if (e) return e;
    trace_job jobs[LVCL_MAX_DEVICES];
    lvcl_particle_source source;
    lvcl_particle_source_init(&source, first, end, s->cluster);
    for (int d = 0; d < n; d++) {
        jobs[d] = (trace_job){.sd = &s->devices[d], .vs = *settings};
        jobs[d].vs.first_particle = first;
        jobs[d].vs.particles = end;
        jobs[d].vs.source = n > 1 || shared ? &source : NULL;
        jobs[d].vs.progress = settings->progress && d == 0;
    }
    e = lvcl_run_parallel(trace_part, jobs, sizeof jobs[0], n, st);
    for (int d = 0; d < n && !e; d++)
        if (jobs[d].e) {
            *st = jobs[d].st;
            e = jobs[d].e;
        }
    if (!e && source.e) {
        *st = source.st;
        e = source.e;
    }
    lvcl_particle_source_destroy(&source);
    if (!add) return shared ? lvcl_cluster_agree(s->cluster, e, st) : e;
    lvcl_light_volume *vols[LVCL_MAX_DEVICES];
    for (int d = 0; d < n; d++) vols[d] = s->devices[d].volume;
    double t = lvcl_seconds();
    if (!e && n > 1) e = lvcl_volume_merge(vols, n, st);
    /* A process whose trace failed still meets the others here. */
    if (shared && !(e = lvcl_cluster_agree(s->cluster, e, st))) e = lvcl_volume_reduce(vols, n, s->cluster, st);
    s->merge_seconds += lvcl_seconds() - t;
    return e;
}

lvcl_error lvcl_session_trace_volume(lvcl_session *s, const lvcl_volume_settings *settings, lvcl_status *st)
{
    lvcl_error e = LVCL_OK;
    int n = s->device_count;
    for (int d = 0; d < n && !e; d++) e = lvcl_session_new_volume(s, d, settings, st);
    if ((e = lvcl_cluster_agree(s->cluster, e, st))) return e;
    s->merge_seconds = 0;
    if ((e = lvcl_session_view_start(s, settings->view_odds, st))) return e;
    uint64_t split_at = lvcl_volume_split_point(settings), first_part = lvcl_session_first_part(s, settings);
    if (split_at > 0) {
        /* Refined cells: every device holds the same tallies after the
         * merge, so each splits the same cells; all but the first (of
         * rank 0) then empty theirs, so that the next merge counts them once. */
        if ((e = trace_devices(s, settings, 0, split_at, 1, st))) return e;
        for (int d = 0; d < n && !e; d++)
            e = lvcl_volume_refine(s->devices[d].volume, (double)settings->particles, settings, st);
        int keeper = s->cluster && s->cluster->rank > 0 ? -1 : 0;
        for (int d = 0; d < n && !e; d++)
            if (d != keeper) e = lvcl_volume_empty(s->devices[d].volume, st);
        if ((e = lvcl_cluster_agree(s->cluster, e, st))) return e;
        /* The refined slots restarted: the particles before the split,
         * again, into them alone (added with the rest below). */
        lvcl_volume_settings retrace = *settings;
        retrace.restarted_only = 1;
        if ((e = trace_devices(s, &retrace, 0, split_at, 0, st))) return e;
    } else if (first_part > 0 && (e = trace_devices(s, settings, 0, first_part, 0, st))) {
        return e;
    }
    /* The particles from here on leave the lights by the view's odds (the
     * retrace above walked its particles with the odds they first had). */
    if ((e = lvcl_session_view_decide(s, settings->store_emitted, st))) return e;
    e = trace_devices(s, settings, first_part, settings->particles, 1, st);
    if (!e) e = lvcl_session_view_gather(s, st);
    /* Every device holds the same tallies now, so each merges the same blocks. */
    for (int d = 0; d < n && !e; d++)
        e = lvcl_volume_adapt(s->devices[d].volume, (double)settings->particles, settings->merge_tolerance, st);
    for (int d = 0; d < n && !e; d++) e = lvcl_volume_finish(s->devices[d].volume, &s->devices[d].program, st);
    return e == LVCL_ERR_CLUSTER ? e : lvcl_cluster_agree(s->cluster, e, st);
}
