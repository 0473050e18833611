/* fd_io.c: whole reads and writes of file descriptors (fd_io.h). */
#include "util/fd_io.h"

#include <errno.h>
#include <poll.h>
#include <sys/types.h>
#include <unistd.h>

#include "util/clock.h"

bool fd_write_all(int fd, const void *data, size_t size) {
    const char *at = data;
    while (size > 0) {
        ssize_t n = write(fd, at, size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        at += n;
        size -= (size_t)n;
    }
    return true;
}

bool fd_read_all_by(int fd, void *data, size_t size, double deadline, bool *late) {
    char *at = data;
    while (size > 0) {
        double left = deadline - clock_seconds();
        struct pollfd pfd = {.fd = fd, .events = POLLIN};
        int ready = left > 0 ? poll(&pfd, 1, (int)(left * 1000) + 1) : 0;
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) {
            *late = true;
            return false;
        }
        ssize_t n = read(fd, at, size > (1u << 20) ? (1u << 20) : size);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        at += n;
        size -= (size_t)n;
    }
    return true;
}

bool fd_copy_at(int fd, void *data, size_t size, bool to) {
    char *at = data;
    size_t done = 0;
    while (done < size) {
        ssize_t n = to ? pwrite(fd, at + done, size - done, (off_t)done)
                       : pread(fd, at + done, size - done, (off_t)done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) {
            if (n == 0) errno = EIO;
            return false;
        }
        done += (size_t)n;
    }
    return true;
}
