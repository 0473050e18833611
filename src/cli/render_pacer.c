/* render_pacer.c: passes, checkpoints, signals and the time limit of `trazador render` (see
 * render_pacer.h). */
#include "cli/render_pacer.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "render/chunk_tree.h"
#include "render/part.h"
#include "util/clock.h"
#include "util/log.h"

/* Seconds a pass aims at: signals and checkpoints wait for the pass in flight. */
#define PASS_SECONDS 0.5

static volatile sig_atomic_t signal_seen;
/* The SIGINT or SIGTERM that came, 0 before one: kept (signal_seen is taken by next_pass), so a
 * pass abandoned for it always ends the render. */
static volatile sig_atomic_t stop_seen;
static const int caught[3] = {SIGINT, SIGTERM, SIGUSR1};

static void on_signal(int sig) {
    /* SIGINT and SIGTERM outrank SIGUSR1: they also stop the render. */
    if (signal_seen == 0 || signal_seen == SIGUSR1) signal_seen = sig;
    if (sig != SIGUSR1) stop_seen = sig;
}

/* The chunks of the next pass, 0 to stop; *sync asks for a checkpoint. */
static uint32_t next_pass(void *user, uint32_t done, bool *sync) {
    render_pacer *pc = user;
    double now = clock_seconds();
    if (pc->started && done > pc->pass_from)
        pc->sample_seconds = (now - pc->pass_start) / (double)(done - pc->pass_from);
    int sig = signal_seen;
    if (sig) signal_seen = 0;
    if (stop_seen && sig != SIGINT && sig != SIGTERM) sig = stop_seen;
    *sync = pc->checkpoint && (sig != 0 || now - pc->last_checkpoint >= pc->every);
    if (sig == SIGINT || sig == SIGTERM) {
        pc->stopped_by = sig;
        return 0;
    }
    double target = PASS_SECONDS;
    if (pc->checkpoint && pc->every < target) target = pc->every;
    uint32_t chunks = 1;
    if (pc->started && pc->sample_seconds > 0.0) {
        double chunk_seconds = pc->sample_seconds * TZ_CHUNK_SAMPLES;
        double fit = floor(target / chunk_seconds);
        chunks = fit < 1.0 ? 1u : fit > 65536.0 ? 65536u : (uint32_t)fit;
        if (pc->time_limit > 0.0) {
            double left = pc->start + pc->time_limit - now;
            double room = floor(left / chunk_seconds);
            if (room < 1.0) {
                pc->time_up = true;
                return 0;
            }
            if (room < chunks) chunks = (uint32_t)room;
        }
    }
    pc->started = true;
    pc->pass_from = done;
    pc->pass_start = clock_seconds();
    return chunks;
}

/* The writer thread: writes pending and frees it. */
static void *write_pending(void *arg) {
    render_pacer *pc = arg;
    double t0 = clock_seconds();
    pc->write_ok = part_write(pc->checkpoint, &pc->pending);
    pc->write_seconds = clock_seconds() - t0;
    part_free(&pc->pending);
    return NULL;
}

/* Waits for the checkpoint being written, if any; false when it failed (logged by it). */
static bool join_writer(render_pacer *pc) {
    if (!pc->writing) return !pc->failed;
    pthread_join(pc->writer, NULL);
    pc->writing = false;
    if (!pc->write_ok) {
        pc->failed = true;
        return false;
    }
    pc->checkpoints++;
    pc->checkpoint_seconds += pc->write_seconds;
    log_debug("checkpoint: %s written in %.1f ms", pc->checkpoint, pc->write_seconds * 1e3);
    return true;
}

/* Starts writing the checkpoint from a copy of p (the write before it done first); false when
 * a checkpoint could not be written or copied (logged). */
static bool synced(void *user, const part *p) {
    render_pacer *pc = user;
    if (!join_writer(pc)) return false;
    double t0 = clock_seconds();
    if (!part_copy(p, &pc->pending)) {
        pc->failed = true;
        return false;
    }
    log_debug("checkpoint: %s, samples %u:%u", pc->checkpoint, p->meta.sample_begin,
              p->meta.sample_end);
    if (pthread_create(&pc->writer, NULL, write_pending, pc) == 0) {
        pc->writing = true;
    } else { /* no thread: write it here */
        write_pending(pc);
        if (!pc->write_ok) {
            pc->failed = true;
            return false;
        }
        pc->checkpoints++;
        pc->checkpoint_seconds += pc->write_seconds;
    }
    double t1 = clock_seconds();
    pc->last_checkpoint = t1;
    pc->pass_start += t1 - t0; /* the copy is no part of the pass's time */
    return true;
}

void render_pacer_start(render_pacer *pc, render_control *control) {
    pc->start = clock_seconds();
    pc->last_checkpoint = pc->start;
    signal_seen = 0;
    stop_seen = 0;
    if (pc->checkpoint) {
        struct sigaction act = {0};
        act.sa_handler = on_signal;
        act.sa_flags = SA_RESTART;
        sigemptyset(&act.sa_mask);
        for (int k = 0; k < 3; k++) sigaction(caught[k], &act, &pc->old[k]);
        pc->catching = true;
        log_debug("checkpoints: to %s every %g s and on SIGUSR1, SIGINT and SIGTERM",
                  pc->checkpoint, pc->every);
    }
    *control = (render_control){.next_pass = next_pass,
                                .synced = synced,
                                .user = pc,
                                .stop = pc->checkpoint ? &stop_seen : NULL};
}

bool render_pacer_stop(render_pacer *pc, const part *done) {
    int sig = pc->catching ? (stop_seen ? stop_seen : signal_seen) : 0;
    bool ok = true;
    if (sig && done && !pc->stopped_by) {
        signal_seen = 0;
        log_debug("%s came during the last pass: checkpointing the finished part",
                  sig == SIGINT    ? "SIGINT"
                  : sig == SIGTERM ? "SIGTERM"
                                   : "SIGUSR1");
        ok = synced(pc, done);
        if (sig != SIGUSR1) pc->stopped_by = sig;
    }
    ok = join_writer(pc) && ok;
    if (pc->catching) {
        for (int k = 0; k < 3; k++) sigaction(caught[k], &pc->old[k], NULL);
        pc->catching = false;
    }
    return ok;
}

double render_pacer_deadline(const render_pacer *pc) {
    return pc->time_limit > 0.0 ? pc->start + pc->time_limit : 0.0;
}
