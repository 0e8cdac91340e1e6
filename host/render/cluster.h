/* Processes that render one frame together (lvcl-mpi, host/mpi/): what the
 * session asks of them at the points where they must agree. The session
 * calls these on every process in the same order; a NULL cluster, or one
 * of one process, is a render alone. The render layer knows nothing of MPI:
 * lvcl-mpi fills in the operations, and build/lvcl keeps no MPI dependency.
 *
 * Everything that crosses processes is chosen so that the result does not
 * depend on which process did what: integer tallies add exactly in any
 * order, masks OR, lit points take the largest, and each image pixel comes
 * from the one process that rendered it (docs/distributed.md). */
#ifndef LVCL_CLUSTER_H
#define LVCL_CLUSTER_H

#include <stddef.h>
#include <stdint.h>

#include "../util/status.h"

/* Element-wise reductions; every process gets the result. */
typedef enum {
    LVCL_REDUCE_SUM_I64,
    LVCL_REDUCE_SUM_U64,
    LVCL_REDUCE_SUM_U32,
    LVCL_REDUCE_OR_U32,
    LVCL_REDUCE_MAX_U32,
    LVCL_REDUCE_MIN_I32,
    LVCL_REDUCE_SUM_F32 /* exact only where one process holds a value and the others +0 */
} lvcl_reduce_op;

/* The phases whose communication is counted apart (the comm_* counters below). */
typedef enum { LVCL_PHASE_SETUP, LVCL_PHASE_PARTICLES, LVCL_PHASE_IMAGE, LVCL_PHASE_COUNT } lvcl_cluster_phase;

typedef struct lvcl_cluster lvcl_cluster;
struct lvcl_cluster {
    int rank, size;
    void *impl;                /* the implementation's own state */
    lvcl_cluster_phase phase;  /* where communication is counted now (restart sets it) */
    double comm_seconds[LVCL_PHASE_COUNT];   /* time in this process's calls below, per phase (waits included) */
    double reduce_seconds[LVCL_PHASE_COUNT]; /* of which in reduce */
    uint64_t comm_bytes[LVCL_PHASE_COUNT];   /* bytes it sent in them, per phase */
    int agreed_failure;        /* the last lvcl_cluster_agree returned an error every process has */
    /* Collective: the shared work counter back to 0, its takes counted in `phase`. */
    lvcl_error (*restart)(lvcl_cluster *c, lvcl_cluster_phase phase, lvcl_status *st);
    /* The next `count` items of the shared counter: *first is where they
     * start (past the end when the work is done). Any thread may call it;
     * processes that finish early take more. */
    lvcl_error (*take)(lvcl_cluster *c, uint64_t count, uint64_t *first, lvcl_status *st);
    /* Collective: data (count elements) reduced over every process, in place. */
    lvcl_error (*reduce)(lvcl_cluster *c, void *data, size_t count, lvcl_reduce_op op, lvcl_status *st);
    /* Collective: every process's `bytes` bytes at `mine`, in rank order into `all`. */
    lvcl_error (*gather)(lvcl_cluster *c, const void *mine, size_t bytes, void *all, lvcl_status *st);
    /* Ends every process at once with `status`: for a failure the others
     * cannot learn of because they wait in a collective this process will
     * not reach. */
    void (*abort)(lvcl_cluster *c, int status);
};

/* Whether a render is shared with other processes. */
static inline int lvcl_cluster_shared(const lvcl_cluster *c)
{
    return c && c->size > 1;
}

/* Collective: makes every process fail alike when any failed. `e` and `st`
 * are this process's outcome; on return they are the lowest failing
 * rank's, its message prefixed with the rank where the processes
 * disagreed (one failed where another did not), so that an error every
 * process meets (bad input) is reported as itself, and one that only
 * some meet (a device that would not open) names where. */
lvcl_error lvcl_cluster_agree(lvcl_cluster *c, lvcl_error e, lvcl_status *st);

#endif
