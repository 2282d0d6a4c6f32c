/* The monotonic clock of timings and progress reports (core/core_internal.h). */
#include <time.h>

#include "core/core_internal.h"
#include "hairkit/core.h"

double hk_seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* CPU time of the calling thread: the work of one task, whatever else the cores run. */
double hk_thread_cpu_seconds(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}
