/* log.h: the one leveled message sink; every library reports through it, only main.c exits. */
#ifndef TRAZADOR_LOG_H
#define TRAZADOR_LOG_H

#include <stdbool.h>

typedef enum log_level { LOG_DEBUG, LOG_INFO, LOG_WARN, LOG_ERROR } log_level;

/* Sets the lowest level that is printed (default LOG_INFO); never fails. */
void log_set_level(log_level level);
/* Prints one line to stderr, prefixed "trazador: " (and the level for warnings/errors), or holds
 * it (log_hold_errors); a failed write is ignored: there is nowhere left to report it. */
void log_message(log_level level, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Holds errors back, unprinted, until log_release_errors (for callers that may recover); never
 * fails (past memory, errors are printed instead). */
void log_hold_errors(void);
/* Stops holding; returns the held errors, one per line ("" for none), valid until the next hold. */
const char *log_release_errors(void);

#define log_debug(...) log_message(LOG_DEBUG, __VA_ARGS__)
#define log_info(...) log_message(LOG_INFO, __VA_ARGS__)
#define log_warn(...) log_message(LOG_WARN, __VA_ARGS__)
#define log_error(...) log_message(LOG_ERROR, __VA_ARGS__)

#endif
