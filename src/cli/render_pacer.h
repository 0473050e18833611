/* render_pacer.h: the render_control of `trazador render`: passes sized to about half a second,
 * checkpoints every so many seconds and on SIGUSR1, SIGINT or SIGTERM (the last two then stop
 * the render), written from a copy of the part while the next pass renders, and a time limit
 * that no pass is started past. */
#ifndef TRAZADOR_RENDER_PACER_H
#define TRAZADOR_RENDER_PACER_H

#include <pthread.h>
#include <signal.h>
#include <stdbool.h>
#include <stdint.h>

#include "render/part.h"
#include "render/render.h"

typedef struct render_pacer {
    const char *checkpoint; /* NULL: none */
    double every;           /* seconds between checkpoints */
    double time_limit;      /* seconds; <= 0: none */
    /* what happened */
    int stopped_by;            /* the signal that stopped the render, 0 if none */
    bool time_up;              /* the time limit stopped it */
    bool failed;               /* a checkpoint could not be written */
    int checkpoints;           /* written */
    double checkpoint_seconds; /* spent writing them */
    /* state */
    double start, pass_start, last_checkpoint, sample_seconds;
    uint32_t pass_from, chunks;
    bool started;
    struct sigaction old[3];
    bool catching;
    /* The checkpoint being written, from a copy, on a thread of its own while the render goes
     * on (its result read when it is joined). */
    pthread_t writer;
    bool writing, write_ok;
    part pending;
    double write_seconds;
} render_pacer;

/* Starts the pacer (clock and, with a checkpoint, the signal handlers) and points control at it;
 * never fails. */
void render_pacer_start(render_pacer *pc, render_control *control);
/* Obeys a signal that came during the last pass, which no next pass saw, as between passes: a
 * checkpoint of done (the finished part; NULL when the render failed), and SIGINT or SIGTERM set
 * stopped_by. Then waits for the checkpoint being written and puts back the signal handlers;
 * false (logged) when a checkpoint could not be written. */
bool render_pacer_stop(render_pacer *pc, const part *done);
/* clock_seconds() when the time limit ends, 0 without one. */
double render_pacer_deadline(const render_pacer *pc);

#endif
