/* scene_file.c: a scene read from a file or standard input (DESIGN section 2) and parsed
 * (scene_parse.c): all of it into memory, a stream checked line by line as it arrives so that
 * one that never ends is refused at its first bad line, and the errors of a file with no line. */
#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene/directives.h"
#include "scene/parser.h"
#include "scene/scene.h"
#include "util/big_memory.h"

/* A file-level error has no position: line and col are 0. */
static bool fail_file(const char *path, scene_error *err, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bool fail_file(const char *path, scene_error *err, const char *fmt, ...) {
    if (err) {
        snprintf(err->file, sizeof err->file, "%s", path);
        err->line = 0;
        err->col = 0;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
    return false;
}

/* A line of each read of a stream parsed as it arrives (the first new one; spheres dropped: the
 * whole text is parsed again, on every core, once read), so that a stream of bad lines that
 * never ends is refused at once rather than read to the size limit, at no cost worth naming
 * to a good one. Lines left out can only hide errors from it (what it parsed is a subset of
 * what the full parse sees), never make up one, so it never stops a good stream. */
typedef struct stream_check {
    parser *p; /* NULL: not checked (no memory: the parse after the read still reports) */
    size_t checked;
} stream_check;

static void stream_check_init(stream_check *c, const char *path) {
    c->checked = 0;
    c->p = calloc(1, sizeof *c->p);
    if (!c->p) return;
    c->p->filename = path;
    c->p->line = 1;
    c->p->mode_given = -1;
    c->p->s = parser_scene_defaults();
}

static void stream_check_free(stream_check *c) {
    if (c->p) scene_free(&c->p->s), free(c->p->views), mesh_placed_free(c->p);
    free(c->p);
}

/* Whether the first complete line of data[checked, used) parses, and the unfinished last one
 * is not already too long; false on an error, which the parse after the read reports as usual
 * (at the first bad line). */
static bool stream_check_lines(stream_check *c, const char *data, size_t used) {
    if (!c->p) return true;
    const char *text = data + c->checked, *end = data + used;
    const char *newline = memchr(text, '\n', (size_t)(end - text));
    if (!newline) return (size_t)(end - text) <= SCENE_MAX_LINE + 1; /* + 1: a CR */
    if (!parser_line(c->p, text, (size_t)(newline - text))) return false;
    c->p->s.sphere_count = 0;
    const char *last = newline;
    for (const char *q; (q = memchr(last + 1, '\n', (size_t)(end - last - 1)));) last = q;
    c->checked = (size_t)(last + 1 - data);
    return (size_t)(end - last - 1) <= SCENE_MAX_LINE + 1;
}

/* Reads all of fd into a malloc'd buffer; sizes a regular file from fstat, grows for pipes. */
static bool read_all(int fd, const char *path, char **data, size_t *length, bool *cut,
                     scene_error *err) {
    *cut = false;
    struct stat st;
    if (fstat(fd, &st) != 0) return fail_file(path, err, "cannot stat: %s", strerror(errno));
    if (S_ISDIR(st.st_mode)) return fail_file(path, err, "is a directory");
    size_t capacity = 1 << 16;
    if (S_ISREG(st.st_mode)) {
        if ((unsigned long long)st.st_size > MAX_TEXT_BYTES) {
            return fail_file(path, err, "file is too large (%lld bytes; the limit is %zu)",
                             (long long)st.st_size, MAX_TEXT_BYTES);
        }
        capacity = (size_t)st.st_size + 1; /* +1 so a regular file ends in one short read */
    }
    char *buffer = big_malloc(capacity);
    if (!buffer) {
        if (err) err->out_of_memory = true;
        return fail_file(path, err, "out of memory reading %zu bytes", capacity);
    }
    size_t used = 0;
    stream_check check = {0};
    if (!S_ISREG(st.st_mode)) stream_check_init(&check, path);
    for (;;) {
        if (used == capacity) {
            if (capacity > MAX_TEXT_BYTES) {
                free(buffer);
                stream_check_free(&check);
                return fail_file(path, err, "file is too large (the limit is %zu bytes)",
                                 MAX_TEXT_BYTES);
            }
            char *grown = big_realloc(buffer, capacity * 2);
            if (!grown) {
                free(buffer);
                stream_check_free(&check);
                if (err) err->out_of_memory = true;
                return fail_file(path, err, "out of memory reading %zu bytes", capacity * 2);
            }
            buffer = grown;
            capacity *= 2;
        }
        ssize_t n = read(fd, buffer + used, capacity - used);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) {
            int error = errno;
            free(buffer);
            stream_check_free(&check);
            return fail_file(path, err, "cannot read: %s", strerror(error));
        }
        if (n == 0) break;
        used += (size_t)n;
        /* A NUL byte is an error wherever it is: stop reading a stream (/dev/zero never ends)
         * and let the parser report it at its line and column. */
        *cut = !S_ISREG(st.st_mode) && (memchr(buffer + used - n, '\0', (size_t)n) ||
                                        /* a bad line stops a stream too */
                                        !stream_check_lines(&check, buffer, used));
        if (*cut) break;
    }
    stream_check_free(&check);
    *data = buffer;
    *length = used;
    return true;
}

bool scene_parse_file(const char *path, scene *out, scene_error *err) {
    return scene_parse_file_in_mode(path, -1, out, err);
}

bool scene_parse_file_in_mode(const char *path, int mode, scene *out, scene_error *err) {
    if (err) err->out_of_memory = false;
    /* "-" is standard input, named as the tools name it. */
    bool is_stdin = !strcmp(path, "-");
    if (is_stdin) path = "<stdin>";
    int fd = is_stdin ? dup(STDIN_FILENO) : open(path, O_RDONLY);
    if (fd < 0) return fail_file(path, err, "cannot open: %s", strerror(errno));
    char *data = NULL;
    size_t length = 0;
    bool cut;
    bool ok = read_all(fd, path, &data, &length, &cut, err);
    close(fd);
    if (ok) ok = parser_run(data, length, path, 0, mode, out, err);
    if (ok && cut) { /* never a scene cut short: the parse must report what stopped the read */
        scene_free(out);
        ok = fail_file(path, err, "stopped reading at a line the parser then accepted");
    }
    free(data);
    return ok;
}
