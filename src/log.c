/* log.c: the message sink behind log.h. */
#include "log.h"

#include <stdarg.h>
#include <stdio.h>

static log_level min_level = LOG_INFO;

void log_set_level(log_level level) { min_level = level; }

void log_message(log_level level, const char *fmt, ...) {
    if (level < min_level) return;
    static const char *const prefix[] = {"debug: ", "", "warning: ", "error: "};
    fprintf(stderr, "trazador: %s", prefix[level]);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
}
