/* The cluster of host/render/cluster.h over MPI: the shared work counter
 * is a 64-bit integer in a window on rank 0, taken by MPI_Fetch_and_op
 * (no rank serves it, so a busy rank 0 never slows the others' takes);
 * reductions are MPI_Allreduce with the built-in operations, which are
 * exact on integers. MPI errors come back as LVCL_ERR_CLUSTER naming the
 * call. Only lvcl-mpi links this. */
#ifndef LVCL_CLUSTER_MPI_H
#define LVCL_CLUSTER_MPI_H

#include <mpi.h>

#include "../render/cluster.h"

/* Collective over comm (MPI initialised with MPI_THREAD_MULTIPLE): fills c. */
lvcl_error lvcl_cluster_mpi_open(MPI_Comm comm, lvcl_cluster *c, lvcl_status *st);
/* Collective; c is unusable after. */
void lvcl_cluster_mpi_close(lvcl_cluster *c);

#endif
