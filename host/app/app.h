/* lvcl's command line as a function: parse the options, load the scene,
 * render, write the image and the stats. build/lvcl's main calls it alone;
 * lvcl-mpi's main (host/mpi/) calls it on every rank with the cluster that
 * shares the render, and then only rank 0 speaks and writes. */
#ifndef LVCL_APP_H
#define LVCL_APP_H

#include "../render/cluster.h"

/* Returns the process's exit status: 0, 1 for a failed run, 2 for bad
 * usage, 128 + the signal that stopped sampling early. */
int lvcl_app_main(int argc, char **argv, lvcl_cluster *cluster);

#endif
