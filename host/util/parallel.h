/* One host thread per device: the passes that run on several devices at
 * once hand each device's work to its own thread. */
#ifndef LVCL_PARALLEL_H
#define LVCL_PARALLEL_H

#include <stddef.h>

#include "status.h"

/* Runs fn on each of the n jobs (job i at (char *)jobs + i * job_size), on
 * a thread each when n > 1, and waits for all. Fails with
 * LVCL_ERR_OUT_OF_MEMORY if a thread could not be started (the jobs that
 * did start have finished). */
lvcl_error lvcl_run_parallel(void *(*fn)(void *), void *jobs, size_t job_size, int n, lvcl_status *st);

#endif
