/* threads.h: how many threads a parallel step starts, and a step's slices run on them. */
#ifndef TRAZADOR_THREADS_H
#define TRAZADOR_THREADS_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>
#include <unistd.h>

/* The most threads threads_run starts. */
#define THREADS_MAX 64

/* `requested` threads, or with 0 (or less) one per online core; between 1 and `most`. */
static inline int thread_count(int requested, int most) {
    long n = requested > 0 ? requested : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > most ? most : (int)n;
}

/* Runs run(&shares[t]) for each of the count (at most THREADS_MAX) shares of `size` bytes, share
 * 0 on this thread and the others on threads of their own, or on this one where a thread cannot
 * start: a slice's work is the same wherever it runs. */
static inline void threads_run(void *(*run)(void *), void *shares, size_t size, int count) {
    pthread_t threads[THREADS_MAX];
    bool started[THREADS_MAX] = {false};
    char *at = shares;
    for (int t = 1; t < count; t++)
        started[t] = pthread_create(&threads[t], NULL, run, at + (size_t)t * size) == 0;
    run(at);
    for (int t = 1; t < count; t++) {
        if (started[t])
            pthread_join(threads[t], NULL);
        else
            run(at + (size_t)t * size);
    }
}

#endif
