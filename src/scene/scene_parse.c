/* scene_parse.c: the scene file tokenizer and parser (DESIGN section 2), from a string or a file.
 *
 * One pass over the text, one line at a time: each line is split into tokens (pointers into the
 * text, no copies), its directive is parsed into a local struct scene, and the first error stops
 * everything with file:line:col. The caller's scene is written only on success.
 *
 * Big texts are cut into chunks at line ends. The first chunk is parsed in order on the calling
 * thread while the others are parsed at the same time, a chunk at a time by whichever thread is
 * free, on the guess that they hold only spheres, comments and blank lines. A chunk that does parse
 * so is appended as if read in order; any other (another directive, an error, too many spheres) is
 * parsed again in order, so messages, warnings and which error comes first are those of one pass.
 */
#include <errno.h>
#include <fcntl.h>
#include <float.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene/decimal.h"
#include "scene/scene.h"
#include "shared_layout.h"

/* Line numbers are ints: even a text of only newlines this long keeps them in range. */
#define MAX_TEXT_BYTES ((size_t)INT_MAX - 1)
/* A line of SCENE_MAX_LINE bytes holds at most this many space-separated tokens. */
#define MAX_TOKENS (SCENE_MAX_LINE / 2 + 1)
/* Characters of a bad token quoted back in an error message. */
#define MAX_QUOTED_CHARS 60
/* Keys per directive: the sphere has the most (center radius color ks alpha ior emission). */
#define MAX_KEYS 7
/* |cross(direction, up)| below this fraction of |direction| |up| leaves the camera frame
 * undefined in single precision (about 0.006 degrees). */
#define CAMERA_MIN_SINE 1e-4
/* The seed's rule: plane size / pixel size within this relative distance of an integer. */
#define PIXEL_TOLERANCE 1e-6
/* Chunks are no shorter than this: a chunk costs a parser and a copy of its spheres. */
#define MIN_CHUNK_BYTES (256 * 1024)
/* Threads a parse uses at most. */
#define MAX_PARSE_THREADS 16
/* Chunks per thread: several, so that a thread that gets a core late (the host is shared) holds
 * up the others by one small chunk at most. */
#define CHUNKS_PER_THREAD 4
#define MAX_CHUNKS (CHUNKS_PER_THREAD * MAX_PARSE_THREADS)

typedef struct token {
    const char *text;
    int length;
    int col;
} token;

/* VALUE_WORD: one of the words listed in the key's `components`, its index the value. */
typedef enum value_kind { VALUE_NUMBER, VALUE_INTEGER, VALUE_SWITCH, VALUE_WORD } value_kind;

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

typedef struct parser {
    const char *text;
    size_t length;
    const char *filename;
    scene_error *err;
    int line;
    token tokens[MAX_TOKENS];
    int token_count;
    scene s;
    size_t sphere_capacity, light_capacity;
    /* line of the first camera, plane, background and render directive; 0 while unseen */
    int camera_line, plane_line, background_line, render_line;
    int camera_col; /* of the camera position, for the near-clip warning */
    bool tiny_warned;
    int emission_line, emission_col; /* the first sphere's emission, an error in seed mode */
    bool spheres_only;               /* a chunk parsed ahead: any directive but sphere stops it */
    char number[SCENE_MAX_LINE + 1]; /* a token NUL-terminated for strtod */
    char quoted[2][MAX_QUOTED_CHARS + 4]; /* two, so one message can quote two tokens */
    int quoted_next;
} parser;

#define NO_RANGE -FLT_MAX, FLT_MAX, false
#define UNIT_RANGE 0.0, 1.0, false
/* Plane sizes: ray directions are normalized from vectors of about this length, whose squares
 * must neither overflow nor vanish in float. */
#define PLANE_RANGE 1e-12, 1e12, false
/* Positions and radii: the renderer squares their differences in float, which overflows past
 * about 1.8e19 (a sphere of radius 2e19 vanished). */
#define COORD_RANGE -1e18, 1e18, false
#define RADIUS_RANGE 0.0, 1e18, true
/* Horizontal field of view in degrees: (0, 179] (180 puts the plane at zero distance). */
#define FOV_RANGE 0.0, 179.0, true

enum {
    CAMERA_POSITION,
    CAMERA_DIRECTION,
    CAMERA_UP,
    CAMERA_LOOK_AT,
    CAMERA_FOV,
    CAMERA_NEAR,
    CAMERA_KEY_COUNT
};
static const key_spec camera_keys[CAMERA_KEY_COUNT] = {
    {"position", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"direction", "x y z", VALUE_NUMBER, NO_RANGE},
    {"up", "x y z", VALUE_NUMBER, NO_RANGE},
    {"look_at", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"fov", NULL, VALUE_NUMBER, FOV_RANGE},
    {"near", NULL, VALUE_NUMBER, 0.0, 1e18, false},
};

enum { PLANE_WIDTH, PLANE_HEIGHT, PLANE_PIXEL, PLANE_KEY_COUNT };
static const key_spec plane_keys[PLANE_KEY_COUNT] = {
    {"width", NULL, VALUE_NUMBER, PLANE_RANGE},
    {"height", NULL, VALUE_NUMBER, PLANE_RANGE},
    {"pixel", NULL, VALUE_NUMBER, PLANE_RANGE},
};

enum { LIGHT_POSITION, LIGHT_POWER, LIGHT_COLOR, LIGHT_KEY_COUNT };
static const key_spec light_keys[LIGHT_KEY_COUNT] = {
    {"position", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"power", NULL, VALUE_NUMBER, 0.0, FLT_MAX, false},
    {"color", "r g b", VALUE_NUMBER, UNIT_RANGE},
};

enum {
    SPHERE_CENTER,
    SPHERE_RADIUS,
    SPHERE_COLOR,
    SPHERE_KS,
    SPHERE_ALPHA,
    SPHERE_IOR,
    SPHERE_EMISSION,
    SPHERE_KEY_COUNT
};
static const key_spec sphere_keys[SPHERE_KEY_COUNT] = {
    {"center", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"radius", NULL, VALUE_NUMBER, RADIUS_RANGE},
    {"color", "r g b", VALUE_NUMBER, UNIT_RANGE},
    {"ks", NULL, VALUE_NUMBER, UNIT_RANGE},
    {"alpha", NULL, VALUE_NUMBER, 0.0, FLT_MAX, false},
    {"ior", NULL, VALUE_NUMBER, 1.0, FLT_MAX, false},
    {"emission", "r g b", VALUE_NUMBER, 0.0, FLT_MAX, false},
};
_Static_assert(SPHERE_KEY_COUNT <= MAX_KEYS, "raise MAX_KEYS");

#define BIT(key) (1u << (key))
#define SPHERE_COMMON_KEYS \
    (BIT(SPHERE_CENTER) | BIT(SPHERE_RADIUS) | BIT(SPHERE_COLOR) | BIT(SPHERE_EMISSION))

typedef struct material_spec {
    const char *word;
    material_kind kind;
    unsigned keys; /* bits of sphere_keys this material accepts */
    float default_color;
} material_spec;

static const material_spec materials[] = {
    {"lambertian", MATERIAL_LAMBERTIAN, SPHERE_COMMON_KEYS, 0.8f},
    {"phong", MATERIAL_PHONG, SPHERE_COMMON_KEYS | BIT(SPHERE_KS) | BIT(SPHERE_ALPHA), 0.8f},
    {"mirror", MATERIAL_MIRROR, SPHERE_COMMON_KEYS, 1.0f},
    {"refractive", MATERIAL_REFRACTIVE, SPHERE_COMMON_KEYS | BIT(SPHERE_IOR), 1.0f},
    /* the seed's Spanish names */
    {"lambertiana", MATERIAL_LAMBERTIAN, SPHERE_COMMON_KEYS, 0.8f},
    {"espejo", MATERIAL_MIRROR, SPHERE_COMMON_KEYS, 1.0f},
    {"refractada", MATERIAL_REFRACTIVE, SPHERE_COMMON_KEYS | BIT(SPHERE_IOR), 1.0f},
};

enum {
    RENDER_SAMPLES,
    RENDER_INDIRECT,
    RENDER_BOUNCES,
    RENDER_SEED,
    RENDER_MODE,
    RENDER_ROULETTE,
    RENDER_KEY_COUNT
};
/* The words of `render mode`, in render_mode order. */
#define RENDER_MODE_WORDS "seed path"
static const key_spec render_keys[RENDER_KEY_COUNT] = {
    {"samples", NULL, VALUE_INTEGER, 1.0, SCENE_MAX_SAMPLES, false},
    {"indirect", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    {"bounces", NULL, VALUE_INTEGER, 0.0, SCENE_MAX_BOUNCES, false},
    {"seed", NULL, VALUE_INTEGER, 0.0, UINT32_MAX, false},
    {"mode", RENDER_MODE_WORDS, VALUE_WORD, 0.0, 1.0, false},
    {"roulette", NULL, VALUE_SWITCH, 0.0, 1.0, false},
};

/* background takes three numbers and no key; this spec names them in messages. */
static const key_spec background_spec = {"background", "r g b", VALUE_NUMBER, 0.0, FLT_MAX, false};

/* Records the first error; always returns false so callers can `return fail_at(...)`. */
static bool fail_at(parser *p, int col, const char *fmt, ...) __attribute__((format(printf, 3, 4)));
static bool fail_at(parser *p, int col, const char *fmt, ...) {
    if (p->err) {
        snprintf(p->err->file, sizeof p->err->file, "%s", p->filename);
        p->err->line = p->line;
        p->err->col = col;
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(p->err->message, sizeof p->err->message, fmt, ap);
        va_end(ap);
    }
    return false;
}

/* Records a warning at line:col of the scene, for the CLI to print (past SCENE_MAX_WARNINGS,
 * dropped). */
static void warn_at(parser *p, int line, int col, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void warn_at(parser *p, int line, int col, const char *fmt, ...) {
    if (p->s.warning_count == SCENE_MAX_WARNINGS) return;
    scene_error *w = &p->s.warnings[p->s.warning_count++];
    snprintf(w->file, sizeof w->file, "%s", p->filename);
    w->line = line;
    w->col = col;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(w->message, sizeof w->message, fmt, ap);
    va_end(ap);
}

/* The token as it should appear in a message; long tokens are cut so the message stays readable. */
static const char *quote(parser *p, const token *t) {
    char *out = p->quoted[p->quoted_next];
    p->quoted_next ^= 1;
    int n = t->length < MAX_QUOTED_CHARS ? t->length : MAX_QUOTED_CHARS;
    memcpy(out, t->text, (size_t)n);
    strcpy(out + n, t->length > n ? "..." : "");
    return out;
}

static bool token_is(const token *t, const char *word) {
    size_t n = strlen(word);
    return (size_t)t->length == n && memcmp(t->text, word, n) == 0;
}

/* Where a value missing at the end of the line was expected: just after the last token. */
static int end_col(const parser *p) {
    const token *last = &p->tokens[p->token_count - 1];
    return last->col + last->length;
}

static bool is_digit(char c) { return c >= '0' && c <= '9'; }

/* [+-]?(digits[.digits*]|.digits)([eE][+-]?digits)? and nothing else: no nan, inf or hex. */
static bool is_decimal(const char *s, int n) {
    int i = 0, digits = 0;
    if (i < n && (s[i] == '+' || s[i] == '-')) i++;
    for (; i < n && is_digit(s[i]); i++) digits++;
    if (i < n && s[i] == '.') {
        for (i++; i < n && is_digit(s[i]); i++) digits++;
    }
    if (digits == 0) return false;
    if (i < n && (s[i] == 'e' || s[i] == 'E')) {
        i++;
        if (i < n && (s[i] == '+' || s[i] == '-')) i++;
        int exponent_digits = 0;
        for (; i < n && is_digit(s[i]); i++) exponent_digits++;
        if (exponent_digits == 0) return false;
    }
    return i == n;
}

/* Case-insensitive match of the words strtod would take for NaN or an infinity. */
static bool is_nonfinite_word(const token *t) {
    const char *s = t->text;
    int n = t->length;
    if (n > 0 && (s[0] == '+' || s[0] == '-')) {
        s++;
        n--;
    }
    static const char *const words[] = {"nan", "inf", "infinity"};
    for (size_t w = 0; w < sizeof words / sizeof words[0]; w++) {
        if ((size_t)n == strlen(words[w]) && strncasecmp(s, words[w], (size_t)n) == 0) return true;
    }
    return false;
}

/* The largest |coordinate| of v, at least 1: what the ray offset TZ_EPS is scaled by there. */
static float largest_coordinate(vec3 v) { return fmaxf(v3_max_abs(v), 1.0f); }

static bool fail_range(parser *p, const key_spec *k, const token *t) {
    if (k->kind == VALUE_INTEGER) {
        return fail_at(p, t->col, "%s must be an integer in [%.0f, %.0f], got %s", k->name, k->min,
                       k->max, quote(p, t));
    }
    if (k->min_exclusive) {
        return fail_at(p, t->col, "%s must be in (%g, %g], got %s", k->name, k->min, k->max,
                       quote(p, t));
    }
    if (k->max < FLT_MAX) {
        return fail_at(p, t->col, "%s must be in [%g, %g], got %s", k->name, k->min, k->max,
                       quote(p, t));
    }
    return fail_at(p, t->col, "%s must be >= %g, got %s", k->name, k->min, quote(p, t));
}

static bool parse_number(parser *p, const key_spec *k, const token *t, double *out) {
    if (!is_decimal(t->text, t->length)) {
        const char *why = "";
        if (is_nonfinite_word(t)) why = " (NaN and infinities are not allowed)";
        if (t->length > 2 && t->text[0] == '0' && (t->text[1] == 'x' || t->text[1] == 'X')) {
            why = " (hexadecimal numbers are not allowed)";
        }
        return fail_at(p, t->col, "expected a number for '%s', got '%s'%s", k->name, quote(p, t),
                       why);
    }
    double d;
    if (!decimal_fast(t->text, t->length, &d)) {
        memcpy(p->number, t->text, (size_t)t->length);
        p->number[t->length] = '\0';
        d = strtod(p->number, NULL);
    }
    if (!(fabs(d) <= FLT_MAX)) {
        return fail_at(p, t->col, "number '%s' for '%s' is out of range (magnitude above %g)",
                       quote(p, t), k->name, FLT_MAX);
    }
    /* Check the float the renderer will see, so 1e-50 is a zero radius, not a tiny one. */
    float f = (float)d;
    float min = (float)k->min, max = (float)k->max; /* as written: "1e-12" is in [1e-12, ..] */
    if (f < min || f > max || (k->min_exclusive && f == min)) return fail_range(p, k, t);
    *out = f;
    return true;
}

static bool parse_integer(parser *p, const key_spec *k, const token *t, double *out) {
    const char *s = t->text;
    int n = t->length, i = 0;
    bool negative = false;
    if (n > 0 && (s[0] == '+' || s[0] == '-')) negative = s[i++] == '-';
    if (i == n) {
        return fail_at(p, t->col, "expected an integer for '%s', got '%s'", k->name, quote(p, t));
    }
    /* Saturating: anything past 10^12 is out of every integer range. */
    double value = 0.0;
    for (; i < n; i++) {
        if (!is_digit(s[i])) {
            return fail_at(p, t->col, "expected an integer for '%s', got '%s'", k->name,
                           quote(p, t));
        }
        if (value < 1e12) value = value * 10.0 + (s[i] - '0');
    }
    if (negative) value = -value;
    if (value < k->min || value > k->max) return fail_range(p, k, t);
    *out = value;
    return true;
}

static bool parse_switch(parser *p, const key_spec *k, const token *t, double *out) {
    if (token_is(t, "on") || token_is(t, "off")) {
        *out = token_is(t, "on");
        return true;
    }
    return fail_at(p, t->col, "expected on or off for '%s', got '%s'", k->name, quote(p, t));
}

/* One of the space-separated words of k->components; the value is its index. */
static bool parse_word(parser *p, const key_spec *k, const token *t, double *out) {
    const char *w = k->components;
    for (int index = 0; *w; index++) {
        size_t n = strcspn(w, " ");
        if ((size_t)t->length == n && memcmp(t->text, w, n) == 0) {
            *out = index;
            return true;
        }
        w += n + (w[n] == ' ');
    }
    return fail_at(p, t->col, "expected one of %s for '%s', got '%s'", k->components, k->name,
                   quote(p, t));
}

/* Parses the value(s) of key k from token *next on; advances *next past them. */
static bool parse_values(parser *p, const key_spec *k, int *next, double value[3],
                         int value_token[3]) {
    int count = k->components && k->kind != VALUE_WORD ? 3 : 1;
    for (int c = 0; c < count; c++) {
        if (*next >= p->token_count) {
            if (count == 1) {
                return fail_at(p, end_col(p), "expected a value for '%s', got end of line",
                               k->name);
            }
            return fail_at(p, end_col(p), "expected 3 numbers (%s) for '%s', got %d", k->components,
                           k->name, c);
        }
        value_token[c] = *next;
        const token *t = &p->tokens[(*next)++];
        bool ok = k->kind == VALUE_NUMBER    ? parse_number(p, k, t, &value[c])
                  : k->kind == VALUE_INTEGER ? parse_integer(p, k, t, &value[c])
                  : k->kind == VALUE_SWITCH  ? parse_switch(p, k, t, &value[c])
                                             : parse_word(p, k, t, &value[c]);
        if (!ok) return false;
    }
    return true;
}

/* Parses `key value...` pairs from token `first` to the end of the line into *kv.
 * `accepted` masks which keys of `keys` this directive (or material) takes; messages name the
 * owner, followed by word unless it is NULL (formatted only for a message: spheres are many). */
static bool parse_keys_of(parser *p, const char *owner, const char *word, const key_spec *keys,
                          int key_count, unsigned accepted, int first, key_values *kv) {
    memset(kv, 0, sizeof *kv);
    int next = first;
    while (next < p->token_count) {
        const token *t = &p->tokens[next++];
        int key = 0;
        while (key < key_count && !((accepted & BIT(key)) && token_is(t, keys[key].name))) key++;
        if (key == key_count) {
            char list[128] = "";
            for (int k = 0; k < key_count; k++) {
                if (!(accepted & BIT(k))) continue;
                if (list[0]) strcat(list, " ");
                strcat(list, keys[k].name);
            }
            return fail_at(p, t->col, "unknown key '%s' for %s%s%s (expected one of: %s)",
                           quote(p, t), owner, word ? " " : "", word ? word : "", list);
        }
        if (kv->given & BIT(key)) return fail_at(p, t->col, "'%s' given twice", keys[key].name);
        kv->given |= BIT(key);
        kv->key_token[key] = next - 1;
        if (!parse_values(p, &keys[key], &next, kv->value[key], kv->value_token[key])) {
            return false;
        }
    }
    return true;
}

static bool parse_keys(parser *p, const char *owner, const key_spec *keys, int key_count,
                       unsigned accepted, int first, key_values *kv) {
    return parse_keys_of(p, owner, NULL, keys, key_count, accepted, first, kv);
}

/* Checks that every key in `required` was given; the error points at the directive word. */
static bool require_keys(parser *p, const char *owner, const key_spec *keys, int key_count,
                         unsigned required, const key_values *kv) {
    for (int k = 0; k < key_count; k++) {
        if ((required & BIT(k)) && !(kv->given & BIT(k))) {
            return fail_at(p, p->tokens[0].col, "%s is missing required key '%s'", owner,
                           keys[k].name);
        }
    }
    return true;
}

static vec3 value_vec3(const key_values *kv, int key, vec3 fallback) {
    if (!(kv->given & BIT(key))) return fallback;
    return v3((float)kv->value[key][0], (float)kv->value[key][1], (float)kv->value[key][2]);
}

static double value_or(const key_values *kv, int key, double fallback) {
    return (kv->given & BIT(key)) ? kv->value[key][0] : fallback;
}

/* camera, plane, background and render describe the whole image: one of each at most. */
static bool claim_once(parser *p, int *first_line) {
    if (*first_line) {
        return fail_at(p, p->tokens[0].col, "'%s' given twice (first on line %d)",
                       quote(p, &p->tokens[0]), *first_line);
    }
    *first_line = p->line;
    return true;
}

/* The renderer normalizes in float by the square root of the squared length: that square must
 * be a normal float, or the vector comes out too short (a denormal square) or zero (an infinite
 * one). */
static bool check_camera_square(parser *p, const key_values *kv, int key, vec3 v) {
    float square = v3_dot(v, v);
    if (!(square >= FLT_MIN && square <= FLT_MAX)) {
        return fail_at(p, p->tokens[kv->key_token[key]].col,
                       "camera %s is too small or too large to normalize in single precision "
                       "(its length must be from about 1.1e-19 to 1.8e19)",
                       camera_keys[key].name);
    }
    return true;
}

static bool check_camera_vector(parser *p, const key_values *kv, int key, vec3 v) {
    if (v.x == 0.0f && v.y == 0.0f && v.z == 0.0f) {
        return fail_at(p, p->tokens[kv->key_token[key]].col, "camera %s must not be zero",
                       camera_keys[key].name);
    }
    return check_camera_square(p, kv, key, v);
}

static bool parse_camera(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->camera_line) ||
        !parse_keys(p, "camera", camera_keys, CAMERA_KEY_COUNT, ~0u, 1, &kv) ||
        !require_keys(p, "camera", camera_keys, CAMERA_KEY_COUNT, BIT(CAMERA_POSITION), &kv)) {
        return false;
    }
    vec3 position = value_vec3(&kv, CAMERA_POSITION, v3(0, 0, 0));
    vec3 direction = value_vec3(&kv, CAMERA_DIRECTION, v3(0, 0, 1));
    vec3 up = value_vec3(&kv, CAMERA_UP, v3(0, 1, 0));
    if (kv.given & BIT(CAMERA_LOOK_AT)) {
        if (kv.given & BIT(CAMERA_DIRECTION)) {
            return fail_at(p, p->tokens[kv.key_token[CAMERA_LOOK_AT]].col,
                           "camera takes direction or look_at, not both");
        }
        vec3 at = value_vec3(&kv, CAMERA_LOOK_AT, position);
        /* In double: the difference of two valid coordinates can overflow float. */
        double dx = (double)at.x - position.x, dy = (double)at.y - position.y,
               dz = (double)at.z - position.z;
        double m = fmax(fabs(dx), fmax(fabs(dy), fabs(dz)));
        if (m == 0.0) {
            return fail_at(p, p->tokens[kv.key_token[CAMERA_LOOK_AT]].col,
                           "camera look_at must differ from position");
        }
        direction = v3((float)(dx / m), (float)(dy / m), (float)(dz / m));
    }
    if (!check_camera_vector(p, &kv, CAMERA_DIRECTION, direction) ||
        !check_camera_vector(p, &kv, CAMERA_UP, up)) {
        return false;
    }
    /* Double precision on unit vectors, so the test cannot itself overflow or underflow. */
    double dl = v3_length(direction), ul = v3_length(up);
    double dx = direction.x / dl, dy = direction.y / dl, dz = direction.z / dl;
    double ux = up.x / ul, uy = up.y / ul, uz = up.z / ul;
    double cx = dy * uz - dz * uy, cy = dz * ux - dx * uz, cz = dx * uy - dy * ux;
    /* Errors of the frame are reported at up, else at what gave the direction. */
    int up_key = (kv.given & BIT(CAMERA_UP))        ? CAMERA_UP
                 : (kv.given & BIT(CAMERA_LOOK_AT)) ? CAMERA_LOOK_AT
                                                    : CAMERA_DIRECTION;
    if (sqrt(cx * cx + cy * cy + cz * cz) < CAMERA_MIN_SINE) {
        return fail_at(p, p->tokens[kv.key_token[up_key]].col,
                       "camera up (%g %g %g) is parallel to direction (%g %g %g)", up.x, up.y, up.z,
                       direction.x, direction.y, direction.z);
    }
    /* The right vector, up x forward, is normalized too: a small up at a small angle. */
    if (!check_camera_square(p, &kv, up_key, v3_cross(up, v3_normalize(direction)))) return false;
    p->s.camera_position = position;
    p->s.camera_fov = (float)value_or(&kv, CAMERA_FOV, 0.0);
    p->s.camera_near = (float)value_or(&kv, CAMERA_NEAR, 0.0);
    p->camera_col = p->tokens[kv.value_token[CAMERA_POSITION][0]].col;
    p->s.camera_direction = direction;
    p->s.camera_up = up;
    return true;
}

/* Pixels across `size`, or 0 when pixel does not divide it within the seed's tolerance. */
static long whole_pixels(double size, float pixel) {
    double ratio = size / pixel;
    double n = nearbyint(ratio);
    if (n < 1.0 || n > SCENE_MAX_RESOLUTION || fabs(ratio - n) > PIXEL_TOLERANCE * ratio) return 0;
    return (long)n;
}

/* Writes the shortest decimal form of `pixel` that, read back as the parser reads it, still
 * divides `side` into `count` pixels and (when other_count > 0) `other` into other_count, so a
 * suggested value can be pasted as is and gives the counts printed beside it. */
static void format_pixel(char *out, size_t size, double pixel, double side, long count,
                         double other, long other_count) {
    for (int digits = 1; digits <= DBL_DIG + 2; digits++) {
        snprintf(out, size, "%.*g", digits, pixel);
        float f = (float)strtod(out, NULL);
        if (f > 0 && whole_pixels(side, f) == count &&
            (other_count <= 0 || whole_pixels(other, f) == other_count))
            return;
    }
}

/* Appends to a message, dropping what does not fit. */
static void append(char *message, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static void append(char *message, size_t size, const char *fmt, ...) {
    size_t used = strlen(message);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(message + used, size - used, fmt, ap);
    va_end(ap);
}

/* The error for a pixel size that does not divide one side of the plane: it names the side and
 * proposes the nearest pixel sizes that divide it, and one that divides both sides if any. */
static bool fail_pixel(parser *p, const key_values *kv, int side, const token *size_token,
                       const token *pixel_token) {
    double size = kv->value[side][0], other = kv->value[side ^ 1][0];
    float pixel = (float)kv->value[PLANE_PIXEL][0];
    double ratio = size / pixel;
    char message[sizeof p->err->message] = "";
    append(message, sizeof message, "plane %s %s is not a whole number of pixels of %s (%.2f); ",
           plane_keys[side].name, quote(p, size_token), quote(p, pixel_token), ratio);
    /* The two pixel counts around the ratio, when they are valid resolutions. */
    long counts[2] = {(long)floor(ratio), (long)floor(ratio) + 1};
    char text[2][32];
    int found = 0;
    for (int i = 0; i < 2; i++) {
        if (counts[i] < 1 || counts[i] > SCENE_MAX_RESOLUTION) continue;
        format_pixel(text[found], sizeof text[found], size / counts[i], size, counts[i], 0, 0);
        counts[found++] = counts[i];
    }
    if (found == 1) {
        append(message, sizeof message, "the nearest pixel size that divides it is %s (%ld px)",
               text[0], counts[0]);
    } else {
        append(message, sizeof message,
               "nearest pixel sizes that divide it: %s (%ld px), %s (%ld px)", text[0], counts[0],
               text[1], counts[1]);
    }
    /* A pixel size that divides both sides, closest to the one asked for; a short search that
     * only runs on this error path. */
    long best = 0;
    double best_distance = INFINITY;
    for (long n = 1; n <= SCENE_MAX_RESOLUTION; n++) {
        float candidate = (float)(size / n);
        double distance = fabs(log(candidate / pixel));
        if (distance < best_distance && whole_pixels(size, candidate) &&
            whole_pixels(other, candidate)) {
            best = n;
            best_distance = distance;
        }
    }
    if (best) {
        char both[32];
        long other_count = whole_pixels(other, (float)(size / best));
        format_pixel(both, sizeof both, size / best, size, best, other, other_count);
        append(message, sizeof message, "; one that divides width and height: %s (%ld x %ld px)",
               both, side == PLANE_WIDTH ? best : other_count,
               side == PLANE_WIDTH ? other_count : best);
    }
    return fail_at(p, pixel_token->col, "%s", message);
}

static bool parse_plane(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->plane_line) ||
        !parse_keys(p, "plane", plane_keys, PLANE_KEY_COUNT, ~0u, 1, &kv) ||
        !require_keys(p, "plane", plane_keys, PLANE_KEY_COUNT, ~0u, &kv)) {
        return false;
    }
    float pixel = (float)kv.value[PLANE_PIXEL][0];
    const token *pixel_token = &p->tokens[kv.value_token[PLANE_PIXEL][0]];
    long pixels[2];
    for (int side = PLANE_WIDTH; side <= PLANE_HEIGHT; side++) {
        const token *size_token = &p->tokens[kv.value_token[side][0]];
        double ratio = kv.value[side][0] / pixel;
        if (ratio >= SCENE_MAX_RESOLUTION + 0.5) {
            return fail_at(p, pixel_token->col,
                           "plane %s %s at pixel %s is %.7g pixels, more than the maximum %d",
                           plane_keys[side].name, quote(p, size_token), quote(p, pixel_token),
                           ratio, SCENE_MAX_RESOLUTION);
        }
        if (ratio < 0.5) {
            return fail_at(p, pixel_token->col, "plane %s %s is less than one pixel of %s",
                           plane_keys[side].name, quote(p, size_token), quote(p, pixel_token));
        }
        pixels[side] = whole_pixels(kv.value[side][0], pixel);
        if (!pixels[side]) return fail_pixel(p, &kv, side, size_token, pixel_token);
    }
    p->s.plane_width = (float)kv.value[PLANE_WIDTH][0];
    p->s.plane_height = (float)kv.value[PLANE_HEIGHT][0];
    p->s.pixel_size = pixel;
    p->s.width = (int)pixels[PLANE_WIDTH];
    p->s.height = (int)pixels[PLANE_HEIGHT];
    return true;
}

/* Grows an array by doubling so a million appends cost a few dozen reallocations. */
static bool grow(parser *p, void **array, size_t *capacity, int count, int max, size_t item,
                 const char *what) {
    if (count >= max) {
        return fail_at(p, p->tokens[0].col, "too many %s (the maximum is %d)", what, max);
    }
    if ((size_t)count < *capacity) return true;
    size_t capacity_new = *capacity ? *capacity * 2 : 64;
    if (capacity_new > (size_t)max) capacity_new = (size_t)max;
    void *grown = realloc(*array, capacity_new * item);
    if (!grown) {
        if (p->err) p->err->out_of_memory = true;
        return fail_at(p, p->tokens[0].col, "out of memory after %d %s", count, what);
    }
    *array = grown;
    *capacity = capacity_new;
    return true;
}

static bool parse_light(parser *p) {
    key_values kv;
    if (!parse_keys(p, "light", light_keys, LIGHT_KEY_COUNT, ~0u, 1, &kv) ||
        !require_keys(p, "light", light_keys, LIGHT_KEY_COUNT,
                      BIT(LIGHT_POSITION) | BIT(LIGHT_POWER), &kv)) {
        return false;
    }
    void *array = p->s.lights;
    bool ok = grow(p, &array, &p->light_capacity, p->s.light_count, SCENE_MAX_LIGHTS, sizeof(light),
                   "lights");
    p->s.lights = array;
    if (!ok) return false;
    p->s.lights[p->s.light_count++] = (light){
        .position = value_vec3(&kv, LIGHT_POSITION, v3(0, 0, 0)),
        .power = (float)value_or(&kv, LIGHT_POWER, 0.0),
        .color = value_vec3(&kv, LIGHT_COLOR, v3(1, 1, 1)),
    };
    return true;
}

static bool parse_sphere(parser *p) {
    if (p->token_count < 2) {
        return fail_at(p, end_col(p),
                       "expected a material after 'sphere' (lambertian, phong, mirror, "
                       "refractive), got end of line");
    }
    const token *word = &p->tokens[1];
    const material_spec *m = NULL;
    for (size_t i = 0; i < sizeof materials / sizeof materials[0] && !m; i++) {
        if (token_is(word, materials[i].word)) m = &materials[i];
    }
    if (!m) {
        return fail_at(p, word->col,
                       "unknown material '%s' for sphere (expected one of: lambertian phong "
                       "mirror refractive, or lambertiana espejo refractada)",
                       quote(p, word));
    }
    key_values kv;
    if (!parse_keys_of(p, "sphere", m->word, sphere_keys, SPHERE_KEY_COUNT, m->keys, 2, &kv) ||
        !require_keys(p, "sphere", sphere_keys, SPHERE_KEY_COUNT,
                      BIT(SPHERE_CENTER) | BIT(SPHERE_RADIUS), &kv)) {
        return false;
    }
    void *array = p->s.spheres;
    bool ok = grow(p, &array, &p->sphere_capacity, p->s.sphere_count, SCENE_MAX_SPHERES,
                   sizeof(sphere), "spheres");
    p->s.spheres = array;
    if (!ok) return false;
    bool phong = m->kind == MATERIAL_PHONG;
    float c = m->default_color;
    p->s.spheres[p->s.sphere_count++] = (sphere){
        .center = value_vec3(&kv, SPHERE_CENTER, v3(0, 0, 0)),
        .radius = (float)value_or(&kv, SPHERE_RADIUS, 0.0),
        .material = m->kind,
        .color = value_vec3(&kv, SPHERE_COLOR, v3(c, c, c)),
        .ks = phong ? (float)value_or(&kv, SPHERE_KS, 0.5) : 0.0f,
        .alpha = phong ? (float)value_or(&kv, SPHERE_ALPHA, 32.0) : 0.0f,
        .ior = (float)value_or(&kv, SPHERE_IOR, m->kind == MATERIAL_REFRACTIVE ? 1.5 : 1.0),
        .emission = value_vec3(&kv, SPHERE_EMISSION, v3(0, 0, 0)),
    };
    if ((kv.given & BIT(SPHERE_EMISSION)) && !p->emission_line) {
        p->emission_line = p->line;
        p->emission_col = p->tokens[kv.key_token[SPHERE_EMISSION]].col;
    }
    const sphere *added = &p->s.spheres[p->s.sphere_count - 1];
    float offset = TZ_EPS * largest_coordinate(added->center);
    if (added->radius < SCENE_TINY_OFFSETS * offset && !p->tiny_warned) {
        p->tiny_warned = true;
        warn_at(p, p->line, p->tokens[kv.value_token[SPHERE_RADIUS][0]].col,
                "radius %g is under %g times the ray offset here (%g: %g times the largest "
                "coordinate, at least %g): rays that enter it start near or past its far side, "
                "so it is shaded wrongly (glass turns black first)",
                (double)added->radius, (double)SCENE_TINY_OFFSETS, (double)offset, (double)TZ_EPS,
                (double)TZ_EPS);
    }
    return true;
}

static bool parse_background(parser *p) {
    if (!claim_once(p, &p->background_line)) return false;
    double value[3];
    int value_token[3], next = 1;
    if (!parse_values(p, &background_spec, &next, value, value_token)) return false;
    if (next < p->token_count) {
        return fail_at(p, p->tokens[next].col, "unexpected '%s' after background's 3 numbers",
                       quote(p, &p->tokens[next]));
    }
    p->s.background = v3((float)value[0], (float)value[1], (float)value[2]);
    return true;
}

static bool parse_render(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->render_line) ||
        !parse_keys(p, "render", render_keys, RENDER_KEY_COUNT, ~0u, 1, &kv)) {
        return false;
    }
    p->s.samples = (int)value_or(&kv, RENDER_SAMPLES, 64);
    p->s.indirect = value_or(&kv, RENDER_INDIRECT, 1) != 0;
    p->s.mode = (render_mode)value_or(&kv, RENDER_MODE, RENDER_MODE_SEED);
    p->s.bounces_given = kv.given & BIT(RENDER_BOUNCES);
    p->s.bounces = (int)value_or(&kv, RENDER_BOUNCES, scene_default_bounces(p->s.mode));
    p->s.seed = (uint32_t)value_or(&kv, RENDER_SEED, 1);
    p->s.roulette = value_or(&kv, RENDER_ROULETTE, 1) != 0;
    return true;
}

typedef struct directive_spec {
    const char *word;
    bool (*parse)(parser *p);
} directive_spec;

static const directive_spec directives[] = {
    {"camera", parse_camera}, {"plane", parse_plane},           {"light", parse_light},
    {"sphere", parse_sphere}, {"background", parse_background}, {"render", parse_render},
};

/* Splits one line (without its '\n') into p->tokens, rejecting bytes that cannot be scene text.
 * Outside comments only printable ASCII, tab and a CR ending the line (whitespace) are allowed;
 * inside a comment anything but NUL, so comments may hold UTF-8. */
static bool tokenize(parser *p, const char *line, size_t length) {
    p->token_count = 0;
    /* Only the last byte may be a CR (CR LF endings), comments included. */
    const char *cr = length > 1 ? memchr(line, '\r', length - 1) : NULL;
    if (cr) {
        return fail_at(p, (int)(cr - line) + 1,
                       "carriage return inside a line (old Mac line endings?): lines end "
                       "in LF or CR LF");
    }
    for (size_t i = 0; i < length;) {
        unsigned char c = (unsigned char)line[i];
        int col = (int)i + 1;
        if (c == '#') {
            const char *nul = memchr(line + i, '\0', length - i);
            if (nul) return fail_at(p, (int)(nul - line) + 1, "NUL byte in a comment");
            break;
        }
        if (c == ' ' || c == '\t' || c == '\r') {
            i++;
            continue;
        }
        if (c < 0x20 || c > 0x7e) {
            if (c == 0) return fail_at(p, col, "unexpected NUL byte (is this a text file?)");
            if (p->line == 1 && i == 0 && length >= 3 && !memcmp(line, "\xef\xbb\xbf", 3))
                return fail_at(p, col,
                               "a UTF-8 byte-order mark (EF BB BF) starts the file: "
                               "save it without one");
            return fail_at(p, col, "unexpected byte 0x%02x (only printable ASCII outside comments)",
                           c);
        }
        size_t start = i;
        while (i < length && line[i] > 0x20 && line[i] < 0x7f && line[i] != '#') i++;
        p->tokens[p->token_count++] = (token){line + start, (int)(i - start), col};
    }
    return true;
}

static bool parse_line(parser *p, const char *line, size_t length) {
    /* A CR before the '\n' belongs to the line ending, not to the line's length. */
    size_t content = length > 0 && line[length - 1] == '\r' ? length - 1 : length;
    if (content > SCENE_MAX_LINE) {
        /* A NUL byte before the limit says more (binary input, /dev/zero): tokenizing those
         * bytes reports it. */
        if (memchr(line, '\0', SCENE_MAX_LINE) && !tokenize(p, line, SCENE_MAX_LINE)) return false;
        return fail_at(p, SCENE_MAX_LINE + 1, "line is longer than %d bytes", SCENE_MAX_LINE);
    }
    if (!tokenize(p, line, length)) return false;
    if (p->token_count == 0) return true;
    const token *word = &p->tokens[0];
    for (size_t i = 0; i < sizeof directives / sizeof directives[0]; i++) {
        if (!token_is(word, directives[i].word)) continue;
        if (p->spheres_only && directives[i].parse != parse_sphere) return false;
        return directives[i].parse(p);
    }
    return fail_at(p, word->col,
                   "unknown directive '%s' (expected one of: camera plane light sphere "
                   "background render)",
                   quote(p, word));
}

/* The spacing of floats around magnitude m (m > 0). */
static double float_step(double m) { return ldexp(1.0, ilogb(m) - 23); }

/* Camera rays start TZ_EPS times the camera's largest |coordinate| (at least 1) along their path,
 * as every ray does from its origin (DESIGN section 3): far from the origin that is a near clip
 * (10 units at 1e5). Warns when a sphere not wholly behind the camera has its surface within
 * SCENE_NEAR_CLIP_FACTOR times that distance of the camera: it may be cut away. Warns instead
 * when a sphere is so big that its surface near the camera is within SCENE_PRECISION_STEPS of
 * the float spacing at its size, and that is coarser than the near clip: single precision cannot
 * place that surface (a floor of radius 3e7 one unit under the camera renders black). */
static void warn_near_surfaces(parser *p) {
    vec3 cam = p->s.camera_position, f = p->s.camera_direction;
    double f_length = sqrt((double)f.x * f.x + (double)f.y * f.y + (double)f.z * f.z);
    float big = largest_coordinate(cam);
    double offset = (double)TZ_EPS * big, nearest = INFINITY, worst = 1.0, step = 0.0;
    int which = -1, coarse = -1;
    for (int k = 0; k < p->s.sphere_count; k++) {
        const sphere *s = &p->s.spheres[k];
        double dx = (double)s->center.x - cam.x, dy = (double)s->center.y - cam.y,
               dz = (double)s->center.z - cam.z;
        double ahead = (dx * f.x + dy * f.y + dz * f.z) / f_length;
        if (ahead < -(double)s->radius) continue; /* wholly behind the camera */
        double distance = sqrt(dx * dx + dy * dy + dz * dz), gap = fabs(distance - s->radius);
        if (gap < nearest) nearest = gap, which = k;
        /* only where precision, not the near clip, is the coarser limit */
        double sk = float_step(fmax(distance, s->radius)), blur = SCENE_PRECISION_STEPS * sk;
        if (blur > SCENE_NEAR_CLIP_FACTOR * offset && gap / blur < worst)
            worst = gap / blur, coarse = k, step = sk;
    }
    if (coarse >= 0) {
        const sphere *s = &p->s.spheres[coarse];
        warn_at(p, p->camera_line, p->camera_col,
                "sphere %d (centre %g %g %g, radius %g) is too big for its surface to lie this "
                "near the camera: at its size single-precision positions are %g apart, and its "
                "surface is less than %g such steps from the camera, so it may be misplaced, "
                "black or missing; use a smaller sphere (a floor of radius 1e4 looks as flat) "
                "or move the camera away",
                coarse + 1, (double)s->center.x, (double)s->center.y, (double)s->center.z,
                (double)s->radius, step, (double)SCENE_PRECISION_STEPS);
        return;
    }
    if (which < 0 || nearest >= SCENE_NEAR_CLIP_FACTOR * offset) return;
    const sphere *s = &p->s.spheres[which];
    warn_at(p, p->camera_line, p->camera_col,
            "camera rays start %g along their path%s, and sphere %d (centre %g %g %g, radius %g) "
            "has its surface %g from the camera: it may be cut away%s",
            offset, big > 1.0f ? " this far from the origin (the ray offset grows with it)" : "",
            which + 1, (double)s->center.x, (double)s->center.y, (double)s->center.z,
            (double)s->radius, nearest, big > 1.0f ? "; move the scene nearer the origin" : "");
}

/* Parses the lines of [text, end), counting them in p->line. */
static bool parse_lines(parser *p, const char *text, const char *end) {
    while (text < end) {
        const char *newline = memchr(text, '\n', (size_t)(end - text));
        const char *line_end = newline ? newline : end;
        if (!parse_line(p, text, (size_t)(line_end - text))) return false;
        if (!newline) break;
        text = newline + 1;
        p->line++;
    }
    return true;
}

/* A chunk of the text parsed ahead on its own thread, its lines counted from 1. */
typedef struct chunk {
    const char *begin, *end;
    parser *p; /* NULL: no memory for it, parse it in order */
    bool ok;   /* every line was a sphere, a comment or blank, and parsed */
} chunk;

typedef struct chunk_list {
    chunk *chunks;
    int count;
    atomic_int next; /* the next chunk to parse ahead */
} chunk_list;

/* Parses chunks ahead, taken from the shared list, until none is left. */
static void *chunks_run(void *arg) {
    chunk_list *l = arg;
    for (;;) {
        int k = atomic_fetch_add(&l->next, 1);
        if (k >= l->count) return NULL;
        chunk *c = &l->chunks[k];
        if (c->p) c->ok = parse_lines(c->p, c->begin, c->end);
    }
}

/* Appends chunk c's spheres and warning to p as if p had parsed its lines; false when c must be
 * parsed in order instead. */
static bool chunk_adopt(parser *p, const chunk *c) {
    if (!c->p) return false;
    const scene *cs = &c->p->s;
    if (!c->ok || cs->sphere_count > SCENE_MAX_SPHERES - p->s.sphere_count) return false;
    size_t total = (size_t)p->s.sphere_count + (size_t)cs->sphere_count;
    if (total > p->sphere_capacity) {
        sphere *grown = realloc(p->s.spheres, total * sizeof *grown);
        if (!grown) return false;
        p->s.spheres = grown;
        p->sphere_capacity = total;
    }
    if (cs->sphere_count > 0) {
        memcpy(p->s.spheres + p->s.sphere_count, cs->spheres,
               (size_t)cs->sphere_count * sizeof *cs->spheres);
    }
    p->s.sphere_count += cs->sphere_count;
    /* Its only possible warning is its first tiny sphere, which counts if p had none yet. */
    if (cs->warning_count > 0 && !p->tiny_warned) {
        p->tiny_warned = true;
        if (p->s.warning_count < SCENE_MAX_WARNINGS) {
            scene_error *w = &p->s.warnings[p->s.warning_count++];
            *w = cs->warnings[0];
            w->line += p->line - 1;
        }
    }
    if (c->p->emission_line && !p->emission_line) {
        p->emission_line = c->p->emission_line + p->line - 1;
        p->emission_col = c->p->emission_col;
    }
    p->line += c->p->line - 1;
    return true;
}

/* Parses p's text on up to threads threads (see the top of the file). */
static bool parse_chunks(parser *p, int threads) {
    const char *text = p->text, *end = p->text + p->length;
    if (threads > MAX_PARSE_THREADS) threads = MAX_PARSE_THREADS;
    int count = threads * CHUNKS_PER_THREAD;
    if (p->length / MIN_CHUNK_BYTES < (size_t)count) count = (int)(p->length / MIN_CHUNK_BYTES);
    if (threads < 2 || count < 2) return parse_lines(p, text, end);
    chunk chunks[MAX_CHUNKS];
    const char *at = text;
    for (int k = 0; k < count; k++) { /* each chunk ends just past a '\n' (the last at end) */
        const char *cut = k == count - 1 ? end : text + p->length / (size_t)count * (size_t)(k + 1);
        if (cut < at) cut = at;
        const char *newline = cut < end ? memchr(cut, '\n', (size_t)(end - cut)) : NULL;
        chunks[k] = (chunk){.begin = at, .end = newline ? newline + 1 : end};
        at = chunks[k].end;
    }
    for (int k = 1; k < count; k++) {
        chunk *c = &chunks[k];
        c->p = calloc(1, sizeof *c->p);
        if (!c->p) continue;
        *c->p = (parser){.text = p->text,
                         .length = p->length,
                         .filename = p->filename,
                         .line = 1,
                         .spheres_only = true};
    }
    chunk_list list = {.chunks = chunks, .count = count};
    atomic_init(&list.next, 1);
    pthread_t workers[MAX_PARSE_THREADS];
    int started = 0;
    while (started < threads - 1 && started < count - 1 &&
           pthread_create(&workers[started], NULL, chunks_run, &list) == 0)
        started++;
    /* The first chunk in order, then whatever chunks the other threads have not taken (none after
     * an error: they would not count). */
    bool ok = parse_lines(p, chunks[0].begin, chunks[0].end);
    if (ok)
        chunks_run(&list);
    else
        atomic_store(&list.next, count);
    for (int t = 0; t < started; t++) pthread_join(workers[t], NULL);
    for (int k = 1; k < count; k++) {
        chunk *c = &chunks[k];
        if (ok && !chunk_adopt(p, c)) ok = parse_lines(p, c->begin, c->end);
        if (c->p) {
            scene_free(&c->p->s);
            free(c->p);
        }
    }
    return ok;
}

static bool parse_text(parser *p, int threads) {
    if (!parse_chunks(p, threads)) return false;
    /* Whole-scene errors are reported at the end of the file: the line after the last '\n'. */
    if (!p->camera_line) return fail_at(p, 1, "missing 'camera' directive");
    if (!p->plane_line) return fail_at(p, 1, "missing 'plane' directive");
    if (p->emission_line && p->s.mode == RENDER_MODE_SEED) {
        p->line = p->emission_line;
        return fail_at(p, p->emission_col,
                       "emission needs path mode: add 'render mode path' (or render with "
                       "--mode path)");
    }
    warn_near_surfaces(p);
    return true;
}

bool scene_parse_string_threads(const char *text, size_t length, const char *filename, int threads,
                                scene *out, scene_error *err) {
    if (err) err->out_of_memory = false;
    parser *p = calloc(1, sizeof *p);
    if (!p) {
        if (err) *err = (scene_error){.message = "out of memory", .out_of_memory = true};
        return false;
    }
    p->text = text;
    p->length = length;
    p->filename = filename ? filename : "<string>";
    p->err = err;
    p->line = 1;
    p->s = (scene){
        .camera_direction = v3(0, 0, 1),
        .camera_up = v3(0, 1, 0),
        .samples = 64,
        .indirect = true,
        .bounces = 5,
        .seed = 1,
        .mode = RENDER_MODE_SEED,
        .roulette = true,
    };
    bool ok;
    if (length > MAX_TEXT_BYTES) {
        p->line = 0;
        ok = fail_at(p, 0, "scene is too large (%zu bytes; the limit is %zu)", length,
                     MAX_TEXT_BYTES);
    } else {
        long online = sysconf(_SC_NPROCESSORS_ONLN);
        ok = parse_text(p, threads > 0 ? threads : online > 1 ? (int)online : 1);
    }
    if (ok) {
        *out = p->s;
    } else {
        scene_free(&p->s);
    }
    free(p);
    return ok;
}

bool scene_parse_string(const char *text, size_t length, const char *filename, scene *out,
                        scene_error *err) {
    return scene_parse_string_threads(text, length, filename, 0, out, err);
}

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

/* Reads all of fd into a malloc'd buffer; sizes a regular file from fstat, grows for pipes. */
static bool read_all(int fd, const char *path, char **data, size_t *length, scene_error *err) {
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
    char *buffer = malloc(capacity);
    if (!buffer) {
        if (err) err->out_of_memory = true;
        return fail_file(path, err, "out of memory reading %zu bytes", capacity);
    }
    size_t used = 0;
    for (;;) {
        if (used == capacity) {
            if (capacity > MAX_TEXT_BYTES) {
                free(buffer);
                return fail_file(path, err, "file is too large (the limit is %zu bytes)",
                                 MAX_TEXT_BYTES);
            }
            char *grown = realloc(buffer, capacity * 2);
            if (!grown) {
                free(buffer);
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
            return fail_file(path, err, "cannot read: %s", strerror(error));
        }
        if (n == 0) break;
        used += (size_t)n;
        /* A NUL byte is an error wherever it is: stop reading a stream (/dev/zero never ends)
         * and let the parser report it at its line and column. */
        if (!S_ISREG(st.st_mode) && memchr(buffer + used - n, '\0', (size_t)n)) break;
    }
    *data = buffer;
    *length = used;
    return true;
}

bool scene_parse_file(const char *path, scene *out, scene_error *err) {
    if (err) err->out_of_memory = false;
    /* "-" is standard input, named as the tools name it. */
    bool is_stdin = !strcmp(path, "-");
    if (is_stdin) path = "<stdin>";
    int fd = is_stdin ? dup(STDIN_FILENO) : open(path, O_RDONLY);
    if (fd < 0) return fail_file(path, err, "cannot open: %s", strerror(errno));
    char *data = NULL;
    size_t length = 0;
    bool ok = read_all(fd, path, &data, &length, err);
    close(fd);
    if (ok) ok = scene_parse_string(data, length, path, out, err);
    free(data);
    return ok;
}
