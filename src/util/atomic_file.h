/* atomic_file.h: writing a file all or nothing: through a temporary file in the same folder that
 * is renamed over the destination only once complete and synced. A failure leaves neither a
 * temporary nor a truncated file; a signal during the write that would kill the process
 * (interrupts.h) removes the temporary file first. An existing file keeps its mode, a new one
 * gets 0666 less the umask. Main thread only: it reads the umask and sets signal handlers. */
#ifndef TRAZADOR_ATOMIC_FILE_H
#define TRAZADOR_ATOMIC_FILE_H

#include <stdbool.h>
#include <stdio.h>

/* Writes the whole content to fp; returns 0 or an errno value. */
typedef int (*atomic_file_fill)(FILE *fp, const void *context);

/* Writes path with fill(fp, context); false (logged) on failure, leaving any old file intact. */
bool atomic_file_write(const char *path, atomic_file_fill fill, const void *context);
/* Whether atomic_file_write could write path (its folder takes a file); false (logged) if not. */
bool atomic_file_check(const char *path);

#endif
