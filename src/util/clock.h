/* clock.h: the monotonic wall clock that timings and benchmarks read. */
#ifndef TRAZADOR_CLOCK_H
#define TRAZADOR_CLOCK_H

#include <time.h>

/* Seconds on the monotonic clock since an arbitrary start; never fails. */
static inline double clock_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

#endif
