/* scene_directives.c: each directive of the scene format (DESIGN section 2; scenes/README.md)
 * parsed from a tokenized line into the scene: its keys, ranges, defaults and the errors that
 * need more than one value (a camera frame, a plane's pixels). */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_load.h"
#include "scene/parser.h"
#include "shared_layout.h"

/* |cross(direction, up)| below this fraction of |direction| |up| leaves the camera frame
 * undefined in single precision (about 0.006 degrees). */
#define CAMERA_MIN_SINE 1e-4
/* The seed's rule: plane size / pixel size within this relative distance of an integer. */
#define PIXEL_TOLERANCE 1e-6

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

/* The keys of a surface's material, the same for every shape: each shape's key table holds its
 * own keys, then these, so that one material table and one reader serve spheres and faces. */
enum { MAT_COLOR, MAT_KS, MAT_ALPHA, MAT_IOR, MAT_EMISSION, MAT_KEY_COUNT };
/* clang-format off */
#define MATERIAL_KEY_SPECS                                          \
    {"color", "r g b", VALUE_NUMBER, UNIT_RANGE},                   \
    {"ks", NULL, VALUE_NUMBER, UNIT_RANGE},                         \
    {"alpha", NULL, VALUE_NUMBER, 0.0, FLT_MAX, false},             \
    {"ior", NULL, VALUE_NUMBER, 1.0, FLT_MAX, false},               \
    {"emission", "r g b", VALUE_NUMBER, 0.0, FLT_MAX, false}
/* clang-format on */

enum {
    SPHERE_CENTER,
    SPHERE_RADIUS,
    SPHERE_MATERIAL,
    SPHERE_KEY_COUNT = SPHERE_MATERIAL + MAT_KEY_COUNT
};
static const key_spec sphere_keys[SPHERE_KEY_COUNT] = {
    {"center", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"radius", NULL, VALUE_NUMBER, RADIUS_RANGE},
    MATERIAL_KEY_SPECS,
};

/* A triangle's corners, its optional shading normals (any finite length but zero: normalized),
 * then the material keys. */
enum {
    TRIANGLE_V0,
    TRIANGLE_N0 = TRIANGLE_V0 + 3,
    TRIANGLE_MATERIAL = TRIANGLE_N0 + 3,
    TRIANGLE_KEY_COUNT = TRIANGLE_MATERIAL + MAT_KEY_COUNT
};
static const key_spec triangle_keys[TRIANGLE_KEY_COUNT] = {
    {"v0", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v1", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v2", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"n0", "x y z", VALUE_NUMBER, NO_RANGE},
    {"n1", "x y z", VALUE_NUMBER, NO_RANGE},
    {"n2", "x y z", VALUE_NUMBER, NO_RANGE},
    MATERIAL_KEY_SPECS,
};
_Static_assert(TRIANGLE_KEY_COUNT <= MAX_KEYS, "raise MAX_KEYS");

enum { QUAD_V0, QUAD_MATERIAL = QUAD_V0 + 4, QUAD_KEY_COUNT = QUAD_MATERIAL + MAT_KEY_COUNT };
static const key_spec quad_keys[QUAD_KEY_COUNT] = {
    {"v0", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v1", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v2", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v3", "x y z", VALUE_NUMBER, COORD_RANGE},
    MATERIAL_KEY_SPECS,
};

/* A mesh's own keys (file, scale and rotate are read by parse_mesh: a path, 1 or 3 numbers, 4
 * numbers), then the material keys. */
enum {
    MESH_FILE,
    MESH_SCALE,
    MESH_ROTATE,
    MESH_TRANSLATE,
    MESH_SMOOTH,
    MESH_MATERIAL,
    MESH_KEY_COUNT = MESH_MATERIAL + MAT_KEY_COUNT
};
static const key_spec mesh_keys[MESH_KEY_COUNT] = {
    {"file", NULL, VALUE_WORD, NO_RANGE},
    {"scale", NULL, VALUE_NUMBER, COORD_RANGE},
    {"rotate", NULL, VALUE_NUMBER, NO_RANGE},
    {"translate", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"smooth", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    MATERIAL_KEY_SPECS,
};
_Static_assert(MESH_KEY_COUNT <= MAX_KEYS, "raise MAX_KEYS");

/* A shape directive (sphere, triangle, quad) as the shared readers (read_shape, read_surface)
 * see it. */
typedef struct shape_spec {
    const char *word;
    const key_spec *keys;
    int key_count;
    int material_first; /* index in keys of the first material key */
    unsigned own_keys;  /* bits of keys the shape takes whatever its material */
    unsigned required;
    bool glass; /* takes refractive: only a closed surface bounds a medium */
} shape_spec;

#define LOW_BITS(n) ((1u << (n)) - 1u)
static const shape_spec sphere_shape = {
    .word = "sphere",
    .keys = sphere_keys,
    .key_count = SPHERE_KEY_COUNT,
    .material_first = SPHERE_MATERIAL,
    .own_keys = LOW_BITS(SPHERE_MATERIAL),
    .required = BIT(SPHERE_CENTER) | BIT(SPHERE_RADIUS),
    .glass = true,
};
static const shape_spec triangle_shape = {
    .word = "triangle",
    .keys = triangle_keys,
    .key_count = TRIANGLE_KEY_COUNT,
    .material_first = TRIANGLE_MATERIAL,
    .own_keys = LOW_BITS(TRIANGLE_MATERIAL),
    .required = LOW_BITS(TRIANGLE_N0), /* v0 v1 v2 */
};
static const shape_spec quad_shape = {
    .word = "quad",
    .keys = quad_keys,
    .key_count = QUAD_KEY_COUNT,
    .material_first = QUAD_MATERIAL,
    .own_keys = LOW_BITS(QUAD_MATERIAL),
    .required = LOW_BITS(QUAD_MATERIAL), /* v0 v1 v2 v3 */
};

static const shape_spec mesh_shape = {
    .word = "mesh",
    .keys = mesh_keys,
    .key_count = MESH_KEY_COUNT,
    .material_first = MESH_MATERIAL,
    .own_keys = LOW_BITS(MESH_MATERIAL),
    .required = BIT(MESH_FILE),
    .glass = true, /* when the mesh is closed (parse_mesh checks) */
};

#define MATERIAL_COMMON_KEYS (BIT(MAT_COLOR) | BIT(MAT_EMISSION))

typedef struct material_spec {
    const char *word;
    material_kind kind;
    unsigned keys; /* bits of the material keys (MAT_*) this material accepts */
    float default_color;
    bool alias; /* one of the seed's Spanish names */
} material_spec;

static const material_spec materials[] = {
    {"lambertian", MATERIAL_LAMBERTIAN, MATERIAL_COMMON_KEYS, 0.8f, false},
    {"phong", MATERIAL_PHONG, MATERIAL_COMMON_KEYS | BIT(MAT_KS) | BIT(MAT_ALPHA), 0.8f, false},
    {"mirror", MATERIAL_MIRROR, MATERIAL_COMMON_KEYS, 1.0f, false},
    {"refractive", MATERIAL_REFRACTIVE, MATERIAL_COMMON_KEYS | BIT(MAT_IOR), 1.0f, false},
    {"lambertiana", MATERIAL_LAMBERTIAN, MATERIAL_COMMON_KEYS, 0.8f, true},
    {"espejo", MATERIAL_MIRROR, MATERIAL_COMMON_KEYS, 1.0f, true},
    {"refractada", MATERIAL_REFRACTIVE, MATERIAL_COMMON_KEYS | BIT(MAT_IOR), 1.0f, true},
};

/* A surface's material as its line gives it, defaults filled in. */
typedef struct surface {
    material_kind material;
    vec3 color;
    float ks, alpha, ior;
    vec3 emission;
} surface;

enum {
    RENDER_SAMPLES,
    RENDER_INDIRECT,
    RENDER_BOUNCES,
    RENDER_SEED,
    RENDER_MODE,
    RENDER_ROULETTE,
    RENDER_SAMPLER,
    RENDER_KEY_COUNT
};
/* The words of `render mode`, in render_mode order. */
#define RENDER_MODE_WORDS "seed path"
/* The words of `render sampler`, in render_sampler order from random. */
#define RENDER_SAMPLER_WORDS "random sobol"
static const key_spec render_keys[RENDER_KEY_COUNT] = {
    {"samples", NULL, VALUE_INTEGER, 1.0, SCENE_MAX_SAMPLES, false},
    {"indirect", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    {"bounces", NULL, VALUE_INTEGER, 0.0, SCENE_MAX_BOUNCES, false},
    {"seed", NULL, VALUE_INTEGER, 0.0, UINT32_MAX, false},
    {"mode", RENDER_MODE_WORDS, VALUE_WORD, 0.0, 1.0, false},
    {"roulette", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    {"sampler", RENDER_SAMPLER_WORDS, VALUE_WORD, 0.0, 1.0, false},
};

/* background takes three numbers and no key; this spec names them in messages. */
static const key_spec background_spec = {"background", "r g b", VALUE_NUMBER, 0.0, FLT_MAX, false};

/* camera, plane, background and render describe the whole image: one of each at most. */
static bool claim_once(parser *p, int *first_line) {
    if (*first_line) {
        return parser_fail(p, p->tokens[0].col, "'%s' given twice (first on line %d)",
                           parser_quote(p, &p->tokens[0]), *first_line);
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
        return parser_fail(p, p->tokens[kv->key_token[key]].col,
                           "camera %s is too small or too large to normalize in single precision "
                           "(its length must be from about 1.1e-19 to 1.8e19)",
                           camera_keys[key].name);
    }
    return true;
}

/* v normalized in double, which holds the square of any float. */
static vec3 unit_in_double(vec3 v) {
    double x = v.x, y = v.y, z = v.z, l = sqrt(x * x + y * y + z * z);
    return v3((float)(x / l), (float)(y / l), (float)(z / l));
}

/* Refuses a zero camera vector. One whose square float cannot hold (a length under about
 * 1.1e-19 or over 1.8e19) becomes its unit vector (unit_in_double), so that any nonzero finite
 * length gives the image of the unit vector; others stay as given (the renderer normalizes them,
 * as it always has, so their images keep their bits). */
static bool check_camera_vector(parser *p, const key_values *kv, int key, vec3 *v) {
    if (v->x == 0.0f && v->y == 0.0f && v->z == 0.0f) {
        return parser_fail(p, p->tokens[kv->key_token[key]].col, "camera %s must not be zero",
                           camera_keys[key].name);
    }
    float square = v3_dot(*v, *v);
    if (!(square >= FLT_MIN && square <= FLT_MAX)) *v = unit_in_double(*v);
    return check_camera_square(p, kv, key, *v);
}

static bool parse_camera(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->camera_line) ||
        !parser_keys(p, "camera", camera_keys, CAMERA_KEY_COUNT, ~0u, 1, &kv) ||
        !parser_require_keys(p, "camera", camera_keys, CAMERA_KEY_COUNT, BIT(CAMERA_POSITION),
                             &kv)) {
        return false;
    }
    vec3 position = parser_vec3(&kv, CAMERA_POSITION, v3(0, 0, 0));
    vec3 direction = parser_vec3(&kv, CAMERA_DIRECTION, v3(0, 0, 1));
    vec3 up = parser_vec3(&kv, CAMERA_UP, v3(0, 1, 0));
    if (kv.given & BIT(CAMERA_LOOK_AT)) {
        if (kv.given & BIT(CAMERA_DIRECTION)) {
            return parser_fail(p, p->tokens[kv.key_token[CAMERA_LOOK_AT]].col,
                               "camera takes direction or look_at, not both");
        }
        vec3 at = parser_vec3(&kv, CAMERA_LOOK_AT, position);
        /* In double: the difference of two valid coordinates can overflow float. */
        double dx = (double)at.x - position.x, dy = (double)at.y - position.y,
               dz = (double)at.z - position.z;
        double m = fmax(fabs(dx), fmax(fabs(dy), fabs(dz)));
        if (m == 0.0) {
            return parser_fail(p, p->tokens[kv.key_token[CAMERA_LOOK_AT]].col,
                               "camera look_at must differ from position");
        }
        direction = v3((float)(dx / m), (float)(dy / m), (float)(dz / m));
    }
    vec3 given_direction = direction, given_up = up; /* as written, for the messages */
    if (!check_camera_vector(p, &kv, CAMERA_DIRECTION, &direction) ||
        !check_camera_vector(p, &kv, CAMERA_UP, &up)) {
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
        return parser_fail(p, p->tokens[kv.key_token[up_key]].col,
                           "camera up (%g %g %g) is parallel to direction (%g %g %g)", given_up.x,
                           given_up.y, given_up.z, given_direction.x, given_direction.y,
                           given_direction.z);
    }
    /* The right vector, up x forward, is normalized too: a small up at a small angle underflows
     * there unless up is a unit vector. */
    vec3 forward = v3_normalize(direction), right = v3_cross(up, forward);
    if (!(v3_dot(right, right) >= FLT_MIN)) {
        up = unit_in_double(up);
        right = v3_cross(up, forward);
    }
    if (!check_camera_square(p, &kv, up_key, right)) return false;
    p->s.camera_position = position;
    p->s.camera_fov = (float)parser_value_or(&kv, CAMERA_FOV, 0.0);
    if (kv.given & BIT(CAMERA_FOV)) {
        p->fov_line = p->line;
        p->fov_col = p->tokens[kv.value_token[CAMERA_FOV][0]].col;
    }
    p->s.camera_near = (float)parser_value_or(&kv, CAMERA_NEAR, 0.0);
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
           plane_keys[side].name, parser_quote(p, size_token), parser_quote(p, pixel_token), ratio);
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
    return parser_fail(p, pixel_token->col, "%s", message);
}

static bool parse_plane(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->plane_line) ||
        !parser_keys(p, "plane", plane_keys, PLANE_KEY_COUNT, ~0u, 1, &kv) ||
        !parser_require_keys(p, "plane", plane_keys, PLANE_KEY_COUNT, ~0u, &kv)) {
        return false;
    }
    float pixel = (float)kv.value[PLANE_PIXEL][0];
    const token *pixel_token = &p->tokens[kv.value_token[PLANE_PIXEL][0]];
    long pixels[2];
    for (int side = PLANE_WIDTH; side <= PLANE_HEIGHT; side++) {
        const token *size_token = &p->tokens[kv.value_token[side][0]];
        double ratio = kv.value[side][0] / pixel;
        if (ratio >= SCENE_MAX_RESOLUTION + 0.5) {
            return parser_fail(p, pixel_token->col,
                               "plane %s %s at pixel %s is %.7g pixels, more than the maximum %d",
                               plane_keys[side].name, parser_quote(p, size_token),
                               parser_quote(p, pixel_token), ratio, SCENE_MAX_RESOLUTION);
        }
        if (ratio < 0.5) {
            return parser_fail(p, pixel_token->col, "plane %s %s is less than one pixel of %s",
                               plane_keys[side].name, parser_quote(p, size_token),
                               parser_quote(p, pixel_token));
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

/* Grows an array by doubling so a million appends cost a few dozen reallocations; room for
 * `adding` more items. */
static bool grow(parser *p, void **array, size_t *capacity, int count, int adding, int max,
                 size_t item, const char *what) {
    if (count > max - adding) {
        return parser_fail(p, p->tokens[0].col, "too many %s (the maximum is %d)", what, max);
    }
    if ((size_t)count + (size_t)adding <= *capacity) return true;
    size_t capacity_new = *capacity ? *capacity * 2 : 64;
    if (capacity_new < (size_t)count + (size_t)adding) capacity_new = (size_t)count + adding;
    if (capacity_new > (size_t)max) capacity_new = (size_t)max;
    void *grown = realloc(*array, capacity_new * item);
    if (!grown) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, p->tokens[0].col, "out of memory after %d %s", count, what);
    }
    *array = grown;
    *capacity = capacity_new;
    return true;
}

/* Spheres and triangles share one primitive index: false (reported at the directive word) when
 * `adding` more would pass PARSER_MAX_PRIMITIVES. */
static bool reserve_primitives(parser *p, int adding) {
    long long total = (long long)p->s.sphere_count + p->s.triangle_count + adding;
    if (total <= PARSER_MAX_PRIMITIVES) return true;
    return parser_fail(p, p->tokens[0].col,
                       "too many primitives (spheres and triangles together, a quad counting as "
                       "two; the maximum is %d)",
                       PARSER_MAX_PRIMITIVES);
}

static bool parse_light(parser *p) {
    key_values kv;
    if (!parser_keys(p, "light", light_keys, LIGHT_KEY_COUNT, ~0u, 1, &kv) ||
        !parser_require_keys(p, "light", light_keys, LIGHT_KEY_COUNT,
                             BIT(LIGHT_POSITION) | BIT(LIGHT_POWER), &kv)) {
        return false;
    }
    void *array = p->s.lights;
    bool ok = grow(p, &array, &p->light_capacity, p->s.light_count, 1, SCENE_MAX_LIGHTS,
                   sizeof(light), "lights");
    p->s.lights = array;
    if (!ok) return false;
    p->s.lights[p->s.light_count++] = (light){
        .position = parser_vec3(&kv, LIGHT_POSITION, v3(0, 0, 0)),
        .power = (float)parser_value_or(&kv, LIGHT_POWER, 0.0),
        .color = parser_vec3(&kv, LIGHT_COLOR, v3(1, 1, 1)),
    };
    return true;
}

/* The materials a shape takes, for messages: "lambertian phong mirror refractive, or lambertiana
 * espejo refractada" (sep " ") or "lambertian, phong, mirror, refractive" (sep ", ", no aliases).
 */
static void material_list(char *out, size_t size, const shape_spec *shape, const char *sep,
                          bool aliases) {
    out[0] = '\0';
    for (int pass = 0; pass < (aliases ? 2 : 1); pass++) {
        bool first = true;
        for (size_t i = 0; i < sizeof materials / sizeof materials[0]; i++) {
            const material_spec *m = &materials[i];
            if (m->alias != (pass == 1) || (m->kind == MATERIAL_REFRACTIVE && !shape->glass))
                continue;
            append(out, size, "%s%s", first ? (pass ? ", or " : "") : sep, m->word);
            first = false;
        }
    }
}

/* Reads a shape's line: its material word (token 1), then its keys and the material's into kv.
 * False (reported) on a missing or unknown material, glass on a shape that takes none, or a bad
 * or missing key. */
static bool read_shape(parser *p, const shape_spec *shape, const material_spec **material,
                       key_values *kv) {
    char list[128];
    if (p->token_count < 2) {
        material_list(list, sizeof list, shape, ", ", false);
        return parser_fail(p, parser_end_col(p),
                           "expected a material after '%s' (%s), got end of line", shape->word,
                           list);
    }
    const token *word = &p->tokens[1];
    const material_spec *m = NULL;
    for (size_t i = 0; i < sizeof materials / sizeof materials[0] && !m; i++) {
        if (parser_token_is(word, materials[i].word)) m = &materials[i];
    }
    if (!m) {
        material_list(list, sizeof list, shape, " ", true);
        return parser_fail(p, word->col, "unknown material '%s' for %s (expected one of: %s)",
                           parser_quote(p, word), shape->word, list);
    }
    if (m->kind == MATERIAL_REFRACTIVE && !shape->glass) {
        return parser_fail(p, word->col,
                           "a %s cannot be '%s': glass needs a closed mesh (load one with the "
                           "'mesh' directive)",
                           shape->word, m->word);
    }
    *material = m;
    unsigned accepted = shape->own_keys | m->keys << shape->material_first;
    return parser_keys_of(p, shape->word, m->word, shape->keys, shape->key_count, accepted, 2,
                          kv) &&
           parser_require_keys(p, shape->word, shape->keys, shape->key_count, shape->required, kv);
}

/* The material of a shape's line, defaults filled in; records the first emission, which seed
 * mode refuses once the whole text is read (render mode may come later). */
static surface read_surface(parser *p, const shape_spec *shape, const material_spec *m,
                            const key_values *kv) {
    int k = shape->material_first;
    bool phong = m->kind == MATERIAL_PHONG;
    float c = m->default_color;
    if ((kv->given & BIT(k + MAT_EMISSION)) && !p->emission_line) {
        p->emission_line = p->line;
        p->emission_col = p->tokens[kv->key_token[k + MAT_EMISSION]].col;
    }
    return (surface){
        .material = m->kind,
        .color = parser_vec3(kv, k + MAT_COLOR, v3(c, c, c)),
        .ks = phong ? (float)parser_value_or(kv, k + MAT_KS, 0.5) : 0.0f,
        .alpha = phong ? (float)parser_value_or(kv, k + MAT_ALPHA, 32.0) : 0.0f,
        .ior = (float)parser_value_or(kv, k + MAT_IOR, m->kind == MATERIAL_REFRACTIVE ? 1.5 : 1.0),
        .emission = parser_vec3(kv, k + MAT_EMISSION, v3(0, 0, 0)),
    };
}

static bool parse_sphere(parser *p) {
    const material_spec *m;
    key_values kv;
    if (!read_shape(p, &sphere_shape, &m, &kv)) return false;
    void *array = p->s.spheres;
    bool ok = grow(p, &array, &p->sphere_capacity, p->s.sphere_count, 1, SCENE_MAX_SPHERES,
                   sizeof(sphere), "spheres");
    p->s.spheres = array;
    if (!ok || !reserve_primitives(p, 1)) return false;
    surface f = read_surface(p, &sphere_shape, m, &kv);
    p->s.spheres[p->s.sphere_count++] = (sphere){
        .center = parser_vec3(&kv, SPHERE_CENTER, v3(0, 0, 0)),
        .radius = (float)parser_value_or(&kv, SPHERE_RADIUS, 0.0),
        .material = f.material,
        .color = f.color,
        .ks = f.ks,
        .alpha = f.alpha,
        .ior = f.ior,
        .emission = f.emission,
    };
    const sphere *added = &p->s.spheres[p->s.sphere_count - 1];
    float offset = TZ_EPS * parser_largest_coordinate(added->center);
    if (added->radius < SCENE_TINY_OFFSETS * offset && !p->tiny_warned) {
        p->tiny_warned = true;
        parser_warn(p, p->line, p->tokens[kv.value_token[SPHERE_RADIUS][0]].col,
                    "radius %g is under %g times the ray offset here (%g: %g times the largest "
                    "coordinate, at least %g): rays that enter it start near or past its far side, "
                    "so it is shaded wrongly (glass turns black first)",
                    (double)added->radius, (double)SCENE_TINY_OFFSETS, (double)offset,
                    (double)TZ_EPS, (double)TZ_EPS);
    }
    return true;
}

/* Double-precision vectors: the face checks must not overflow or cancel where float would. */
typedef struct dvec3 {
    double x, y, z;
} dvec3;
static dvec3 d3_sub(vec3 a, vec3 b) {
    return (dvec3){(double)a.x - b.x, (double)a.y - b.y, (double)a.z - b.z};
}
static dvec3 d3_cross(dvec3 a, dvec3 b) {
    return (dvec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static double d3_dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static double d3_length(dvec3 a) { return sqrt(d3_dot(a, a)); }

/* True, with the reason in why, unless face a b c is one the renderer can normalize in single
 * precision: not degenerate (SCENE_FACE_MIN_SHAPE) and twice its area within
 * [SCENE_FACE_MIN_CROSS, SCENE_FACE_MAX_CROSS]. `what` names the face ("triangle", "quad half
 * v0 v1 v2"). */
static bool face_problem(vec3 a, vec3 b, vec3 c, const char *what, char *why, size_t size) {
    dvec3 ab = d3_sub(b, a), ac = d3_sub(c, a), bc = d3_sub(c, b);
    double cross = d3_length(d3_cross(ab, ac));
    double longest = fmax(d3_dot(ab, ab), fmax(d3_dot(ac, ac), d3_dot(bc, bc)));
    if (cross == 0.0) {
        double shortest = fmin(d3_dot(ab, ab), fmin(d3_dot(ac, ac), d3_dot(bc, bc)));
        snprintf(why, size, "%s is degenerate: %s (zero area)", what,
                 longest == 0.0    ? "its corners are one point"
                 : shortest == 0.0 ? "two of its corners are the same point"
                                   : "its corners are on a line");
        return true;
    }
    if (cross < SCENE_FACE_MIN_SHAPE * longest) {
        snprintf(why, size,
                 "%s is degenerate: its height is %.6g of its longest edge, under the %g that "
                 "single precision needs for its normal",
                 what, cross / longest, SCENE_FACE_MIN_SHAPE);
        return true;
    }
    if (cross < SCENE_FACE_MIN_CROSS || cross > SCENE_FACE_MAX_CROSS) {
        snprintf(why, size,
                 "%s is too %s for single precision: twice its area (the length of the cross "
                 "product of two edges) is %g, and must be from %g to %g",
                 what, cross < SCENE_FACE_MIN_CROSS ? "small" : "large", cross,
                 SCENE_FACE_MIN_CROSS, SCENE_FACE_MAX_CROSS);
        return true;
    }
    return false;
}

/* face_problem reported at the directive word. */
static bool check_face(parser *p, vec3 a, vec3 b, vec3 c, const char *what) {
    char why[256];
    if (face_problem(a, b, c, what, why, sizeof why))
        return parser_fail(p, p->tokens[0].col, "%s", why);
    return true;
}

/* Appends one face to the scene's triangles (room reserved by the caller). */
static void add_triangle(parser *p, vec3 a, vec3 b, vec3 c, const surface *f) {
    triangle *t = &p->s.triangles[p->s.triangle_count++];
    memset(t, 0, sizeof *t); /* padding too: equal faces are equal bytes */
    t->v[0] = a;
    t->v[1] = b;
    t->v[2] = c;
    t->material = f->material;
    t->color = f->color;
    t->ks = f->ks;
    t->alpha = f->alpha;
    t->ior = f->ior;
    t->emission = f->emission;
}

/* Room for `adding` triangles; false (reported) past the limits or out of memory. */
static bool reserve_triangles(parser *p, int adding) {
    if (!reserve_primitives(p, adding)) return false;
    void *array = p->s.triangles;
    bool ok = grow(p, &array, &p->triangle_capacity, p->s.triangle_count, adding,
                   PARSER_MAX_PRIMITIVES, sizeof(triangle), "triangles");
    p->s.triangles = array;
    return ok;
}

static bool parse_triangle(parser *p) {
    const material_spec *m;
    key_values kv;
    if (!read_shape(p, &triangle_shape, &m, &kv)) return false;
    unsigned normals = kv.given & (BIT(TRIANGLE_N0) | BIT(TRIANGLE_N0 + 1) | BIT(TRIANGLE_N0 + 2));
    if (normals && normals != (BIT(TRIANGLE_N0) | BIT(TRIANGLE_N0 + 1) | BIT(TRIANGLE_N0 + 2))) {
        int given = TRIANGLE_N0, missing = TRIANGLE_N0;
        while (!(normals & BIT(given))) given++;
        while (normals & BIT(missing)) missing++;
        return parser_fail(p, p->tokens[kv.key_token[given]].col,
                           "triangle %s needs %s: shading normals come all three (n0 n1 n2) or "
                           "none",
                           triangle_keys[given].name, triangle_keys[missing].name);
    }
    vec3 v[3], n[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int k = 0; k < 3; k++) v[k] = parser_vec3(&kv, TRIANGLE_V0 + k, v3(0, 0, 0));
    for (int k = 0; normals && k < 3; k++) {
        /* In double: any finite nonzero float vector normalizes there without overflow. */
        double x = kv.value[TRIANGLE_N0 + k][0], y = kv.value[TRIANGLE_N0 + k][1],
               z = kv.value[TRIANGLE_N0 + k][2];
        double length = sqrt(x * x + y * y + z * z);
        if (length == 0.0) {
            return parser_fail(p, p->tokens[kv.key_token[TRIANGLE_N0 + k]].col,
                               "triangle %s must not be zero (a shading normal is a direction)",
                               triangle_keys[TRIANGLE_N0 + k].name);
        }
        n[k] = v3((float)(x / length), (float)(y / length), (float)(z / length));
    }
    if (!check_face(p, v[0], v[1], v[2], "triangle") || !reserve_triangles(p, 1)) return false;
    surface f = read_surface(p, &triangle_shape, m, &kv);
    add_triangle(p, v[0], v[1], v[2], &f);
    triangle *t = &p->s.triangles[p->s.triangle_count - 1];
    t->smooth = normals != 0;
    for (int k = 0; k < 3; k++) t->n[k] = n[k];
    return true;
}

/* A quad is stored as (v0 v1 v2) and (v0 v2 v3): both must be faces, v3 on the plane of the
 * first (SCENE_QUAD_PLANE_TOLERANCE) and the quad convex, so that the halves tile it without
 * folding over each other. */
static bool parse_quad(parser *p) {
    const material_spec *m;
    key_values kv;
    if (!read_shape(p, &quad_shape, &m, &kv)) return false;
    vec3 v[4];
    for (int k = 0; k < 4; k++) v[k] = parser_vec3(&kv, QUAD_V0 + k, v3(0, 0, 0));
    if (!check_face(p, v[0], v[1], v[2], "quad half v0 v1 v2")) return false;
    dvec3 normal = d3_cross(d3_sub(v[1], v[0]), d3_sub(v[2], v[0]));
    double normal_length = d3_length(normal);
    double off = fabs(d3_dot(d3_sub(v[3], v[0]), normal)) / normal_length;
    double diagonal = fmax(d3_length(d3_sub(v[2], v[0])), d3_length(d3_sub(v[3], v[1])));
    if (off > SCENE_QUAD_PLANE_TOLERANCE * diagonal) {
        return parser_fail(p, p->tokens[kv.key_token[QUAD_V0 + 3]].col,
                           "quad is not flat: v3 is %.3g off the plane of v0 v1 v2, more than %g "
                           "times its longest diagonal (%.3g)",
                           off, SCENE_QUAD_PLANE_TOLERANCE, diagonal);
    }
    if (!check_face(p, v[0], v[2], v[3], "quad half v0 v2 v3")) return false;
    /* Convex: seen along the first half's normal, every corner turns the same way. */
    for (int k = 0; k < 4; k++) {
        dvec3 in = d3_sub(v[k], v[(k + 3) % 4]), out = d3_sub(v[(k + 1) % 4], v[k]);
        if (!(d3_dot(d3_cross(in, out), normal) > 0.0)) {
            return parser_fail(p, p->tokens[kv.key_token[QUAD_V0 + k]].col,
                               "quad is not convex at v%d: its corners v0 v1 v2 v3 must go once "
                               "around it, turning the same way at each",
                               k);
        }
    }
    if (!reserve_triangles(p, 2)) return false;
    surface f = read_surface(p, &quad_shape, m, &kv);
    add_triangle(p, v[0], v[1], v[2], &f);
    add_triangle(p, v[0], v[2], v[3], &f);
    return true;
}

/* Whether the token can start a number (scale's second value or the next key). */
static bool looks_numeric(const token *t) {
    char c = t->text[0];
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

/* The mesh file's path: absolute as given, else relative to the scene file's folder (the working
 * folder for text that is not a file: standard input, strings). False when it does not fit. */
static bool mesh_path(const parser *p, const token *t, char *out, size_t size) {
    const char *slash = strrchr(p->filename, '/');
    int dir =
        t->text[0] == '/' || p->filename[0] == '<' || !slash ? 0 : (int)(slash - p->filename) + 1;
    int n = snprintf(out, size, "%.*s%.*s", dir, p->filename, t->length, t->text);
    return n >= 0 && (size_t)n < size;
}

/* A mesh line's transform: scale, then rotation about a unit axis, then translation. */
typedef struct mesh_transform {
    double scale[3], r[3][3], translate[3];
} mesh_transform;

static mesh_transform make_transform(const double scale[3], const double rotate[4],
                                     const double translate[3]) {
    mesh_transform m;
    double length = sqrt(rotate[0] * rotate[0] + rotate[1] * rotate[1] + rotate[2] * rotate[2]);
    double u[3] = {rotate[0] / length, rotate[1] / length, rotate[2] / length};
    double angle = rotate[3] * 3.14159265358979323846 / 180.0, c = cos(angle), s = sin(angle);
    /* Rodrigues: c I + s [u]x + (1 - c) u u^T (right-handed). */
    double cross[3][3] = {{0, -u[2], u[1]}, {u[2], 0, -u[0]}, {-u[1], u[0], 0}};
    for (int i = 0; i < 3; i++) {
        m.scale[i] = scale[i];
        m.translate[i] = translate[i];
        for (int j = 0; j < 3; j++)
            m.r[i][j] = (i == j ? c : 0.0) + s * cross[i][j] + (1.0 - c) * u[i] * u[j];
    }
    return m;
}

/* A corner moved by the transform; false when it leaves the coordinate range. */
static bool transform_point(const mesh_transform *m, vec3 v, vec3 *out) {
    double in[3] = {(double)v.x * m->scale[0], (double)v.y * m->scale[1],
                    (double)v.z * m->scale[2]};
    float o[3];
    for (int i = 0; i < 3; i++) {
        double x = m->r[i][0] * in[0] + m->r[i][1] * in[1] + m->r[i][2] * in[2] + m->translate[i];
        if (!(fabs(x) <= 1e18)) return false;
        o[i] = (float)x;
    }
    *out = v3(o[0], o[1], o[2]);
    return true;
}

/* A normal by the inverse transpose, R S^-1, renormalized; false when it is zero. */
static bool transform_normal(const mesh_transform *m, vec3 n, vec3 *out) {
    double in[3] = {n.x / m->scale[0], n.y / m->scale[1], n.z / m->scale[2]}, o[3];
    for (int i = 0; i < 3; i++) o[i] = m->r[i][0] * in[0] + m->r[i][1] * in[1] + m->r[i][2] * in[2];
    double length = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    if (!(length > 0.0) || !isfinite(length)) return false;
    *out = v3((float)(o[0] / length), (float)(o[1] / length), (float)(o[2] / length));
    return true;
}

/* Reads a mesh line's keys after the optional material word (in any order; scale takes 1 or 3
 * numbers, rotate 4). False (reported) on a bad key or value. */
static bool read_mesh_keys(parser *p, const material_spec *m, int next, key_values *kv,
                           double scale[3], double rotate[4]) {
    unsigned accepted = mesh_shape.own_keys | (m ? m->keys << MESH_MATERIAL : 0u);
    memset(kv, 0, sizeof *kv);
    while (next < p->token_count) {
        const token *t = &p->tokens[next++];
        int key = 0;
        while (key < MESH_KEY_COUNT && !parser_token_is(t, mesh_keys[key].name)) key++;
        if (key < MESH_KEY_COUNT && key >= MESH_MATERIAL && !m) {
            return parser_fail(p, t->col,
                               "mesh '%s' needs a material word (mesh lambertian file ... %s ...): "
                               "without one every face takes the file's own material",
                               parser_quote(p, t), mesh_keys[key].name);
        }
        if (key == MESH_KEY_COUNT || !(accepted & BIT(key))) {
            char list[128] = "";
            for (int k = 0; k < MESH_KEY_COUNT; k++) {
                if (accepted & BIT(k))
                    append(list, sizeof list, "%s%s", list[0] ? " " : "", mesh_keys[k].name);
            }
            return parser_fail(p, t->col, "unknown key '%s' for mesh%s%s (expected one of: %s)",
                               parser_quote(p, t), m ? " " : "", m ? m->word : "", list);
        }
        if (kv->given & BIT(key))
            return parser_fail(p, t->col, "'%s' given twice", mesh_keys[key].name);
        kv->given |= BIT(key);
        kv->key_token[key] = next - 1;
        if (key == MESH_FILE) {
            if (next >= p->token_count)
                return parser_fail(p, parser_end_col(p), "expected a path after 'file'");
            kv->value_token[key][0] = next++;
        } else if (key == MESH_SCALE || key == MESH_ROTATE) {
            int count = key == MESH_ROTATE ? 4 : 3;
            double *out = key == MESH_ROTATE ? rotate : scale;
            for (int c = 0; c < count; c++) {
                if (key == MESH_SCALE && c == 1 &&
                    (next >= p->token_count || !looks_numeric(&p->tokens[next]))) {
                    out[1] = out[2] = out[0];
                    break;
                }
                double value[3];
                int value_token[3];
                if (!parser_values(p, &mesh_keys[key], &next, value, value_token)) return false;
                out[c] = value[0];
            }
        } else if (!parser_values(p, &mesh_keys[key], &next, kv->value[key],
                                  kv->value_token[key])) {
            return false;
        }
    }
    if (!parser_require_keys(p, "mesh", mesh_keys, MESH_KEY_COUNT, mesh_shape.required, kv))
        return false;
    if (scale[0] == 0.0 || scale[1] == 0.0 || scale[2] == 0.0) {
        return parser_fail(p, p->tokens[kv->key_token[MESH_SCALE]].col,
                           "mesh scale must not be zero (it would flatten every face)");
    }
    if (rotate[0] == 0.0 && rotate[1] == 0.0 && rotate[2] == 0.0) {
        return parser_fail(p, p->tokens[kv->key_token[MESH_ROTATE]].col,
                           "mesh rotate axis must not be zero");
    }
    return true;
}

/* The surface of a mapped file material (a lambertian grey when the face has none). */
static surface mapped_surface(const mesh *me, int material) {
    if (material < 0 || material >= me->material_count) {
        return (surface){.material = MATERIAL_LAMBERTIAN, .color = v3(0.8f, 0.8f, 0.8f), .ior = 1};
    }
    const mesh_material *mm = &me->materials[material];
    return (surface){.material = mm->kind,
                     .color = mm->color,
                     .ks = mm->ks,
                     .alpha = mm->alpha,
                     .ior = mm->ior,
                     .emission = mm->emission};
}

/* A mesh from a model file (mesh_load.c): transformed, its degenerate faces dropped (one
 * warning), glass only when it is closed. */
static bool parse_mesh(parser *p) {
    const material_spec *m = NULL;
    int next = 1;
    if (p->token_count > 1 && !parser_token_is(&p->tokens[1], "file")) {
        const token *word = &p->tokens[1];
        for (size_t i = 0; i < sizeof materials / sizeof materials[0] && !m; i++) {
            if (parser_token_is(word, materials[i].word)) m = &materials[i];
        }
        if (!m) {
            char list[128];
            material_list(list, sizeof list, &mesh_shape, " ", true);
            return parser_fail(p, word->col,
                               "unknown material '%s' for mesh (expected 'file' or one of: %s)",
                               parser_quote(p, word), list);
        }
        next = 2;
    }
    key_values kv;
    double scale[3] = {1, 1, 1}, rotate[4] = {0, 0, 1, 0};
    if (!read_mesh_keys(p, m, next, &kv, scale, rotate)) return false;
    const token *file = &p->tokens[kv.value_token[MESH_FILE][0]];
    char path[PATH_MAX];
    if (!mesh_path(p, file, path, sizeof path))
        return parser_fail(p, file->col, "mesh path is too long");
    bool smooth = parser_value_or(&kv, MESH_SMOOTH, 0) != 0;
    mesh me;
    char error[512];
    if (!mesh_load(path, smooth, &me, error, sizeof error))
        return parser_fail(p, file->col, "mesh '%s': %s", path, error);
    double translate[3] = {0, 0, 0};
    for (int k = 0; k < 3 && (kv.given & BIT(MESH_TRANSLATE)); k++)
        translate[k] = kv.value[MESH_TRANSLATE][k];
    mesh_transform xf = make_transform(scale, rotate, translate);
    surface given = {0};
    if (m) given = read_surface(p, &mesh_shape, m, &kv);
    bool glass = m && m->kind == MATERIAL_REFRACTIVE, emits = false;
    for (int k = 0; !m && k < me.material_count; k++)
        glass |= me.materials[k].kind == MATERIAL_REFRACTIVE;
    if (glass && !mesh_closed(&me)) {
        mesh_free(&me);
        return parser_fail(p, file->col,
                           "mesh '%s' is refractive but not closed (an edge is not shared by "
                           "exactly two faces wound the opposite ways): glass needs a surface "
                           "that bounds its inside",
                           path);
    }
    /* Transformed in place; kept faces first. */
    size_t kept = 0, dropped = 0;
    char first_drop[320] = "";
    for (size_t f = 0; f < me.face_count; f++) {
        mesh_face face = me.faces[f];
        for (int k = 0; k < 3; k++) {
            if (!transform_point(&xf, me.faces[f].v[k], &face.v[k])) {
                mesh_free(&me);
                return parser_fail(p, file->col,
                                   "mesh '%s': face %zu leaves the coordinate range (1e18) once "
                                   "transformed",
                                   path, f + 1);
            }
        }
        char why[256];
        if (face_problem(face.v[0], face.v[1], face.v[2], "face", why, sizeof why)) {
            if (!dropped++) snprintf(first_drop, sizeof first_drop, "%zu: %s", f + 1, why);
            continue;
        }
        bool normals = smooth;
        for (int k = 0; k < 3 && normals; k++)
            normals = transform_normal(&xf, me.faces[f].n[k], &face.n[k]);
        for (int k = 0; k < 3 && !normals; k++) face.n[k] = v3(0, 0, 0); /* flat */
        me.faces[kept++] = face;
    }
    if (kept == 0) {
        mesh_free(&me);
        return parser_fail(p, file->col, "mesh '%s': every face is degenerate (face %s)", path,
                           first_drop);
    }
    /* Glass tells entering from leaving by the geometric normal: wind the faces outward (a
     * positive signed volume). */
    double volume = 0.0;
    for (size_t f = 0; glass && f < kept; f++) {
        const mesh_face *face = &me.faces[f];
        dvec3 a = d3_sub(face->v[0], v3(0, 0, 0)), b = d3_sub(face->v[1], v3(0, 0, 0)),
              c = d3_sub(face->v[2], v3(0, 0, 0));
        volume += d3_dot(a, d3_cross(b, c));
    }
    for (size_t f = 0; volume < 0.0 && f < kept; f++) {
        mesh_face *face = &me.faces[f];
        vec3 v = face->v[1], n = face->n[1];
        face->v[1] = face->v[2], face->n[1] = face->n[2];
        face->v[2] = v, face->n[2] = n;
    }
    if (!reserve_triangles(p, kept > (size_t)INT_MAX / 2 ? INT_MAX / 2 : (int)kept)) {
        mesh_free(&me);
        return false;
    }
    for (size_t f = 0; f < kept; f++) {
        const mesh_face *face = &me.faces[f];
        surface s = m ? given : mapped_surface(&me, face->material);
        emits |= s.emission.x > 0.0f || s.emission.y > 0.0f || s.emission.z > 0.0f;
        add_triangle(p, face->v[0], face->v[1], face->v[2], &s);
        triangle *t = &p->s.triangles[p->s.triangle_count - 1];
        t->smooth = face->n[0].x != 0.0f || face->n[0].y != 0.0f || face->n[0].z != 0.0f;
        for (int k = 0; k < 3; k++) t->n[k] = face->n[k];
    }
    if (emits && !m && !p->emission_line) {
        p->emission_line = p->line;
        p->emission_col = file->col;
    }
    if (!m && me.unsupported[0]) {
        parser_warn(p, p->line, file->col, "mesh '%s': trazador cannot show its %s (ignored)", path,
                    me.unsupported);
    }
    if (dropped) {
        parser_warn(p, p->line, file->col,
                    "mesh '%s': %zu degenerate face%s dropped (the first, face %s)", path, dropped,
                    dropped == 1 ? "" : "s", first_drop);
    }
    mesh_free(&me);
    return true;
}

static bool parse_background(parser *p) {
    if (!claim_once(p, &p->background_line)) return false;
    double value[3];
    int value_token[3], next = 1;
    if (!parser_values(p, &background_spec, &next, value, value_token)) return false;
    if (next < p->token_count) {
        return parser_fail(p, p->tokens[next].col, "unexpected '%s' after background's 3 numbers",
                           parser_quote(p, &p->tokens[next]));
    }
    p->s.background = v3((float)value[0], (float)value[1], (float)value[2]);
    return true;
}

static bool parse_render(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->render_line) ||
        !parser_keys(p, "render", render_keys, RENDER_KEY_COUNT, ~0u, 1, &kv)) {
        return false;
    }
    p->s.samples = (int)parser_value_or(&kv, RENDER_SAMPLES, 64);
    p->s.indirect = parser_value_or(&kv, RENDER_INDIRECT, 1) != 0;
    p->s.mode = (render_mode)parser_value_or(&kv, RENDER_MODE, RENDER_MODE_SEED);
    p->s.bounces_given = kv.given & BIT(RENDER_BOUNCES);
    p->s.bounces = (int)parser_value_or(&kv, RENDER_BOUNCES, scene_default_bounces(p->s.mode));
    p->s.seed = (uint32_t)parser_value_or(&kv, RENDER_SEED, 1);
    p->s.roulette = parser_value_or(&kv, RENDER_ROULETTE, 1) != 0;
    if (kv.given & BIT(RENDER_SAMPLER))
        p->s.sampler =
            (render_sampler)(RENDER_SAMPLER_RANDOM + (int)parser_value_or(&kv, RENDER_SAMPLER, 0));
    if (kv.given & BIT(RENDER_ROULETTE))
        p->roulette_col = p->tokens[kv.key_token[RENDER_ROULETTE]].col;
    return true;
}

typedef struct directive_spec {
    const char *word;
    bool (*parse)(parser *p);
    bool primitive; /* parsed in chunks ahead (primitives_only) */
} directive_spec;

static const directive_spec directives[] = {
    {"camera", parse_camera, false},
    {"plane", parse_plane, false},
    {"light", parse_light, false},
    {"sphere", parse_sphere, true},
    {"triangle", parse_triangle, true},
    {"quad", parse_quad, true},
    {"background", parse_background, false},
    {"render", parse_render, false},
    {"mesh", parse_mesh, false}, /* in order: it reads a file and may warn */
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
                       "triangle quad mesh background render)",
                       parser_quote(p, word));
}
