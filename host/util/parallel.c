#include "parallel.h"

#include <pthread.h>
#include <stdlib.h>

int lvcl_run_parallel(void *(*fn)(void *), void *jobs, size_t job_size, int n)
{
    if (n == 1) {
        fn(jobs);
        return 0;
    }
    pthread_t *threads = malloc((size_t)n * sizeof *threads);
    if (!threads) return -1;
    int started = 0;
    for (; started < n; started++)
        if (pthread_create(&threads[started], NULL, fn, (char *)jobs + (size_t)started * job_size)) break;
    for (int i = 0; i < started; i++) pthread_join(threads[i], NULL);
    free(threads);
    return started == n ? 0 : -1;
}
