/* log.h: the one leveled message sink; every library reports through it, only main.c exits. */
#ifndef TRAZADOR_LOG_H
#define TRAZADOR_LOG_H

#include <stdbool.h>

typedef enum log_level { LOG_DEBUG, LOG_INFO, LOG_WARN, LOG_ERROR } log_level;

/* Sets the lowest level that is printed (default LOG_INFO); never fails. */
void log_set_level(log_level level);
/* Each prints one line to stderr at its level, prefixed "trazador: " (and "warning: " or
 * "error: "), unless below the level set; log_error holds it instead while log_hold_errors is on.
 * A failed write is ignored: there is nowhere left to report it. */
void log_debug(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void log_info(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void log_warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void log_error(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

/* Holds errors back, unprinted, until log_release_errors (for callers that may recover); never
 * fails (past memory, errors are printed instead). */
void log_hold_errors(void);
/* Stops holding; returns the held errors, one per line ("" for none), valid until the next hold. */
const char *log_release_errors(void);

#endif
