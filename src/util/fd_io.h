/* fd_io.h: whole reads and writes of file descriptors, through interruptions and short counts
 * (assimp's child process sends its outcome down a pipe and its faces through shared memory). */
#ifndef TRAZADOR_FD_IO_H
#define TRAZADOR_FD_IO_H

#include <stdbool.h>
#include <stddef.h>
#include <time.h>

/* Writes size bytes of data to fd; false on an error or a write that makes no progress. */
bool fd_write_all(int fd, const void *data, size_t size);

/* A writer process's time limit: processor time, so that a loaded machine does not end a child
 * that is merely waiting for a core, and a wall deadline for one blocked on something else. */
typedef struct {
    clockid_t cpu_clock;  /* the writer's processor clock (clock_getcpuclockid) */
    double cpu_seconds;   /* the most processor time it may use */
    double wall_deadline; /* clock_seconds() past which it is late all the same */
} fd_time_limit;

/* Reads size bytes from fd into data while the writer is within limit; false on end of file,
 * an error, or the limit passed (*late set). */
bool fd_read_all_by(int fd, void *data, size_t size, const fd_time_limit *limit, bool *late);

/* Copies size bytes between data and the file fd from its start: pwrite when `to`, else pread;
 * false (errno set, EIO when the file ends first) on failure. */
bool fd_copy_at(int fd, void *data, size_t size, bool to);

#endif
