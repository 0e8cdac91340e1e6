/* One host thread per device: the passes that run on several devices at
 * once hand each device's work to its own thread. */
#ifndef LVCL_PARALLEL_H
#define LVCL_PARALLEL_H

#include <stddef.h>

/* Runs fn on each of the n jobs (job i at (char *)jobs + i * job_size), on
 * a thread each when n > 1, and waits for all. Returns 0, or -1 if a thread
 * could not be started (the jobs that did start have finished). */
int lvcl_run_parallel(void *(*fn)(void *), void *jobs, size_t job_size, int n);

#endif
