/* scene_primitives.c: the primitive directives, sphere, triangle and quad (DESIGN section 2;
 * scenes/README.md), the ones a chunk parsed ahead may hold; and the face checks and appends that
 * mesh lines reuse (directives.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/parser.h"
#include "shared_layout.h"

/* Radii: as far as positions go (COORD_RANGE), zero excluded. */
#define RADIUS_RANGE 0.0, 1e18, true
/* Texture coordinates: a texture repeats, so any within float's exact integers. */
#define UV_RANGE -16777216.0, 16777216.0, false

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
    TRIANGLE_UV0 = TRIANGLE_N0 + 3,
    TRIANGLE_MATERIAL = TRIANGLE_UV0 + 3,
    TRIANGLE_KEY_COUNT = TRIANGLE_MATERIAL + MAT_KEY_COUNT
};
static const key_spec triangle_keys[TRIANGLE_KEY_COUNT] = {
    {"v0", "x y z", VALUE_NUMBER, COORD_RANGE}, {"v1", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v2", "x y z", VALUE_NUMBER, COORD_RANGE}, {"n0", "x y z", VALUE_NUMBER, NO_RANGE},
    {"n1", "x y z", VALUE_NUMBER, NO_RANGE},    {"n2", "x y z", VALUE_NUMBER, NO_RANGE},
    {"uv0", "u v", VALUE_NUMBER, UV_RANGE},     {"uv1", "u v", VALUE_NUMBER, UV_RANGE},
    {"uv2", "u v", VALUE_NUMBER, UV_RANGE},     MATERIAL_KEY_SPECS,
};
_Static_assert(TRIANGLE_KEY_COUNT <= MAX_KEYS, "raise MAX_KEYS");

enum {
    QUAD_V0,
    QUAD_UV0 = QUAD_V0 + 4,
    QUAD_MATERIAL = QUAD_UV0 + 4,
    QUAD_KEY_COUNT = QUAD_MATERIAL + MAT_KEY_COUNT
};
static const key_spec quad_keys[QUAD_KEY_COUNT] = {
    {"v0", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v1", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v2", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"v3", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"uv0", "u v", VALUE_NUMBER, UV_RANGE},
    {"uv1", "u v", VALUE_NUMBER, UV_RANGE},
    {"uv2", "u v", VALUE_NUMBER, UV_RANGE},
    {"uv3", "u v", VALUE_NUMBER, UV_RANGE},
    MATERIAL_KEY_SPECS,
};
_Static_assert(QUAD_KEY_COUNT <= MAX_KEYS, "raise MAX_KEYS");

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
    .required = LOW_BITS(QUAD_UV0), /* v0 v1 v2 v3 */
};

/* Spheres and triangles share one primitive index: false (reported at the directive word) when
 * `adding` more would pass PARSER_MAX_PRIMITIVES. */
static bool reserve_primitives(parser *p, int adding) {
    long long total =
        (long long)p->s.sphere_count + p->s.triangle_count + p->s.model_face_count + adding;
    if (total <= PARSER_MAX_PRIMITIVES) return true;
    return parser_fail(p, p->tokens[0].col,
                       "too many primitives (spheres and triangles together, a quad counting as "
                       "two; the maximum is %d)",
                       PARSER_MAX_PRIMITIVES);
}

bool directive_sphere(parser *p) {
    const material_spec *m;
    key_values kv;
    if (!shape_read(p, &sphere_shape, &m, &kv)) return false;
    void *array = p->s.spheres;
    bool ok = directive_grow(p, &array, &p->sphere_capacity, p->s.sphere_count, 1,
                             SCENE_MAX_SPHERES, sizeof(sphere), "spheres");
    p->s.spheres = array;
    if (!ok || !reserve_primitives(p, 1)) return false;
    if (kv.given & BIT(SPHERE_MATERIAL + MAT_ALPHA_MAP))
        return parser_fail(p, p->tokens[kv.value_token[SPHERE_MATERIAL + MAT_ALPHA_MAP][0]].col,
                           "alpha_map: cut-outs are for faces (triangle, quad, mesh), not spheres");
    material f = shape_material_of(p, &sphere_shape, m, &kv);
    uint32_t index;
    if (!material_maps_read(p, SPHERE_MATERIAL, &kv, &f) || !material_add(p, &f, &index))
        return false;
    p->s.spheres[p->s.sphere_count++] = (sphere){
        .center = parser_vec3(&kv, SPHERE_CENTER, v3(0, 0, 0)),
        .radius = (float)parser_value_or(&kv, SPHERE_RADIUS, 0.0),
        .material = index,
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

/* True, with the reason in why, unless face a b c is one the renderer can normalize in single
 * precision: not degenerate (SCENE_FACE_MIN_SHAPE) and twice its area within
 * [SCENE_FACE_MIN_CROSS, SCENE_FACE_MAX_CROSS]. `what` names the face ("triangle", "quad half
 * v0 v1 v2"). */
bool face_problem(vec3 a, vec3 b, vec3 c, const char *what, char *why, size_t size) {
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

void face_add(parser *p, vec3 a, vec3 b, vec3 c, uint32_t material, uint32_t normals) {
    p->s.triangles[p->s.triangle_count++] = (triangle){{a, b, c}, material, normals};
}

bool material_add(parser *p, const material *m, uint32_t *index) {
    int n = p->s.material_count;
    if (n > 0 && material_same(&p->s.materials[n - 1], m)) {
        *index = (uint32_t)n - 1;
        return true;
    }
    void *array = p->s.materials;
    bool ok = directive_grow(p, &array, &p->material_capacity, n, 1, PARSER_MAX_PRIMITIVES,
                             sizeof(material), "materials");
    p->s.materials = array;
    if (!ok) return false;
    p->s.materials[n] = *m;
    p->s.material_count = n + 1;
    *index = (uint32_t)n;
    return true;
}

bool normals_reserve(parser *p, int adding) {
    void *array = p->s.normals;
    bool ok = directive_grow(p, &array, &p->normals_capacity, p->s.normals_count, adding,
                             PARSER_MAX_PRIMITIVES, sizeof(face_normals), "shading normals");
    p->s.normals = array;
    return ok;
}

uint32_t normals_add(parser *p, const vec3 n[3]) {
    p->s.normals[p->s.normals_count] = (face_normals){.n = {n[0], n[1], n[2]}};
    return (uint32_t)p->s.normals_count++;
}

/* Room for `adding` triangles; false (reported) past the limits or out of memory. */
bool faces_reserve(parser *p, int adding) {
    if (!reserve_primitives(p, adding)) return false;
    void *array = p->s.triangles;
    bool ok = directive_grow(p, &array, &p->triangle_capacity, p->s.triangle_count, adding,
                             PARSER_MAX_PRIMITIVES, sizeof(triangle), "triangles");
    p->s.triangles = array;
    return ok;
}

bool directive_triangle(parser *p) {
    const material_spec *m;
    key_values kv;
    if (!shape_read(p, &triangle_shape, &m, &kv)) return false;
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
    unsigned uvs = kv.given & (BIT(TRIANGLE_UV0) | BIT(TRIANGLE_UV0 + 1) | BIT(TRIANGLE_UV0 + 2));
    if (uvs && uvs != (BIT(TRIANGLE_UV0) | BIT(TRIANGLE_UV0 + 1) | BIT(TRIANGLE_UV0 + 2))) {
        int given = TRIANGLE_UV0, missing = TRIANGLE_UV0;
        while (!(uvs & BIT(given))) given++;
        while (uvs & BIT(missing)) missing++;
        return parser_fail(p, p->tokens[kv.key_token[given]].col,
                           "triangle %s needs %s: texture coordinates come all three (uv0 uv1 "
                           "uv2) or none",
                           triangle_keys[given].name, triangle_keys[missing].name);
    }
    bool corners = normals || uvs;
    if (!check_face(p, v[0], v[1], v[2], "triangle") || !faces_reserve(p, 1) ||
        (corners && !normals_reserve(p, 1)))
        return false;
    material f = shape_material_of(p, &triangle_shape, m, &kv);
    uint32_t index;
    if (!material_maps_read(p, TRIANGLE_MATERIAL, &kv, &f) || !material_add(p, &f, &index))
        return false;
    uint32_t at = corners ? normals_add(p, n) : TRIANGLE_FLAT;
    for (int k = 0; uvs && k < 3; k++) {
        p->s.normals[at].uv[k][0] = (float)kv.value[TRIANGLE_UV0 + k][0];
        p->s.normals[at].uv[k][1] = (float)kv.value[TRIANGLE_UV0 + k][1];
    }
    face_add(p, v[0], v[1], v[2], index, at);
    return true;
}

/* A quad is stored as (v0 v1 v2) and (v0 v2 v3): both must be faces, v3 on the plane of the
 * first (SCENE_QUAD_PLANE_TOLERANCE) and the quad convex, so that the halves tile it without
 * folding over each other. */
bool directive_quad(parser *p) {
    const material_spec *m;
    key_values kv;
    if (!shape_read(p, &quad_shape, &m, &kv)) return false;
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
    material f = shape_material_of(p, &quad_shape, m, &kv);
    if (!material_maps_read(p, QUAD_MATERIAL, &kv, &f)) return false;
    /* Texture coordinates where given or where a map reads them: the unit square by default. */
    bool corners = (kv.given & (LOW_BITS(4) << QUAD_UV0)) || material_textured(&f);
    uint32_t index;
    if (!faces_reserve(p, 2) || (corners && !normals_reserve(p, 2)) || !material_add(p, &f, &index))
        return false;
    if (!corners) {
        face_add(p, v[0], v[1], v[2], index, TRIANGLE_FLAT);
        face_add(p, v[0], v[2], v[3], index, TRIANGLE_FLAT);
        return true;
    }
    static const float unit[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    float uv[4][2];
    for (int k = 0; k < 4; k++)
        for (int c = 0; c < 2; c++)
            uv[k][c] = kv.given & BIT(QUAD_UV0 + k) ? (float)kv.value[QUAD_UV0 + k][c] : unit[k][c];
    static const int halves[2][3] = {{0, 1, 2}, {0, 2, 3}};
    const vec3 flat[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int h = 0; h < 2; h++) {
        uint32_t at = normals_add(p, flat);
        for (int k = 0; k < 3; k++) memcpy(p->s.normals[at].uv[k], uv[halves[h][k]], sizeof uv[0]);
        face_add(p, v[halves[h][0]], v[halves[h][1]], v[halves[h][2]], index, at);
    }
    return true;
}
