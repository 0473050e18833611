/* threads.h: how many threads a parallel step starts. */
#ifndef TRAZADOR_THREADS_H
#define TRAZADOR_THREADS_H

#include <unistd.h>

/* `requested` threads, or with 0 (or less) one per online core; between 1 and `most`. */
static inline int thread_count(int requested, int most) {
    long n = requested > 0 ? requested : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > most ? most : (int)n;
}

#endif
