/* mesh_lights.c: a model file's lights as the scene's lights (`mesh ... lights on`): glTF's
 * KHR_lights_punctual point and spot lights as `light` lines, its directional light as the `sun`
 * (a delta: glTF's is), in the units scenes/README.md's "A model file as the scene" states. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/mesh_load.h"

/* A spot's cone no wider than this (radians, just under 90 degrees), as a `light` line's. */
#define SPOT_MAX_ANGLE 1.5707963267948966

/* The unit vector of a file light's direction moved by xf; false when it is zero or not finite
 * once moved. */
static bool moved_direction(const mesh_transform *xf, vec3 d, vec3 *out) {
    vec3 m = mesh_transform_direction(xf, d);
    double x = m.x, y = m.y, z = m.z, l = sqrt(x * x + y * y + z * z);
    if (!(l > 0.0) || !isfinite(l)) return false;
    *out = v3((float)(x / l), (float)(y / l), (float)(z / l));
    return true;
}

/* File light k as a scene light in *out; false (reported at col) when it cannot be one. */
static bool light_of(parser *p, const mesh_light *l, int k, const mesh_transform *xf,
                     const char *path, int col, light *out) {
    bool sun = !strcmp(l->kind, "directional"), spot = !strcmp(l->kind, "spot");
    *out = (light){.kind = sun ? LIGHT_SUN : spot ? LIGHT_SPOT : LIGHT_POINT};
    if (!mesh_light_power(l, &out->power, &out->color))
        return parser_fail(p, col,
                           "mesh '%s': light %d '%s' (%s) has colour x intensity %g %g %g: "
                           "each must be finite and at least 0",
                           path, k, l->name, l->kind, l->color[0], l->color[1], l->color[2]);
    if (!sun && !mesh_transform_point(xf, l->position, &out->position))
        return parser_fail(p, col,
                           "mesh '%s': light %d '%s' leaves the coordinate range (1e18) once "
                           "transformed",
                           path, k, l->name);
    if ((sun || spot) && !moved_direction(xf, l->direction, &out->direction))
        return parser_fail(p, col, "mesh '%s': light %d '%s' (%s) has no direction once moved",
                           path, k, l->name, l->kind);
    if (spot) {
        /* glTF: 0 <= inner < outer <= pi / 2 */
        if (!(l->inner >= 0.0) || !(l->outer > 0.0) || !(l->inner <= l->outer) ||
            l->outer > SPOT_MAX_ANGLE)
            return parser_fail(p, col,
                               "mesh '%s': spot light %d '%s' has a cone of %g to %g radians: "
                               "they must be 0 <= inner <= outer <= pi/2, outer above 0",
                               path, k, l->name, l->inner, l->outer);
        out->cos_inner = (float)cos(l->inner);
        out->cos_outer = (float)cos(l->outer);
    }
    return true;
}

bool mesh_lights_add(parser *p, const mesh *me, const mesh_transform *xf, const char *path,
                     int col) {
    char others[256] = "";
    size_t used = 0;
    bool has_sun = false;
    for (int k = 0; k < p->s.light_count; k++) has_sun |= p->s.lights[k].kind == LIGHT_SUN;
    for (int k = 0; k < me->light_count; k++) {
        const mesh_light *l = &me->lights[k];
        bool sun = !strcmp(l->kind, "directional");
        bool known = sun || !strcmp(l->kind, "point") || !strcmp(l->kind, "spot");
        if (!known || (sun && has_sun)) { /* a scene has one sun at most */
            if (used < sizeof others)
                used += (size_t)snprintf(others + used, sizeof others - used, "%s%s light '%s'%s",
                                         used ? ", " : "", l->kind, l->name,
                                         known ? " (a second sun)" : "");
            continue;
        }
        light out;
        if (!light_of(p, l, k, xf, path, col, &out)) return false;
        has_sun |= sun;
        void *array = p->s.lights;
        bool ok = directive_grow(p, &array, &p->light_capacity, p->s.light_count, 1,
                                 SCENE_MAX_LIGHTS, sizeof(light), "lights");
        p->s.lights = array;
        if (!ok) return false;
        p->s.lights[p->s.light_count++] = out;
    }
    if (others[0])
        parser_warn(p, p->line, col,
                    "mesh '%s': its %s %s not rendered: trazador renders point, spot and one "
                    "directional light",
                    path, others, strchr(others, ',') ? "are" : "is");
    return true;
}
