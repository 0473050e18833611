/* interrupts.c: cleanup before death by a signal (see interrupts.h). */
#include "util/interrupts.h"

#include <pthread.h>

/* The signals whose default action ends the process that a user or the system sends a run:
 * Ctrl-C, kill, a closed terminal, Ctrl-\, a reader gone from a pipe, alarm and CPU-time limits. */
static const int interrupt_signals[INTERRUPT_SIGNALS] = {SIGINT,  SIGTERM, SIGHUP, SIGQUIT,
                                                         SIGPIPE, SIGALRM, SIGXCPU};

void interrupts_catch(void (*cleanup)(int), interrupts_saved *saved) {
    struct sigaction act = {0};
    act.sa_handler = cleanup;
    sigemptyset(&act.sa_mask);
    for (int k = 0; k < INTERRUPT_SIGNALS; k++) {
        sigaction(interrupt_signals[k], NULL, &saved->old[k]);
        if (saved->old[k].sa_handler == SIG_DFL) sigaction(interrupt_signals[k], &act, NULL);
    }
}

void interrupts_restore(const interrupts_saved *saved) {
    for (int k = 0; k < INTERRUPT_SIGNALS; k++)
        sigaction(interrupt_signals[k], &saved->old[k], NULL);
}

void interrupts_block(sigset_t *previous) {
    sigset_t block;
    sigemptyset(&block);
    for (int k = 0; k < INTERRUPT_SIGNALS; k++) sigaddset(&block, interrupt_signals[k]);
    pthread_sigmask(SIG_BLOCK, &block, previous);
}

void interrupts_unblock(const sigset_t *previous) { pthread_sigmask(SIG_SETMASK, previous, NULL); }

void interrupts_die(int sig) {
    signal(sig, SIG_DFL); /* async-signal-safe, as is raise() */
    raise(sig);
}
