/* scene_setup.c: the directives that set the scene up around its geometry (DESIGN section 2;
 * scenes/README.md): camera, plane and render, with the errors that need more than one value (a
 * camera frame, a plane's pixels); the lights are scene_lights.c's. */
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/parser.h"

/* |cross(direction, up)| below this fraction of |direction| |up| leaves the camera frame
 * undefined in single precision (about 0.006 degrees). */
#define CAMERA_MIN_SINE 1e-4
/* The seed's rule: plane size / pixel size within this relative distance of an integer. */
#define PIXEL_TOLERANCE 1e-6

/* Plane sizes: ray directions are normalized from vectors of about this length, whose squares
 * must neither overflow nor vanish in float. */
#define PLANE_RANGE 1e-12, 1e12, false
/* Horizontal field of view in degrees: (0, 179] (180 puts the plane at zero distance). */
#define FOV_RANGE 0.0, 179.0, true

enum {
    CAMERA_POSITION,
    CAMERA_DIRECTION,
    CAMERA_UP,
    CAMERA_LOOK_AT,
    CAMERA_FOV,
    CAMERA_NEAR,
    CAMERA_APERTURE,
    CAMERA_FOCUS,
    CAMERA_PROJECTION,
    CAMERA_KEY_COUNT
};
static const key_spec camera_keys[CAMERA_KEY_COUNT] = {
    {"position", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"direction", "x y z", VALUE_NUMBER, NO_RANGE},
    {"up", "x y z", VALUE_NUMBER, NO_RANGE},
    {"look_at", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"fov", NULL, VALUE_NUMBER, FOV_RANGE},
    {"near", NULL, VALUE_NUMBER, 0.0, 1e18, false},
    {"aperture", NULL, VALUE_NUMBER, 0.0, 1e18, false},
    {"focus", NULL, VALUE_NUMBER, 0.0, 1e18, true},
    {"projection", "perspective orthographic", VALUE_WORD, 0.0, 1.0, false},
};

enum { PLANE_WIDTH, PLANE_HEIGHT, PLANE_PIXEL, PLANE_KEY_COUNT };
static const key_spec plane_keys[PLANE_KEY_COUNT] = {
    {"width", NULL, VALUE_NUMBER, PLANE_RANGE},
    {"height", NULL, VALUE_NUMBER, PLANE_RANGE},
    {"pixel", NULL, VALUE_NUMBER, PLANE_RANGE},
};

enum {
    RENDER_SAMPLES,
    RENDER_INDIRECT,
    RENDER_BOUNCES,
    RENDER_SEED,
    RENDER_MODE,
    RENDER_ROULETTE,
    RENDER_SAMPLER,
    RENDER_LIGHT_SAMPLES,
    RENDER_NOISE_THRESHOLD,
    RENDER_KEY_COUNT
};
/* The words of `render mode`, in render_mode order, then "seed", report's old name. */
#define RENDER_MODE_WORDS "report path seed"
/* The words of `render sampler`, in render_sampler order from random. */
#define RENDER_SAMPLER_WORDS "random sobol"
static const key_spec render_keys[RENDER_KEY_COUNT] = {
    {"samples", NULL, VALUE_INTEGER, 1.0, SCENE_MAX_SAMPLES, false},
    {"indirect", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    {"bounces", NULL, VALUE_INTEGER, 0.0, SCENE_MAX_BOUNCES, false},
    {"seed", NULL, VALUE_INTEGER, 0.0, UINT32_MAX, false},
    {"mode", RENDER_MODE_WORDS, VALUE_WORD, 0.0, 2.0, false},
    {"roulette", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    {"sampler", RENDER_SAMPLER_WORDS, VALUE_WORD, 0.0, 1.0, false},
    {"light_samples", NULL, VALUE_INTEGER, 1.0, SCENE_MAX_LIGHT_SAMPLES, false},
    {"noise_threshold", NULL, VALUE_NUMBER, 0.0, 1e6, false},
};

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

/* The lens and the projection: an aperture above 0 needs a focus, a focus needs an aperture,
 * and an orthographic camera has no field of view. */
static bool camera_lens(parser *p, const key_values *kv) {
    float aperture = (float)parser_value_or(kv, CAMERA_APERTURE, 0.0);
    if (aperture > 0.0f && !(kv->given & BIT(CAMERA_FOCUS))) {
        return parser_fail(p, p->tokens[kv->key_token[CAMERA_APERTURE]].col,
                           "camera aperture above 0 needs focus (the distance to the plane in "
                           "focus)");
    }
    if ((kv->given & BIT(CAMERA_FOCUS)) && !(aperture > 0.0f)) {
        return parser_fail(p, p->tokens[kv->key_token[CAMERA_FOCUS]].col,
                           "camera focus needs an aperture above 0 (a pinhole is sharp at every "
                           "distance)");
    }
    bool orthographic = parser_value_or(kv, CAMERA_PROJECTION, 0.0) == 1.0;
    if (orthographic && (kv->given & BIT(CAMERA_FOV))) {
        return parser_fail(p, p->tokens[kv->key_token[CAMERA_FOV]].col,
                           "an orthographic camera takes no fov: the plane's width and height "
                           "are the view's size");
    }
    p->s.camera_aperture = aperture;
    p->s.camera_focus = aperture > 0.0f ? (float)kv->value[CAMERA_FOCUS][0] : 0.0f;
    p->s.camera_orthographic = orthographic;
    return true;
}

bool directive_camera(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->camera_line)) return false;
    if (p->token_count > 1 && parser_token_is(&p->tokens[1], "file"))
        return directive_camera_file(p);
    if (!parser_keys(p, "camera", camera_keys, CAMERA_KEY_COUNT, ~0u, 1, &kv) ||
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
    if (!camera_lens(p, &kv)) return false;
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

/* The error for a pixel size that does not divide one side of the plane: it names the side and
 * proposes the nearest pixel sizes that divide it, and one that divides both sides if any. */
static bool fail_pixel(parser *p, const key_values *kv, int side, const token *size_token,
                       const token *pixel_token) {
    double size = kv->value[side][0], other = kv->value[side ^ 1][0];
    float pixel = (float)kv->value[PLANE_PIXEL][0];
    double ratio = size / pixel;
    char message[sizeof p->err->message] = "";
    directive_append(
        message, sizeof message, "plane %s %s is not a whole number of pixels of %s (%.2f); ",
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
        directive_append(message, sizeof message,
                         "the nearest pixel size that divides it is %s (%ld px)", text[0],
                         counts[0]);
    } else {
        directive_append(message, sizeof message,
                         "nearest pixel sizes that divide it: %s (%ld px), %s (%ld px)", text[0],
                         counts[0], text[1], counts[1]);
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
        directive_append(
            message, sizeof message, "; one that divides width and height: %s (%ld x %ld px)", both,
            side == PLANE_WIDTH ? best : other_count, side == PLANE_WIDTH ? other_count : best);
    }
    return parser_fail(p, pixel_token->col, "%s", message);
}

bool directive_plane(parser *p) {
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

bool directive_render(parser *p) {
    key_values kv;
    if (!claim_once(p, &p->render_line) ||
        !parser_keys(p, "render", render_keys, RENDER_KEY_COUNT, ~0u, 1, &kv)) {
        return false;
    }
    p->s.spp = (int)parser_value_or(&kv, RENDER_SAMPLES, 64);
    p->s.indirect = parser_value_or(&kv, RENDER_INDIRECT, 1) != 0;
    p->s.mode = scene_mode_of_word((int)parser_value_or(&kv, RENDER_MODE, RENDER_MODE_REPORT));
    p->s.bounces_given = kv.given & BIT(RENDER_BOUNCES);
    p->s.bounces = (int)parser_value_or(&kv, RENDER_BOUNCES, scene_default_bounces(p->s.mode));
    p->s.seed = (uint32_t)parser_value_or(&kv, RENDER_SEED, 1);
    p->s.roulette = parser_value_or(&kv, RENDER_ROULETTE, 1) != 0;
    if (kv.given & BIT(RENDER_SAMPLER))
        p->s.sampler =
            (render_sampler)(RENDER_SAMPLER_RANDOM + (int)parser_value_or(&kv, RENDER_SAMPLER, 0));
    p->s.light_samples = (int)parser_value_or(&kv, RENDER_LIGHT_SAMPLES, 1);
    p->s.noise_threshold = (float)parser_value_or(&kv, RENDER_NOISE_THRESHOLD, 0.0);
    if (kv.given & BIT(RENDER_ROULETTE))
        p->roulette_col = p->tokens[kv.key_token[RENDER_ROULETTE]].col;
    if (kv.given & BIT(RENDER_INDIRECT))
        p->indirect_col = p->tokens[kv.key_token[RENDER_INDIRECT]].col;
    if (kv.given & BIT(RENDER_LIGHT_SAMPLES))
        p->light_samples_col = p->tokens[kv.key_token[RENDER_LIGHT_SAMPLES]].col;
    return true;
}
