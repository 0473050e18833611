/* atomic_file.h: writing a file all or nothing: through a temporary file in the same folder that
 * is renamed over the destination only once complete and synced, and the folder synced after the
 * rename. A failure leaves neither a temporary nor a truncated file; a signal during the write
 * that would kill the process (interrupts.h) removes the temporary file first. An existing file
 * keeps its mode, a new one gets 0666 less the umask; the new file is the caller's (its owner,
 * not the old file's) and other hard links to the old file keep the old content. Main thread
 * only: it reads the umask and sets signal handlers. */
#ifndef TRAZADOR_ATOMIC_FILE_H
#define TRAZADOR_ATOMIC_FILE_H

#include <stdbool.h>
#include <stdio.h>

/* Writes the whole content to fp; returns 0 or an errno value. */
typedef int (*atomic_file_fill)(FILE *fp, const void *context);

/* Writes path with fill(fp, context); false (logged) on failure, leaving any old file intact. */
bool atomic_file_write(const char *path, atomic_file_fill fill, const void *context);
/* Whether atomic_file_write could write path: its folder exists and takes a file, its name fits
 * the file system, and (unless `force`) it is not write-protected (no write permission for the
 * caller, or no write bit at all, which root would otherwise ignore); false (logged) if not. */
bool atomic_file_check_force(const char *path, bool force);
/* atomic_file_check_force without force: a write-protected file is refused. */
bool atomic_file_check(const char *path);
/* Whether a and b name one file: the same device and inode (through any name, hard or symbolic
 * link), or, where neither exists yet, the same name in the same folder; never fails. */
bool atomic_file_same(const char *a, const char *b);

#endif
