/* lvcl-mpi: lvcl over MPI ranks, one frame shared by all (docs/distributed.md).
 * mpirun -np N build/lvcl-mpi [lvcl options] SCENE */
#include <mpi.h>
#include <stdio.h>

#include "../app/app.h"
#include "cluster_mpi.h"

int main(int argc, char **argv)
{
    int provided = MPI_THREAD_SINGLE, rank = 0;
    if (MPI_Init_thread(&argc, &argv, MPI_THREAD_MULTIPLE, &provided) != MPI_SUCCESS) {
        fprintf(stderr, "lvcl: error: MPI could not be initialised\n");
        return 1;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    /* Each device of a rank has a host thread, and any of them may take work. */
    if (provided < MPI_THREAD_MULTIPLE) {
        if (rank == 0) fprintf(stderr, "lvcl: error: this MPI does not support MPI_THREAD_MULTIPLE, which lvcl-mpi needs\n");
        MPI_Finalize();
        return 1;
    }
    lvcl_cluster cluster;
    lvcl_status st = {0};
    int status;
    if (lvcl_cluster_mpi_open(MPI_COMM_WORLD, &cluster, &st)) {
        fprintf(stderr, "lvcl: error: rank %d: %s\n", rank, st.message);
        status = 1;
    } else status = lvcl_app_main(argc, argv, &cluster);
    lvcl_cluster_mpi_close(&cluster);
    MPI_Finalize();
    return status;
}
