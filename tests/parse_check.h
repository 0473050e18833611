/* parse_check.h: what the parser's tests share: the check counter, parsing that must succeed or
 * fail at a line and column, and the big texts parsed in chunks on every thread count. */
#ifndef TRAZADOR_PARSE_CHECK_H
#define TRAZADOR_PARSE_CHECK_H

#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene.h"

static int passed, failed;

/* Counts one check; prints the case name and why when it fails. */
static inline bool check(bool ok, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static inline bool check(bool ok, const char *name, const char *fmt, ...) {
    if (ok) {
        passed++;
        return true;
    }
    failed++;
    fprintf(stderr, "FAIL %s: ", name);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fputc('\n', stderr);
    return false;
}

static inline bool vec_is(vec3 v, float x, float y, float z) {
    return v.x == x && v.y == y && v.z == z;
}

/* Parses text that must be valid; on failure prints the parser's error under `name`. */
static inline bool parse_ok(const char *name, const char *text, size_t length, scene *s) {
    scene_error err;
    bool ok = scene_parse_string(text, length, "test.scene", s, &err);
    return check(ok, name, "unexpected error %d:%d: %s", err.line, err.col, err.message);
}

#define BYTES(literal) literal, sizeof(literal) - 1
/* Two valid lines that most invalid cases start from, so their errors land on line 3. */
#define BASE "camera position 0 0 0\nplane width 4 height 3 pixel 0.01\n"

/* Parses text that must fail at line:col with `message` in the error, and leave *out alone. */
static inline void expect_error(const char *name, const char *text, size_t length, int line,
                                int col, const char *message) {
    scene s, sentinel;
    memset(&s, 0xab, sizeof s);
    memcpy(&sentinel, &s, sizeof s);
    scene_error err;
    memset(&err, 0xab, sizeof err); /* every field the parser must set, out_of_memory too */
    if (!check(!scene_parse_string(text, length, "bad.scene", &s, &err), name,
               "parsed without error")) {
        scene_free(&s);
        return;
    }
    check(err.line == line && err.col == col, name, "at %d:%d, expected %d:%d (%s)", err.line,
          err.col, line, col, err.message);
    check(strstr(err.message, message) != NULL, name, "message '%s' lacks '%s'", err.message,
          message);
    check(strcmp(err.file, "bad.scene") == 0, name, "file '%s'", err.file);
    check(!err.out_of_memory, name, "a scene error is marked out of memory (exit 1, not 2)");
    check(memcmp(&s, &sentinel, sizeof s) == 0, name, "*out was modified on failure");
}

/* A text of BASE and `lines` lines, mostly spheres (some with CR LF, comments and blank lines
 * between), where line number `tiny` (0: none) and every 997th line after it hold tiny spheres;
 * *line_at[k] is where line k + 1 starts. */
static inline char *chunked_text(int lines, int tiny, size_t *length, size_t *line_at) {
    char *text = malloc((size_t)lines * 64 + 128);
    size_t used = 0;
    for (int k = 1; k <= lines; k++) {
        line_at[k - 1] = used;
        if (k <= 2) {
            used += (size_t)sprintf(
                text + used, "%s\n",
                k == 1 ? "camera position 0 0 0" : "plane width 4 height 3 pixel 0.01");
        } else if (k % 101 == 0) {
            used += (size_t)sprintf(text + used, "# comment %d\n", k);
        } else if (k % 103 == 0) {
            used += (size_t)sprintf(text + used, "\n");
        } else {
            bool small = tiny && k >= tiny && (k - tiny) % 997 == 0;
            used += (size_t)sprintf(text + used, "sphere phong center %d.5 %d -%d radius %s%s\n",
                                    k % 1000, k % 17, k % 13, small ? "1e-9" : "0.25",
                                    k % 5 == 0 ? "\r" : "");
        }
    }
    line_at[lines] = used;
    *length = used;
    return text;
}

/* Text with line k (1-based) replaced by `line`, which must be no longer than the original. */
static inline void replace_line(char *text, const size_t *line_at, int k, const char *line) {
    size_t room = line_at[k] - line_at[k - 1] - 1, n = strlen(line);
    if (n > room) abort(); /* the test's own mistake: pick a longer line */
    memcpy(text + line_at[k - 1], line, n);
    memset(text + line_at[k - 1] + n, ' ', room - n); /* trailing blanks are whitespace */
}

/* Whether scenes a and b hold the same triangles, materials and normals, byte for byte. */
static inline bool same_faces(const scene *a, const scene *b) {
    return a->triangle_count == b->triangle_count && a->material_count == b->material_count &&
           a->normals_count == b->normals_count &&
           (!a->triangle_count || !memcmp(a->triangles, b->triangles,
                                          (size_t)a->triangle_count * sizeof *a->triangles)) &&
           (!a->material_count || !memcmp(a->materials, b->materials,
                                          (size_t)a->material_count * sizeof *a->materials)) &&
           (!a->normals_count ||
            !memcmp(a->normals, b->normals, (size_t)a->normals_count * sizeof *a->normals));
}

/* Parses text on 1 and on several threads: both fail or succeed alike, with the same error or
 * the same spheres, triangles with their materials and normals (bytes), lights and warnings;
 * returns the one-thread result (*err set on failure). */
static inline bool parse_all_threads(const char *name, const char *text, size_t length,
                                     scene_error *err, scene *s) {
    bool ok = scene_parse_string_threads(text, length, "big.scene", 1, s, err);
    const int counts[] = {2, 3, 4, 7};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        scene t;
        scene_error e;
        memset(&e, 0, sizeof e);
        bool ok_t = scene_parse_string_threads(text, length, "big.scene", counts[k], &t, &e);
        if (!check(ok_t == ok, name, "%d threads: %s", counts[k], ok_t ? "parsed" : e.message))
            continue;
        if (!ok) {
            check(e.line == err->line && e.col == err->col && !strcmp(e.message, err->message) &&
                      !strcmp(e.file, err->file),
                  name, "%d threads: %d:%d %s, one thread: %d:%d %s", counts[k], e.line, e.col,
                  e.message, err->line, err->col, err->message);
            continue;
        }
        check(t.sphere_count == s->sphere_count && t.light_count == s->light_count &&
                  (!s->sphere_count ||
                   !memcmp(t.spheres, s->spheres, (size_t)s->sphere_count * sizeof *s->spheres)) &&
                  same_faces(&t, s) && t.warning_count == s->warning_count &&
                  !memcmp(t.warnings, s->warnings, (size_t)s->warning_count * sizeof *t.warnings),
              name, "%d threads: %d spheres, %d triangles, %d warnings; one thread: %d, %d, %d",
              counts[k], t.sphere_count, t.triangle_count, t.warning_count, s->sphere_count,
              s->triangle_count, s->warning_count);
        scene_free(&t);
    }
    return ok;
}

/* Prints the closing "name: N passed, N failed" line; returns the exit code. */
static inline int parse_check_summary(const char *name) {
    printf("%s: %d passed, %d failed\n", name, passed, failed);
    return failed ? 1 : 0;
}

#endif
