/* scene_directives.c: the directives of the scene format (DESIGN section 2; scenes/README.md) by
 * their words: which parser (directives.h) takes a tokenized line, which lines a chunk parsed ahead
 * may hold; and what the parsers share to build their messages and grow the scene's arrays. */
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/parser.h"
#include "util/big_memory.h"

void directive_append(char *message, size_t size, const char *fmt, ...) {
    size_t used = strlen(message);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message + used, size - used, fmt, ap);
    va_end(ap);
}

/* Grows an array by doubling so a million appends cost a few dozen reallocations; room for
 * `adding` more items. */
bool directive_grow(parser *p, void **array, size_t *capacity, int count, int adding, int max,
                    size_t item, const char *what) {
    if (count > max - adding) {
        return parser_fail(p, p->tokens[0].col, "too many %s (the maximum is %d)", what, max);
    }
    if ((size_t)count + (size_t)adding <= *capacity) return true;
    size_t capacity_new = *capacity ? *capacity * 2 : 64;
    if (capacity_new < (size_t)count + (size_t)adding) capacity_new = (size_t)count + adding;
    if (capacity_new > (size_t)max) capacity_new = (size_t)max;
    void *grown = big_realloc(*array, capacity_new * item);
    if (!grown) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, p->tokens[0].col, "out of memory after %d %s", count, what);
    }
    *array = grown;
    *capacity = capacity_new;
    return true;
}

bool directive_file_path(parser *p, const token *t, const char *what, char *out, size_t size) {
    char named[PATH_MAX];
    if (!parser_path(p, t, named, sizeof named)) return false;
    const char *slash = strrchr(p->filename, '/');
    int dir =
        named[0] == '/' || p->filename[0] == '<' || !slash ? 0 : (int)(slash - p->filename) + 1;
    int n = snprintf(out, size, "%.*s%s", dir, p->filename, named);
    return (n >= 0 && (size_t)n < size) || parser_fail(p, t->col, "%s path is too long", what);
}

typedef struct directive_spec {
    const char *word;
    bool (*parse)(parser *p);
    bool primitive; /* parsed in chunks ahead (primitives_only) */
} directive_spec;

static const directive_spec directives[] = {
    {"camera", directive_camera, false},
    {"plane", directive_plane, false},
    {"light", directive_light, false},
    {"sun", directive_sun, false},
    {"sphere", directive_sphere, true},
    {"triangle", directive_triangle, true},
    {"quad", directive_quad, true},
    {"background", directive_background, false},
    {"environment", directive_environment, false}, /* in order: it reads a file */
    {"render", directive_render, false},
    {"mesh", directive_mesh, false}, /* in order: it reads a file and may warn */
};

bool parser_directive(parser *p) {
    const token *word = &p->tokens[0];
    for (size_t i = 0; i < sizeof directives / sizeof directives[0]; i++) {
        if (!parser_token_is(word, directives[i].word)) continue;
        if (p->primitives_only && !directives[i].primitive) return false;
        return directives[i].parse(p);
    }
    return parser_fail(p, word->col,
                       "unknown directive '%s' (expected one of: camera plane light sphere "
                       "triangle quad mesh environment background render)",
                       parser_quote(p, word));
}
