#include "cluster_mpi.h"

#include <limits.h>
#include <stdlib.h>

#include "../util/timer.h"

typedef struct {
    MPI_Comm comm;
    MPI_Win counter_win;
    uint64_t *counter; /* rank 0's; NULL elsewhere */
} mpi_cluster;

/* Reductions are sent in pieces of at most this many elements (MPI counts are ints). */
#define REDUCE_PIECE (1u << 26)

static lvcl_error mpi_check(int rc, const char *call, lvcl_status *st)
{
    if (rc == MPI_SUCCESS) return LVCL_OK;
    char text[MPI_MAX_ERROR_STRING];
    int len = 0;
    MPI_Error_string(rc, text, &len);
    return lvcl_fail(st, LVCL_ERR_CLUSTER, "%s failed: %.*s", call, len, text);
}

/* Counts the time and bytes of one call in the current phase. */
static void count(lvcl_cluster *c, double since, uint64_t bytes)
{
    c->comm_seconds[c->phase] += lvcl_seconds() - since;
    c->comm_bytes[c->phase] += bytes;
}

static lvcl_error mpi_restart(lvcl_cluster *c, lvcl_cluster_phase phase, lvcl_status *st)
{
    mpi_cluster *m = c->impl;
    double t = lvcl_seconds();
    c->phase = phase;
    /* Every rank is past the last phase's takes before the counter is
     * reset, and the reset is done before anyone takes again. */
    uint64_t zero = 0;
    int rc = MPI_Barrier(m->comm);
    if (rc == MPI_SUCCESS && c->rank == 0) {
        rc = MPI_Accumulate(&zero, 1, MPI_UINT64_T, 0, 0, 1, MPI_UINT64_T, MPI_REPLACE, m->counter_win);
        if (rc == MPI_SUCCESS) rc = MPI_Win_flush(0, m->counter_win);
    }
    if (rc == MPI_SUCCESS) rc = MPI_Barrier(m->comm);
    count(c, t, 0);
    return mpi_check(rc, "restarting the shared work counter (MPI_Barrier, MPI_Accumulate)", st);
}

static lvcl_error mpi_take(lvcl_cluster *c, uint64_t n, uint64_t *first, lvcl_status *st)
{
    mpi_cluster *m = c->impl;
    double t = lvcl_seconds();
    int rc = MPI_Fetch_and_op(&n, first, MPI_UINT64_T, 0, 0, MPI_SUM, m->counter_win);
    if (rc == MPI_SUCCESS) rc = MPI_Win_flush(0, m->counter_win);
    count(c, t, sizeof n);
    return mpi_check(rc, "taking work from the shared counter (MPI_Fetch_and_op)", st);
}

static lvcl_error mpi_reduce(lvcl_cluster *c, void *data, size_t n, lvcl_reduce_op op, lvcl_status *st)
{
    MPI_Datatype type;
    MPI_Op mop;
    size_t size;
    switch (op) {
    case LVCL_REDUCE_SUM_I64: type = MPI_INT64_T, mop = MPI_SUM, size = 8; break;
    case LVCL_REDUCE_SUM_U64: type = MPI_UINT64_T, mop = MPI_SUM, size = 8; break;
    case LVCL_REDUCE_SUM_U32: type = MPI_UINT32_T, mop = MPI_SUM, size = 4; break;
    case LVCL_REDUCE_OR_U32: type = MPI_UINT32_T, mop = MPI_BOR, size = 4; break;
    case LVCL_REDUCE_MAX_U32: type = MPI_UINT32_T, mop = MPI_MAX, size = 4; break;
    case LVCL_REDUCE_MIN_I32: type = MPI_INT32_T, mop = MPI_MIN, size = 4; break;
    default: type = MPI_FLOAT, mop = MPI_SUM, size = 4; break;
    }
    mpi_cluster *m = c->impl;
    double t = lvcl_seconds();
    int rc = MPI_SUCCESS;
    for (size_t done = 0; done < n && rc == MPI_SUCCESS; done += REDUCE_PIECE) {
        size_t piece = n - done < REDUCE_PIECE ? n - done : REDUCE_PIECE;
        rc = MPI_Allreduce(MPI_IN_PLACE, (char *)data + done * size, (int)piece, type, mop, m->comm);
    }
    c->reduce_seconds[c->phase] += lvcl_seconds() - t;
    count(c, t, n * size);
    return mpi_check(rc, "adding the ranks' results (MPI_Allreduce)", st);
}

static lvcl_error mpi_gather(lvcl_cluster *c, const void *mine, size_t bytes, void *all, lvcl_status *st)
{
    mpi_cluster *m = c->impl;
    if (bytes > INT_MAX) return lvcl_fail(st, LVCL_ERR_CLUSTER, "%zu bytes are too many to gather at once", bytes);
    double t = lvcl_seconds();
    int rc = MPI_Allgather(mine, (int)bytes, MPI_BYTE, all, (int)bytes, MPI_BYTE, m->comm);
    count(c, t, bytes);
    return mpi_check(rc, "gathering the ranks' outcomes (MPI_Allgather)", st);
}

static void mpi_abort(lvcl_cluster *c, int status)
{
    MPI_Abort(((mpi_cluster *)c->impl)->comm, status);
}

lvcl_error lvcl_cluster_mpi_open(MPI_Comm comm, lvcl_cluster *c, lvcl_status *st)
{
    *c = (lvcl_cluster){.restart = mpi_restart,
                        .take = mpi_take,
                        .reduce = mpi_reduce,
                        .gather = mpi_gather,
                        .abort = mpi_abort};
    mpi_cluster *m = calloc(1, sizeof *m);
    if (!m) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "out of host memory for the cluster");
    m->comm = MPI_COMM_NULL;
    m->counter_win = MPI_WIN_NULL;
    c->impl = m;
    /* Failures come back to lvcl, which names the rank and the call. */
    int rc = MPI_Comm_dup(comm, &m->comm);
    if (rc == MPI_SUCCESS) rc = MPI_Comm_set_errhandler(m->comm, MPI_ERRORS_RETURN);
    if (rc == MPI_SUCCESS) rc = MPI_Comm_rank(m->comm, &c->rank);
    if (rc == MPI_SUCCESS) rc = MPI_Comm_size(m->comm, &c->size);
    if (rc == MPI_SUCCESS)
        rc = MPI_Win_allocate(c->rank == 0 ? sizeof(uint64_t) : 0, sizeof(uint64_t), MPI_INFO_NULL, m->comm,
                              &m->counter, &m->counter_win);
    if (rc == MPI_SUCCESS) rc = MPI_Win_set_errhandler(m->counter_win, MPI_ERRORS_RETURN);
    if (rc == MPI_SUCCESS && c->rank == 0) *m->counter = 0;
    /* One passive-target epoch for the window's life: takes need no partner. */
    if (rc == MPI_SUCCESS) rc = MPI_Win_lock_all(0, m->counter_win);
    if (rc == MPI_SUCCESS) rc = MPI_Barrier(m->comm);
    return mpi_check(rc, "setting up the ranks' shared counter (MPI_Win_allocate)", st);
}

void lvcl_cluster_mpi_close(lvcl_cluster *c)
{
    mpi_cluster *m = c->impl;
    if (!m) return;
    if (m->counter_win != MPI_WIN_NULL) {
        MPI_Win_unlock_all(m->counter_win);
        MPI_Win_free(&m->counter_win);
    }
    if (m->comm != MPI_COMM_NULL) MPI_Comm_free(&m->comm);
    free(m);
    c->impl = NULL;
}
