/* log.c: the message sink behind log.h. */
#include "log.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static log_level min_level = LOG_INFO;

/* Errors held back by log_hold_errors, one per line (a validation callback may come from a driver
 * thread, hence the lock). */
static pthread_mutex_t held_lock = PTHREAD_MUTEX_INITIALIZER;
static bool holding;
static char held[4096];
static size_t held_length;

void log_hold_errors(void) {
    pthread_mutex_lock(&held_lock);
    holding = true;
    held_length = 0;
    held[0] = '\0';
    pthread_mutex_unlock(&held_lock);
}

const char *log_release_errors(void) {
    pthread_mutex_lock(&held_lock);
    holding = false;
    pthread_mutex_unlock(&held_lock);
    return held;
}

/* Appends one held error line; false when not holding (the caller prints it). */
static bool hold(const char *fmt, va_list ap) {
    pthread_mutex_lock(&held_lock);
    bool held_it = holding;
    if (holding && held_length + 2 < sizeof held) {
        int n = vsnprintf(held + held_length, sizeof held - held_length - 1, fmt, ap);
        if (n > 0)
            held_length += (size_t)n < sizeof held - held_length - 2
                               ? (size_t)n
                               : sizeof held - held_length - 2;
        held[held_length++] = '\n';
        held[held_length] = '\0';
    }
    pthread_mutex_unlock(&held_lock);
    return held_it;
}

void log_set_level(log_level level) { min_level = level; }

void log_message(log_level level, const char *fmt, ...) {
    if (level == LOG_ERROR) {
        va_list ap;
        va_start(ap, fmt);
        bool held_it = hold(fmt, ap);
        va_end(ap);
        if (held_it) return;
    }
    if (level < min_level) return;
    static const char *const prefix[] = {"debug: ", "", "warning: ", "error: "};
    fprintf(stderr, "trazador: %s", prefix[level]);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}
