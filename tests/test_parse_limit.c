/* test_parse_limit.c: the limit on primitives (spheres and triangles together, a quad counting as
 * two), against a copy of the parser built with PARSER_MAX_PRIMITIVES lowered to 30000
 * (tests/CMakeLists.txt): the real limit, 16777216, takes gigabytes to reach. The error is at the
 * directive word of the first line past the limit, on 1 thread and on several (chunks parsed
 * ahead are refused by the limit too). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "parse_check.h"
#include "scene/parser.h"

_Static_assert(PARSER_MAX_PRIMITIVES == 30000, "built with the lowered limit");

/* A text of the two required lines and then `count` primitive lines: line k (from 3) is a
 * sphere, a triangle or a quad by `pattern`, k - 3 taken modulo its length (s, t, q), but for the
 * last line, which is `last` when not 0. */
static char *primitives_text(int count, const char *pattern, char last, size_t *length) {
    size_t size = (size_t)count * 80 + 128, used = 0;
    char *text = malloc(size);
    used +=
        (size_t)snprintf(text, size, "camera position 0 0 -5\nplane width 4 height 3 pixel 1\n");
    size_t n = strlen(pattern);
    for (int k = 0; k < count; k++) {
        char kind = last && k == count - 1 ? last : pattern[(size_t)k % n];
        const char *fmt = kind == 's'   ? "sphere lambertian center %d 0 0 radius 0.25\n"
                          : kind == 't' ? "triangle mirror v0 %d 0 0 v1 0 1 0 v2 0 0 1\n"
                                        : "quad phong v0 0 0 %d v1 1 0 %d v2 1 1 %d v3 0 1 %d\n";
        used += (size_t)snprintf(text + used, size - used, fmt, k, k, k, k);
    }
    *length = used;
    return text;
}

/* Parses on 1, 2 and 4 threads; each must fail at line:1 with the limit's message, or (line 0)
 * succeed with `primitives` spheres and triangles in all. */
static void expect(const char *name, const char *text, size_t length, int line, int primitives) {
    const int threads[] = {1, 2, 4};
    for (size_t k = 0; k < sizeof threads / sizeof threads[0]; k++) {
        scene s;
        scene_error err;
        memset(&err, 0, sizeof err);
        bool ok = scene_parse_string_threads(text, length, "limit.scene", threads[k], &s, &err);
        if (line == 0) {
            check(ok && s.sphere_count + s.triangle_count == primitives, name,
                  "%d threads: %s, %d primitives", threads[k], ok ? "parsed" : err.message,
                  ok ? s.sphere_count + s.triangle_count : 0);
        } else {
            check(!ok && err.line == line && err.col == 1 &&
                      strstr(err.message,
                             "too many primitives (spheres and triangles together, a quad "
                             "counting as two; the maximum is 30000)"),
                  name, "%d threads: %s %d:%d %s", threads[k], ok ? "parsed" : "failed", err.line,
                  err.col, err.message);
        }
        if (ok) scene_free(&s);
    }
}

int main(void) {
    size_t length;
    char *text = primitives_text(30000, "s", 0, &length);
    expect("30000 spheres", text, length, 0, 30000);
    free(text);
    text = primitives_text(30001, "s", 0, &length);
    expect("30001 spheres", text, length, 30003, 0);
    free(text);
    text = primitives_text(30001, "t", 0, &length);
    expect("30001 triangles", text, length, 30003, 0);
    free(text);
    /* s t q repeats: 4 primitives every 3 lines; 22500 lines hold exactly 30000. */
    text = primitives_text(22500, "stq", 0, &length);
    expect("30000 mixed", text, length, 0, 30000);
    free(text);
    text = primitives_text(29999, "t", 'q', &length);
    expect("a quad filling the limit", text, length, 0, 30000);
    free(text);
    text = primitives_text(30000, "t", 'q', &length);
    expect("a quad whose second half is one too many", text, length, 30002, 0);
    free(text);
    /* Far past the limit, the text cut into chunks: the first line past it (after 7500 groups of
     * q t s, 22500 lines, line 22503) fails. */
    text = primitives_text(60000, "qts", 0, &length);
    expect("60000 mixed lines", text, length, 22503, 0);
    free(text);
    return parse_check_summary("test_parse_limit");
}
