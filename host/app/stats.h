/* --stats: what a run did and how long each part took, as JSON. */
#ifndef LVCL_STATS_H
#define LVCL_STATS_H

#include "options.h"
#include "../render/session.h"

/* One process's share of a distributed render (lvcl-mpi), gathered to rank 0. */
typedef struct {
    char host[64];
    int devices;
    uint64_t particles, segments;
    double particle_trace_seconds;
    int bands;
    uint64_t pixels;
    double render_busy_seconds;
    double comm_seconds[LVCL_PHASE_COUNT]; /* setup, particles, image: time in MPI calls, waits included */
    double reduce_seconds[LVCL_PHASE_COUNT]; /* of which adding volumes or images */
    uint64_t comm_bytes[LVCL_PHASE_COUNT];
    int interrupted_by; /* the signal that stopped its sampling early, or 0 */
} lvcl_rank_share;

typedef struct {
    const lvcl_options *options;
    const lvcl_rank_share *ranks; /* every rank's share, in rank order; NULL when alone */
    int rank_count;
    const lvcl_session *session;
    const lvcl_render_result *result;
    double process_start;
    double scene_load_seconds;
    double startup_seconds; /* process start to the first kernel launch */
    int interrupted_by;     /* the signal that stopped sampling early, or 0 */
} lvcl_stats;

lvcl_error lvcl_stats_write(const char *path, const lvcl_stats *s, lvcl_status *st);

#endif
