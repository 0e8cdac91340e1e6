/* Wall-clock time for measurements. */
#ifndef LVCL_TIMER_H
#define LVCL_TIMER_H

#include <time.h>

static inline double lvcl_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#endif
