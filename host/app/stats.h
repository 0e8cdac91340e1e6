/* --stats: what a run did and how long each part took, as JSON. */
#ifndef LVCL_STATS_H
#define LVCL_STATS_H

#include "options.h"
#include "../render/session.h"

typedef struct {
    const lvcl_options *options;
    const lvcl_session *session;
    const lvcl_render_result *result;
    double process_start;
    double scene_load_seconds;
    double startup_seconds; /* process start to the first kernel launch */
    int interrupted_by;     /* the signal that stopped sampling early, or 0 */
} lvcl_stats;

lvcl_error lvcl_stats_write(const char *path, const lvcl_stats *s, lvcl_status *st);

#endif
