/* interrupts.h: a cleanup step run when a signal is about to kill the process (SIGINT, SIGTERM,
 * SIGHUP, SIGQUIT, SIGPIPE, SIGALRM or SIGXCPU: a temporary file to remove, a progress line to
 * clear), then death by the same signal. */
#ifndef TRAZADOR_INTERRUPTS_H
#define TRAZADOR_INTERRUPTS_H

#include <signal.h>

#define INTERRUPT_SIGNALS 7

/* The actions a catch replaced, for interrupts_restore. */
typedef struct interrupts_saved {
    struct sigaction old[INTERRUPT_SIGNALS];
} interrupts_saved;

/* Runs cleanup(sig) on those signals that would kill the process as is (ignored or handled ones
 * are left alone); cleanup must be async-signal-safe and end with interrupts_die(sig). Never
 * fails. */
void interrupts_catch(void (*cleanup)(int), interrupts_saved *saved);
/* Puts back the actions interrupts_catch replaced; never fails. */
void interrupts_restore(const interrupts_saved *saved);
/* Holds the signals back (until interrupts_unblock), so that two steps happen with none between;
 * never fails. */
void interrupts_block(sigset_t *previous);
/* Lets held signals through again: previous is interrupts_block's; never fails. */
void interrupts_unblock(const sigset_t *previous);
/* Ends a cleanup: the default action again, and the signal, which kills the process; does not
 * return. */
void interrupts_die(int sig);

#endif
