/* parser.h: what the files of the scene parser share (not an API): the parser's state, the
 * tokens and key tables of a line, the lexer's functions and the driver's. scene_lex.c splits
 * lines into tokens and reads values and keys; scene_directives.c hands each directive to its
 * parser (directives.h); scene_parse.c drives them over a text, in chunks on several threads;
 * scene_file.c reads files. */
#ifndef TRAZADOR_SCENE_PARSER_H
#define TRAZADOR_SCENE_PARSER_H

#include <limits.h>
#include <stdbool.h>
#include <stddef.h>

#include "scene/scene.h"

/* A line of SCENE_MAX_LINE bytes holds at most this many space-separated tokens. */
#define MAX_TOKENS (SCENE_MAX_LINE / 2 + 1)
/* Characters of a bad token quoted back in an error message. */
#define MAX_QUOTED_CHARS 60
/* Keys per directive: the triangle has the most (v0 v1 v2 n0 n1 n2 uv0 uv1 uv2 and the
 * material keys, the texture keys among them). */
#define MAX_KEYS 26
/* Spheres and triangles in all (a quad is two). A test build lowers it (test_parse_limit) to
 * reach the limit with a small text. */
#ifndef PARSER_MAX_PRIMITIVES
#define PARSER_MAX_PRIMITIVES SCENE_MAX_PRIMITIVES
#endif

/* Line numbers are ints: even a text of only newlines this long keeps them in range. */
#define MAX_TEXT_BYTES ((size_t)INT_MAX - 1)

#define BIT(key) (1u << (key))

typedef struct token {
    const char *text;
    int length;
    int col;
} token;

/* VALUE_WORD: one of the words listed in the key's `components`, its index the value;
 * VALUE_PATH: one token, a file's path (parser_path reads it from value_token). */
typedef enum value_kind {
    VALUE_NUMBER,
    VALUE_INTEGER,
    VALUE_SWITCH,
    VALUE_WORD,
    VALUE_PATH
} value_kind;

typedef struct key_spec {
    const char *name;
    const char *components; /* "x y z" or "r g b" for three numbers, NULL for one value; the
                             * words of a VALUE_WORD */
    value_kind kind;
    double min, max;    /* inclusive range of every value */
    bool min_exclusive; /* min itself is invalid: radius, plane sizes */
} key_spec;

/* The values of one directive line, indexed like its key_spec table. */
typedef struct key_values {
    unsigned given;            /* bit i set: key i appeared */
    int key_token[MAX_KEYS];   /* index in parser.tokens, for errors found after parsing */
    double value[MAX_KEYS][3]; /* numbers already rounded to float; integers exact; on = 1 */
    int value_token[MAX_KEYS][3];
} key_values;

/* A mesh line's bounding box after its transform, for --verbose and the out-of-view warning
 * (scene_view.c), which need the camera and plane, given on any line. */
typedef struct mesh_view {
    int line, col; /* of the mesh line's file value */
    size_t faces;
    /* A file whose nodes share meshes (scene_mesh_nodes.c): the faces placed once, the shared
     * meshes' faces (kept once), how many such meshes and their instances (0 without). */
    size_t once, shared;
    int shared_meshes, instances;
    vec3 lo, hi;
    char path[SCENE_INPUT_PATH];
} mesh_view;

typedef struct parser {
    const char *text;
    size_t length;
    const char *filename;
    scene_error *err;
    int line;
    token tokens[MAX_TOKENS];
    int token_count;
    scene s;
    size_t sphere_capacity, triangle_capacity, light_capacity, material_capacity, normals_capacity;
    /* line of the first camera, plane, background and render directive; 0 while unseen */
    int camera_line, plane_line, background_line, render_line;
    int camera_col;        /* of the camera position, for the near-clip warning */
    int fov_line, fov_col; /* of the camera's fov, 0 without one */
    int roulette_col;      /* of render's roulette key, 0 without one (on render_line) */
    int light_samples_col; /* of render's light_samples key, the same */
    int indirect_col;      /* of render's indirect key, the same */
    bool tiny_warned;
    int emission_line, emission_col; /* the first emission (sphere or face): report mode refuses */
    /* The first Phong material whose max(color) + ks is above 1 (a line's or a file's), said in
     * path mode once the whole text is read: its line, column and description. */
    int bright_line, bright_col;
    char bright_what[320];
    int mode_given; /* the render's mode from the command line; -1: the scene's */
    /* A chunk parsed ahead: any directive but sphere, triangle and quad stops it. */
    bool primitives_only;
    /* A model's own textures: one that cannot be read is a warning, its map dropped. */
    bool textures_optional;
    struct mesh_cache *meshes;  /* the models mesh lines loaded (mesh_cache.c), NULL before one */
    struct mesh_placed *placed; /* the mesh lines' models, for instances (scene_instance.c) */
    size_t placed_count;
    mesh_view *views; /* the mesh lines' boxes, in order (parser_note_mesh); freed by the parse */
    size_t view_count, view_capacity;
    char number[SCENE_MAX_LINE + 1];      /* a token NUL-terminated for strtod */
    char quoted[2][MAX_QUOTED_CHARS + 4]; /* two, so one message can quote two tokens */
    int quoted_next;
} parser;

/* Records the first error at column col of the current line; always returns false, so that
 * callers can `return parser_fail(...)`. */
bool parser_fail(parser *p, int col, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
/* Records a warning at line:col for the CLI to print (past SCENE_MAX_WARNINGS, dropped). */
void parser_warn(parser *p, int line, int col, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* The token as a message quotes it, long ones cut; two stay valid at once. */
const char *parser_quote(parser *p, const token *t);
/* Whether the token is the word. */
bool parser_token_is(const token *t, const char *word);
/* The column just after the line's last token (where a missing value was expected). */
int parser_end_col(const parser *p);
/* Warns of a surface the camera's near clip may cut away, or a sphere or face too big to place
 * near the camera (scene_near_clip.c); the scene's camera and primitives are final. */
void parser_warn_near_clip(parser *p);
/* The largest |coordinate| of v, at least 1: what the ray offset TZ_EPS is scaled by there. */
float parser_largest_coordinate(vec3 v);
/* Keeps a mesh line's box (its file value at col, its faces, its path) for parser_report_meshes;
 * false (reported) out of memory. */
bool parser_note_mesh(parser *p, int col, size_t faces, vec3 lo, vec3 hi, const char *path);
/* Notes of the last mesh line noted that `once` of its faces are placed once and that
 * `shared_meshes` meshes of `shared` faces are kept once, placed by `instances` instances. */
void parser_note_mesh_nodes(parser *p, size_t once, size_t shared, int shared_meshes,
                            int instances);
/* Prints each mesh's box (--verbose) and warns of the first mesh wholly outside the camera's
 * view (scene_view.c); the scene's camera and plane are final. */
void parser_report_meshes(parser *p);
/* Reads key k's value(s) from token *next on, advancing *next; false (reported) on a bad value. */
bool parser_values(parser *p, const key_spec *k, int *next, double value[3], int value_token[3]);
/* Reads `key value...` pairs from token first to the end of the line into kv, the keys of
 * `accepted` only; owner (and word, when not NULL) name the directive in messages. False
 * (reported) on an unknown key, a key given twice or a bad value. */
bool parser_keys_of(parser *p, const char *owner, const char *word, const key_spec *keys,
                    int key_count, unsigned accepted, int first, key_values *kv);
/* parser_keys_of for a directive named by owner alone. */
bool parser_keys(parser *p, const char *owner, const key_spec *keys, int key_count,
                 unsigned accepted, int first, key_values *kv);
/* False (reported at the directive word) when a key of `required` is missing. */
bool parser_require_keys(parser *p, const char *owner, const key_spec *keys, int key_count,
                         unsigned required, const key_values *kv);
/* Key's three values, or fallback when not given. */
vec3 parser_vec3(const key_values *kv, int key, vec3 fallback);
/* Key's value, or fallback when not given. */
double parser_value_or(const key_values *kv, int key, double fallback);
/* The path token t names into out: a bare word as it is, a quoted one ("my bunny.ply") without
 * its quotes and escapes; false (reported) when it is empty or does not fit size. */
bool parser_path(parser *p, const token *t, char *out, size_t size);
/* Splits one line (without its '\n') into p->tokens; false (reported) on bytes that cannot be
 * scene text, or a quoted path not closed on its line. */
bool parser_tokenize(parser *p, const char *line, size_t length);
/* Parses the directive of the tokenized line p->tokens into p->s; false (reported) on any error,
 * or unreported for a chunk parsed ahead (primitives_only) meeting another directive. */
bool parser_directive(parser *p);
/* Parses one line, without its '\n' (a CR left before it counts as the line ending); false
 * (reported) on an error. */
bool parser_line(parser *p, const char *line, size_t length);
/* A scene before its first directive. */
scene parser_scene_defaults(void);
/* Parses text on up to threads threads (0: one per core) for a render in mode (-1: the scene's
 * own mode) into *out, written only on success; false (reported in *err) on any error. */
bool parser_run(const char *text, size_t length, const char *filename, int threads, int mode,
                scene *out, scene_error *err);
/* parser_run with the models of cache (mesh_cache.h) already loaded, which it releases. */
bool parser_run_cached(const char *text, size_t length, const char *filename, int mode,
                       struct mesh_cache *cache, scene *out, scene_error *err);

#endif
