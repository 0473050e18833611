/* scene_lights.c: the light directives (scenes/README.md): `light`, a point light or, with
 * `direction` and `cone`, a spot; `sun`, a distant light; with their errors. */
#include <float.h>
#include <math.h>
#include <stdio.h>

#include "scene/directives.h"
#include "scene/parser.h"

#define DEGREES (3.14159265358979323846 / 180.0)

enum { LIGHT_POSITION, LIGHT_POWER, LIGHT_COLOR, LIGHT_DIRECTION, LIGHT_CONE, LIGHT_KEY_COUNT };
static const key_spec light_keys[LIGHT_KEY_COUNT] = {
    {"position", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"power", NULL, VALUE_NUMBER, 0.0, FLT_MAX, false},
    {"color", "r g b", VALUE_NUMBER, UNIT_RANGE},
    {"direction", "x y z", VALUE_NUMBER, NO_RANGE},
    {"cone", "inner outer", VALUE_NUMBER, 0.0, 90.0, true},
};

enum { SUN_DIRECTION, SUN_IRRADIANCE, SUN_COLOR, SUN_ANGLE, SUN_KEY_COUNT };
static const key_spec sun_keys[SUN_KEY_COUNT] = {
    {"direction", "x y z", VALUE_NUMBER, NO_RANGE},
    {"irradiance", NULL, VALUE_NUMBER, 0.0, FLT_MAX, false},
    {"color", "r g b", VALUE_NUMBER, UNIT_RANGE},
    {"angle", NULL, VALUE_NUMBER, 0.0, 90.0, false},
};

/* The sun's angular diameter in degrees by default: the Sun's, seen from the Earth. */
#define SUN_DEFAULT_ANGLE 0.53

/* The unit vector of key's value (in double, rounded once); false (reported at the key) when it
 * is zero. */
static bool unit_direction(parser *p, const key_values *kv, int key, const char *what, vec3 *out) {
    double x = kv->value[key][0], y = kv->value[key][1], z = kv->value[key][2];
    double m = fmax(fabs(x), fmax(fabs(y), fabs(z)));
    if (!(m > 0.0)) {
        return parser_fail(p, p->tokens[kv->key_token[key]].col, "%s direction must not be zero",
                           what);
    }
    x /= m, y /= m, z /= m;
    double l = sqrt(x * x + y * y + z * z);
    *out = v3((float)(x / l), (float)(y / l), (float)(z / l));
    return true;
}

/* Appends l to the scene's lights; false (reported) past SCENE_MAX_LIGHTS. */
static bool add_light(parser *p, light l) {
    void *array = p->s.lights;
    bool ok = directive_grow(p, &array, &p->light_capacity, p->s.light_count, 1, SCENE_MAX_LIGHTS,
                             sizeof(light), "lights");
    p->s.lights = array;
    if (ok) p->s.lights[p->s.light_count++] = l;
    return ok;
}

bool directive_light(parser *p) {
    key_values kv;
    if (!parser_keys(p, "light", light_keys, LIGHT_KEY_COUNT, ~0u, 1, &kv) ||
        !parser_require_keys(p, "light", light_keys, LIGHT_KEY_COUNT,
                             BIT(LIGHT_POSITION) | BIT(LIGHT_POWER), &kv)) {
        return false;
    }
    light l = {
        .position = parser_vec3(&kv, LIGHT_POSITION, v3(0, 0, 0)),
        .power = (float)parser_value_or(&kv, LIGHT_POWER, 0.0),
        .color = parser_vec3(&kv, LIGHT_COLOR, v3(1, 1, 1)),
        .kind = LIGHT_POINT,
    };
    unsigned spot = BIT(LIGHT_DIRECTION) | BIT(LIGHT_CONE);
    if ((kv.given & spot) != 0 && (kv.given & spot) != spot) {
        int given = (kv.given & BIT(LIGHT_DIRECTION)) ? LIGHT_DIRECTION : LIGHT_CONE;
        return parser_fail(p, p->tokens[kv.key_token[given]].col,
                           "a spot light takes both direction and cone");
    }
    if (kv.given & spot) {
        double inner = kv.value[LIGHT_CONE][0], outer = kv.value[LIGHT_CONE][1];
        if (inner > outer) {
            return parser_fail(p, p->tokens[kv.value_token[LIGHT_CONE][0]].col,
                               "cone inner angle %g is above the outer angle %g", inner, outer);
        }
        if (!unit_direction(p, &kv, LIGHT_DIRECTION, "light", &l.direction)) return false;
        l.kind = LIGHT_SPOT;
        l.cos_inner = (float)cos(inner * DEGREES);
        l.cos_outer = (float)cos(outer * DEGREES);
    }
    return add_light(p, l);
}

bool directive_sun(parser *p) {
    key_values kv;
    if (!parser_keys(p, "sun", sun_keys, SUN_KEY_COUNT, ~0u, 1, &kv) ||
        !parser_require_keys(p, "sun", sun_keys, SUN_KEY_COUNT,
                             BIT(SUN_DIRECTION) | BIT(SUN_IRRADIANCE), &kv)) {
        return false;
    }
    light l = {
        .power = (float)parser_value_or(&kv, SUN_IRRADIANCE, 0.0),
        .color = parser_vec3(&kv, SUN_COLOR, v3(1, 1, 1)),
        .kind = LIGHT_SUN,
        .angle = (float)parser_value_or(&kv, SUN_ANGLE, SUN_DEFAULT_ANGLE),
    };
    for (int k = 0; k < p->s.light_count; k++)
        if (p->s.lights[k].kind == LIGHT_SUN)
            return parser_fail(p, p->tokens[0].col, "a scene has one sun at most");
    if (!unit_direction(p, &kv, SUN_DIRECTION, "sun", &l.direction)) return false;
    return add_light(p, l);
}
