/* atomic_file.h: writing a file all or nothing: through a temporary file in the same folder that
 * is renamed over the destination only once complete and synced. */
#ifndef TRAZADOR_ATOMIC_FILE_H
#define TRAZADOR_ATOMIC_FILE_H

#include <stdbool.h>
#include <stdio.h>

/* Writes the whole content to fp; returns 0 or an errno value. */
typedef int (*atomic_file_fill)(FILE *fp, const void *context);

/* Writes path with fill(fp, context), keeping an existing file's mode (a new one gets 0666 less
 * the umask); false (logged) on any failure, which leaves neither a temporary nor a truncated
 * file, and any existing file intact. SIGINT, SIGTERM or SIGHUP during the write (when not
 * ignored or handled) remove the temporary file before the process dies of them. Main thread
 * only: it reads the umask and sets signal handlers. */
bool atomic_file_write(const char *path, atomic_file_fill fill, const void *context);

#endif
