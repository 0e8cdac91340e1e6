#include "parallel.h"

#include <pthread.h>
#include <stdlib.h>

lvcl_error lvcl_run_parallel(void *(*fn)(void *), void *jobs, size_t job_size, int n, lvcl_status *st)
{
    if (n == 1) {
        fn(jobs);
        return LVCL_OK;
    }
    pthread_t *threads = malloc((size_t)n * sizeof *threads);
    if (!threads) return lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "cannot start a thread per device");
    int started = 0;
    for (; started < n; started++)
        if (pthread_create(&threads[started], NULL, fn, (char *)jobs + (size_t)started * job_size)) break;
    for (int i = 0; i < started; i++) pthread_join(threads[i], NULL);
    free(threads);
    return started == n ? LVCL_OK : lvcl_fail(st, LVCL_ERR_OUT_OF_MEMORY, "cannot start a thread per device");
}
