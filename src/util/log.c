/* log.c: the message sink behind log.h. */
#include "util/log.h"

#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

static log_level min_level = LOG_INFO;

void log_set_level(log_level level) { min_level = level; }

/* Errors held back by log_hold_errors, one per line, in a buffer that grows (a validation
 * callback may come from a driver thread, hence the lock). */
static pthread_mutex_t held_lock = PTHREAD_MUTEX_INITIALIZER;
static bool holding;
static char *held;
static size_t held_length, held_capacity;

void log_hold_errors(void) {
    pthread_mutex_lock(&held_lock);
    holding = true;
    held_length = 0;
    if (held) held[0] = '\0';
    pthread_mutex_unlock(&held_lock);
}

const char *log_release_errors(void) {
    pthread_mutex_lock(&held_lock);
    holding = false;
    pthread_mutex_unlock(&held_lock);
    return held ? held : "";
}

/* Appends one held error line; false when not holding, or out of memory (the caller prints it). */
static bool hold(const char *fmt, va_list ap) {
    pthread_mutex_lock(&held_lock);
    bool held_it = false;
    va_list measure;
    va_copy(measure, ap);
    int n = holding ? vsnprintf(NULL, 0, fmt, measure) : -1;
    va_end(measure);
    size_t need = n >= 0 ? held_length + (size_t)n + 2 : 0;
    if (n >= 0 && need > held_capacity) {
        size_t capacity = held_capacity ? held_capacity : 1024;
        while (capacity < need) capacity *= 2;
        char *grown = realloc(held, capacity);
        if (grown) held = grown, held_capacity = capacity;
    }
    if (n >= 0 && need <= held_capacity) {
        vsnprintf(held + held_length, held_capacity - held_length, fmt, ap);
        held_length += (size_t)n;
        held[held_length++] = '\n';
        held[held_length] = '\0';
        held_it = true;
    }
    pthread_mutex_unlock(&held_lock);
    return held_it;
}

/* Prints (or, for an error while holding, holds) one message of the level. */
static void log_vmessage(log_level level, const char *fmt, va_list ap) {
    if (level == LOG_ERROR) {
        va_list copy;
        va_copy(copy, ap);
        bool held_it = hold(fmt, copy);
        va_end(copy);
        if (held_it) return;
    }
    if (level < min_level) return;
    static const char *const prefix[] = {"debug: ", "", "warning: ", "error: "};
    fprintf(stderr, "trazador: %s", prefix[level]);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
}

#define LOG_AT(level)                 \
    do {                              \
        va_list ap;                   \
        va_start(ap, fmt);            \
        log_vmessage(level, fmt, ap); \
        va_end(ap);                   \
    } while (0)

void log_debug(const char *fmt, ...) { LOG_AT(LOG_DEBUG); }

void log_info(const char *fmt, ...) { LOG_AT(LOG_INFO); }

void log_warn(const char *fmt, ...) { LOG_AT(LOG_WARN); }

void log_error(const char *fmt, ...) { LOG_AT(LOG_ERROR); }
