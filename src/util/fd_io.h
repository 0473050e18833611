/* fd_io.h: whole reads and writes of file descriptors, through interruptions and short counts
 * (assimp's child process sends its outcome down a pipe and its faces through shared memory). */
#ifndef TRAZADOR_FD_IO_H
#define TRAZADOR_FD_IO_H

#include <stdbool.h>
#include <stddef.h>

/* Writes size bytes of data to fd; false on an error or a write that makes no progress. */
bool fd_write_all(int fd, const void *data, size_t size);

/* Reads size bytes from fd into data before deadline (clock_seconds()); false on end of file,
 * an error, or the deadline passed (*late set). */
bool fd_read_all_by(int fd, void *data, size_t size, double deadline, bool *late);

/* Copies size bytes between data and the file fd from its start: pwrite when `to`, else pread;
 * false (errno set, EIO when the file ends first) on failure. */
bool fd_copy_at(int fd, void *data, size_t size, bool to);

#endif
