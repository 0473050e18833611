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

/* Seconds of the limit left now: the lesser of processor and wall time; 0 or less when passed
 * (a processor clock that cannot be read leaves the wall deadline alone to judge). */
static double time_left(const fd_time_limit *limit) {
    double wall_left = limit->wall_deadline - clock_seconds();
    struct timespec used;
    if (clock_gettime(limit->cpu_clock, &used) != 0) return wall_left;
    double cpu_left = limit->cpu_seconds - ((double)used.tv_sec + (double)used.tv_nsec * 1e-9);
    return cpu_left < wall_left ? cpu_left : wall_left;
}

bool fd_read_all_by(int fd, void *data, size_t size, const fd_time_limit *limit, bool *late) {
    /* Processor time runs slower than the wall clock: polls of at most this long re-read it. */
    const int poll_ms_max = 100;
    char *at = data;
    while (size > 0) {
        double left = time_left(limit);
        if (left <= 0.0) {
            *late = true;
            return false;
        }
        int wait_ms = left * 1000.0 >= poll_ms_max ? poll_ms_max : (int)(left * 1000.0) + 1;
        struct pollfd pfd = {.fd = fd, .events = POLLIN};
        int ready = poll(&pfd, 1, wait_ms);
        if (ready < 0 && errno == EINTR) continue;
        if (ready == 0) continue;
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
