/* test_parse.c: the scene parser on valid input (exact struct values, defaults, layout freedom),
 * on every kind of invalid input (line, column and message), on files, and the same scene, warnings
 * and first error for every thread count on texts big enough to be parsed in chunks. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "scene/scene.h"

static int passed, failed;

/* Counts one check; prints the case name and why when it fails. */
static bool check(bool ok, const char *name, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bool check(bool ok, const char *name, const char *fmt, ...) {
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

static bool vec_is(vec3 v, float x, float y, float z) { return v.x == x && v.y == y && v.z == z; }

/* Parses text that must be valid; on failure prints the parser's error under `name`. */
static bool parse_ok(const char *name, const char *text, size_t length, scene *s) {
    scene_error err;
    bool ok = scene_parse_string(text, length, "test.scene", s, &err);
    return check(ok, name, "unexpected error %d:%d: %s", err.line, err.col, err.message);
}

#define BYTES(literal) literal, sizeof(literal) - 1
/* Two valid lines that most invalid cases start from, so their errors land on line 3. */
#define BASE "camera position 0 0 0\nplane width 4 height 3 pixel 0.01\n"

static const char full_example[] =
    "camera  position 0 1 -8   direction 0 0 1   up 0 1 0\n"
    "plane   width 4  height 3  pixel 0.01\n"
    "light   position -2 3 -1  power 60  color 1 1 1\n"
    "sphere  lambertian center 0 -1001 0 radius 1000 color 0.8 0.8 0.8\n"
    "sphere  phong      center -1 0 2 radius 1 color 0.6 0.1 0.1 ks 0.3 alpha 40\n"
    "sphere  mirror     center  1 0 3 radius 1\n"
    "sphere  refractive center  0 0 1 radius 0.7 ior 1.5\n"
    "background 0 0 0\n"
    "render  samples 64 indirect on bounces 5 seed 1\n";

static void check_full_example(const char *name, const scene *s) {
    check(vec_is(s->camera_position, 0, 1, -8), name, "camera position");
    check(vec_is(s->camera_direction, 0, 0, 1), name, "camera direction");
    check(vec_is(s->camera_up, 0, 1, 0), name, "camera up");
    check(s->plane_width == 4.0f && s->plane_height == 3.0f && s->pixel_size == 0.01f, name,
          "plane %g %g %g", s->plane_width, s->plane_height, s->pixel_size);
    check(s->width == 400 && s->height == 300, name, "resolution %dx%d", s->width, s->height);
    check(vec_is(s->background, 0, 0, 0), name, "background");
    check(s->spp == 64 && s->indirect && s->bounces == 5 && s->seed == 1 &&
              s->mode == RENDER_MODE_REPORT,
          name, "render settings");
    if (!check(s->light_count == 1 && s->sphere_count == 4, name, "counts %d lights %d spheres",
               s->light_count, s->sphere_count)) {
        return;
    }
    const light *l = &s->lights[0];
    check(vec_is(l->position, -2, 3, -1) && l->power == 60.0f && vec_is(l->color, 1, 1, 1), name,
          "light");
    const sphere *p = s->spheres;
    check(p[0].material == TZ_MATERIAL_LAMBERTIAN && vec_is(p[0].center, 0, -1001, 0) &&
              p[0].radius == 1000.0f && vec_is(p[0].color, 0.8f, 0.8f, 0.8f) && p[0].ks == 0 &&
              p[0].alpha == 0 && p[0].ior == 1.0f && vec_is(p[0].emission, 0, 0, 0),
          name, "lambertian sphere");
    check(p[1].material == TZ_MATERIAL_PHONG && vec_is(p[1].center, -1, 0, 2) && p[1].radius == 1 &&
              vec_is(p[1].color, 0.6f, 0.1f, 0.1f) && p[1].ks == 0.3f && p[1].alpha == 40.0f &&
              p[1].ior == 1.0f && vec_is(p[1].emission, 0, 0, 0),
          name, "phong sphere");
    check(p[2].material == TZ_MATERIAL_MIRROR && vec_is(p[2].center, 1, 0, 3) && p[2].radius == 1 &&
              vec_is(p[2].color, 1, 1, 1) && p[2].ks == 0 && p[2].alpha == 0 && p[2].ior == 1.0f &&
              vec_is(p[2].emission, 0, 0, 0),
          name, "mirror sphere");
    check(p[3].material == TZ_MATERIAL_REFRACTIVE && vec_is(p[3].center, 0, 0, 1) &&
              p[3].radius == 0.7f && vec_is(p[3].color, 1, 1, 1) && p[3].ks == 0 &&
              p[3].alpha == 0 && p[3].ior == 1.5f && vec_is(p[3].emission, 0, 0, 0),
          name, "refractive sphere");
}

static void test_valid(void) {
    scene s;
    if (parse_ok("full example", BYTES(full_example), &s)) {
        check_full_example("full example", &s);
        scene_free(&s);
    }

    /* Small camera vectors whose squared lengths are still normal floats normalize exactly. */
    static const char small_camera[] =
        "camera position 0 0 0 direction 0 0 2e-19 up 0 1e-10 0\n"
        "plane width 2 height 1 pixel 0.5\n";
    if (parse_ok("small camera vectors", BYTES(small_camera), &s)) scene_free(&s);

    static const char defaults[] =
        "camera position 1 2 3\n"
        "plane width 2 height 1 pixel 0.5\n"
        "light position 0 5 0 power 10\n"
        "sphere phong center 0 0 0 radius 1\n"
        "sphere lambertiana center 0 0 0 radius 1\n"
        "sphere espejo center 0 0 0 radius 1\n"
        "sphere refractada center 0 0 0 radius 1\n"
        "sphere lambertian center 0 0 0 radius 1\n";
    if (parse_ok("defaults", BYTES(defaults), &s)) {
        const char *n = "defaults";
        check(vec_is(s.camera_direction, 0, 0, 1) && vec_is(s.camera_up, 0, 1, 0), n, "camera");
        check(s.width == 4 && s.height == 2, n, "resolution %dx%d", s.width, s.height);
        check(vec_is(s.lights[0].color, 1, 1, 1), n, "light color");
        check(vec_is(s.background, 0, 0, 0), n, "background");
        check(s.spp == 64 && s.indirect && s.bounces == 5 && s.seed == 1 &&
                  s.mode == RENDER_MODE_REPORT,
              n, "render settings");
        const sphere *p = s.spheres;
        check(p[0].material == TZ_MATERIAL_PHONG && vec_is(p[0].color, 0.8f, 0.8f, 0.8f) &&
                  p[0].ks == 0.5f && p[0].alpha == 32.0f && p[0].ior == 1.0f,
              n, "phong defaults");
        check(p[1].material == TZ_MATERIAL_LAMBERTIAN && vec_is(p[1].color, 0.8f, 0.8f, 0.8f) &&
                  p[1].ks == 0 && p[1].alpha == 0 && p[1].ior == 1.0f,
              n, "lambertiana");
        check(
            p[2].material == TZ_MATERIAL_MIRROR && vec_is(p[2].color, 1, 1, 1) && p[2].ior == 1.0f,
            n, "espejo");
        check(p[3].material == TZ_MATERIAL_REFRACTIVE && vec_is(p[3].color, 1, 1, 1) &&
                  p[3].ior == 1.5f,
              n, "refractada");
        check(p[4].material == TZ_MATERIAL_LAMBERTIAN && vec_is(p[4].color, 0.8f, 0.8f, 0.8f), n,
              "lambertian color");
        scene_free(&s);
    }

    static const char settings[] = BASE
        "render seed 4294967295 bounces 64 indirect off samples 1048576\n"
        "background 0.5 2 0\n"
        "sphere mirror radius 2 color 0.5 0.25 0 center 1 2 3\n";
    if (parse_ok("render settings, background, key order", BYTES(settings), &s)) {
        const char *n = "render settings";
        check(s.spp == SCENE_MAX_SAMPLES && !s.indirect && s.bounces == SCENE_MAX_BOUNCES &&
                  s.seed == 4294967295u,
              n, "got %d %d %d %u", s.spp, s.indirect, s.bounces, s.seed);
        check(vec_is(s.background, 0.5f, 2, 0), n, "background above 1 is allowed");
        check(vec_is(s.spheres[0].center, 1, 2, 3) && s.spheres[0].radius == 2 &&
                  vec_is(s.spheres[0].color, 0.5f, 0.25f, 0),
              n, "keys in any order");
        scene_free(&s);
    }

    /* The same scene as full_example, written with every layout freedom the format allows. */
    static const char layout[] =
        "# a header comment, with UTF-8: esfera lambertiana, cámara \xe2\x9c\x93\r\n"
        "\r\n"
        "   \t \r\n"
        "\tcamera up 0 1 0 direction 0 0 1\tposition 0 1 -8 # trailing comment\r\n"
        "plane pixel 0.01 height 3 width 4#comment glued to a value\n"
        "\n"
        "light color 1 1 1 power 60 position -2 3 -1\n"
        "sphere lambertiana color 0.8 .8 8e-1 radius 1e3 center 0 -1001 +0\r\n"
        "sphere phong alpha 40. ks 0.3 color 0.6 0.1 0.1 radius 1 center -1 0 2\n"
        "sphere espejo radius 1 center 1 0 3\n"
        "render seed 1 bounces 5 indirect on samples 64\n"
        "background 0 -0 0.0e+5\n"
        "sphere refractada ior 1.5 radius 0.7 center 0 0 1";
    if (parse_ok("layout freedom", BYTES(layout), &s)) {
        check_full_example("layout freedom", &s);
        scene_free(&s);
    }

    if (parse_ok("zero spheres and lights", BYTES(BASE), &s)) {
        check(s.sphere_count == 0 && s.light_count == 0 && !s.spheres && !s.lights,
              "zero spheres and lights", "counts %d %d", s.sphere_count, s.light_count);
        scene_free(&s);
    }

    if (parse_ok("pixel within 1e-6 of dividing",
                 BYTES("camera position 0 0 0\n"
                       "plane width 1 height 1 pixel 0.3333333\n"),
                 &s)) {
        check(s.width == 3 && s.height == 3, "pixel within 1e-6", "%dx%d", s.width, s.height);
        scene_free(&s);
    }

    if (parse_ok("largest resolution",
                 BYTES("camera position 0 0 0\nplane width 16384 height 1 pixel 1\n"), &s)) {
        check(s.width == 16384 && s.height == 1, "largest resolution", "%dx%d", s.width, s.height);
        scene_free(&s);
    }

    /* err may be NULL, and a NULL file name is reported as <string>. */
    check(!scene_parse_string(BYTES("spere"), "x", &s, NULL), "NULL err", "bad text accepted");
    if (check(scene_parse_string(BYTES(BASE), "x", &s, NULL), "NULL err", "good text refused")) {
        scene_free(&s);
    }
    scene_error err;
    check(!scene_parse_string(BYTES(""), NULL, &s, &err) && strcmp(err.file, "<string>") == 0,
          "NULL file name", "file '%s'", err.file);
}

static bool triangle_at(const triangle *t, vec3 a, vec3 b, vec3 c) {
    return vec_is(t->v[0], a.x, a.y, a.z) && vec_is(t->v[1], b.x, b.y, b.z) &&
           vec_is(t->v[2], c.x, c.y, c.z);
}

/* Triangles and quads: every field, defaults, the quad's split, Spanish names, and spheres and
 * faces kept apart in file order. */
static void test_faces(void) {
    static const char faces[] = BASE
        "triangle lambertian v0 0 0 0 v1 1 0 0 v2 0 1 0\n"
        "sphere mirror center 0 0 9 radius 1\n"
        "triangle phong v2 0 1 2 v0 -1 0 2 n1 3 4 0 v1 1 0 2 n0 0 0 -2 n2 0 0 -1e-30 "
        "color 0.5 0.25 1 ks 0.1 alpha 8\n"
        "quad espejo v0 0 0 0 v1 2 0 0 v2 2 0 2 v3 0 0 2 color 0.9 0.5 0.1\n"
        "triangle lambertiana v0 0 0 0 v1 1 0 0 v2 0 0 1 emission 1 2 3\n"
        "quad mirror v0 -1 -1 5 v1 1 -1 5 v2 1 1 5 v3 -1 1 5\n"
        "triangle espejo v0 0 0 0 v1 1 0 0 v2 0 1 0\n"
        "quad phong v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0 ks 1 alpha 0 emission 0 0 0.5\n"
        "sphere lambertian center 0 0 -9 radius 1\n"
        "render mode path\n";
    scene s;
    const char *n = "faces";
    if (!parse_ok(n, BYTES(faces), &s)) return;
    if (!check(s.triangle_count == 10 && s.sphere_count == 2, n, "%d triangles, %d spheres",
               s.triangle_count, s.sphere_count)) {
        scene_free(&s);
        return;
    }
    const triangle *t = s.triangles;
    check(triangle_at(&t[0], v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)) && !t[0].smooth &&
              vec_is(t[0].n[0], 0, 0, 0) && vec_is(t[0].n[1], 0, 0, 0) &&
              vec_is(t[0].n[2], 0, 0, 0) && t[0].material == TZ_MATERIAL_LAMBERTIAN &&
              vec_is(t[0].color, 0.8f, 0.8f, 0.8f) && t[0].ks == 0 && t[0].alpha == 0 &&
              t[0].ior == 1.0f && vec_is(t[0].emission, 0, 0, 0) && !triangle_emits(&t[0]),
          n, "lambertian triangle and its defaults");
    /* Keys in any order; normals of any length normalized, their direction kept. */
    check(triangle_at(&t[1], v3(-1, 0, 2), v3(1, 0, 2), v3(0, 1, 2)) && t[1].smooth &&
              vec_is(t[1].n[0], 0, 0, -1) && vec_is(t[1].n[1], 0.6f, 0.8f, 0) &&
              vec_is(t[1].n[2], 0, 0, -1) && t[1].material == TZ_MATERIAL_PHONG &&
              vec_is(t[1].color, 0.5f, 0.25f, 1) && t[1].ks == 0.1f && t[1].alpha == 8.0f &&
              t[1].ior == 1.0f,
          n, "phong triangle with normals: n1 %g %g %g", t[1].n[1].x, t[1].n[1].y, t[1].n[1].z);
    /* A quad is (v0 v1 v2) then (v0 v2 v3), both with its material. */
    check(triangle_at(&t[2], v3(0, 0, 0), v3(2, 0, 0), v3(2, 0, 2)) &&
              triangle_at(&t[3], v3(0, 0, 0), v3(2, 0, 2), v3(0, 0, 2)),
          n, "quad split");
    for (int k = 2; k <= 3; k++)
        check(t[k].material == TZ_MATERIAL_MIRROR && vec_is(t[k].color, 0.9f, 0.5f, 0.1f) &&
                  !t[k].smooth && vec_is(t[k].n[0], 0, 0, 0) && t[k].ks == 0 && t[k].ior == 1.0f,
              n, "espejo quad half %d", k - 2);
    check(t[4].material == TZ_MATERIAL_LAMBERTIAN && vec_is(t[4].color, 0.8f, 0.8f, 0.8f) &&
              vec_is(t[4].emission, 1, 2, 3) && triangle_emits(&t[4]),
          n, "lambertiana triangle with emission");
    check(triangle_at(&t[5], v3(-1, -1, 5), v3(1, -1, 5), v3(1, 1, 5)) &&
              triangle_at(&t[6], v3(-1, -1, 5), v3(1, 1, 5), v3(-1, 1, 5)) &&
              t[5].material == TZ_MATERIAL_MIRROR && vec_is(t[5].color, 1, 1, 1),
          n, "mirror quad");
    check(t[7].material == TZ_MATERIAL_MIRROR && vec_is(t[7].color, 1, 1, 1), n, "espejo triangle");
    for (int k = 8; k <= 9; k++)
        check(t[k].material == TZ_MATERIAL_PHONG && t[k].ks == 1.0f && t[k].alpha == 0.0f &&
                  vec_is(t[k].color, 0.8f, 0.8f, 0.8f) && vec_is(t[k].emission, 0, 0, 0.5f) &&
                  triangle_emits(&t[k]),
              n, "phong quad half %d", k - 8);
    check(vec_is(s.spheres[0].center, 0, 0, 9) && vec_is(s.spheres[1].center, 0, 0, -9), n,
          "spheres among the faces");
    scene_free(&s);
    check(!s.triangles && s.triangle_count == 0, n, "scene_free leaves triangles zeroed");

    /* The tolerances' edges: a quad 0.9e-5 of its diagonal off flat, a face of height 1.1e-5 of
     * its longest edge, faces just inside the sizes single precision can normalize. */
    static const char edges[] = BASE
        "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 1.27e-5\n"
        "triangle lambertian v0 0 0 0 v1 1 0 0 v2 0.5 1.1e-5 0\n"
        "triangle lambertian v0 0 0 0 v1 4e-10 0 0 v2 0 4e-10 0\n"
        "triangle lambertian v0 0 0 0 v1 3.6e9 0 0 v2 0 3.6e9 0\n"
        "quad mirror v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 -0.5 0.5 0\n"
        "triangle mirror v0 1e9 1e9 -1e9 v1 -1e9 1e9 -1e9 v2 1e9 -1e9 -1e9\n";
    n = "face tolerances";
    if (parse_ok(n, BYTES(edges), &s)) {
        check(s.triangle_count == 8, n, "%d triangles", s.triangle_count);
        scene_free(&s);
    }
}

typedef struct invalid_case {
    const char *name;
    const char *text;
    size_t length;
    int line, col;
    const char *message; /* expected substring */
} invalid_case;

static const invalid_case invalid_cases[] = {
    {"unknown directive", BYTES(BASE "spere lambertian"), 3, 1,
     "unknown directive 'spere' (expected one of: camera plane light sphere triangle quad "
     "mesh background render)"},
    {"unknown key", BYTES(BASE "sphere lambertian center 0 0 0 radiu 1"), 3, 32,
     "unknown key 'radiu' for sphere lambertian (expected one of: center radius color emission)"},
    {"ior on lambertian", BYTES(BASE "sphere lambertian center 0 0 0 radius 1 ior 1.5"), 3, 41,
     "unknown key 'ior' for sphere lambertian (expected one of: center radius color emission)"},
    {"ks on mirror", BYTES(BASE "sphere mirror center 0 0 0 radius 1 ks 0.5"), 3, 37,
     "unknown key 'ks' for sphere mirror (expected one of: center radius color emission)"},
    {"unknown key lists phong keys", BYTES(BASE "sphere phong center 0 0 0 radius 1 ior 2"), 3, 36,
     "(expected one of: center radius color ks alpha emission)"},
    {"emission in report mode",
     BYTES(BASE "sphere lambertian center 0 0 0 radius 1 emission 1 1 1"), 3, 41,
     "emission needs path mode: add 'render mode path'"},
    {"negative emission",
     BYTES(BASE "sphere lambertian center 0 0 0 radius 1 emission 1 -1 1\nrender mode path"), 3, 52,
     "emission must be >= 0, got -1"},
    {"infinite emission",
     BYTES(BASE "sphere lambertian center 0 0 0 radius 1 emission 1 1 inf\nrender mode path"), 3,
     54, "(NaN and infinities are not allowed)"},
    {"unknown mode", BYTES(BASE "render mode paths"), 3, 13,
     "expected one of report path seed for 'mode', got 'paths'"},
    {"roulette not a switch", BYTES(BASE "render mode path roulette 1"), 3, 27,
     "expected on or off for 'roulette'"},
    {"fov zero", BYTES("camera position 0 0 0 fov 0\nplane width 1 height 1 pixel 1\n"), 1, 27,
     "fov must be in (0, 179], got 0"},
    {"fov 180", BYTES("camera position 0 0 0 fov 180\nplane width 1 height 1 pixel 1\n"), 1, 27,
     "fov must be in (0, 179], got 180"},
    {"negative near", BYTES("camera position 0 0 0 near -1\nplane width 1 height 1 pixel 1\n"), 1,
     28, "near must be in [0, 1e+18], got -1"},
    {"look_at and direction",
     BYTES("camera position 0 0 0 direction 0 0 1 look_at 1 1 1\nplane width 1 height 1 pixel "
           "1\n"),
     1, 39, "camera takes direction or look_at, not both"},
    {"look_at at the camera",
     BYTES("camera position 1 2 3 look_at 1 2 3\nplane width 1 height 1 pixel 1\n"), 1, 23,
     "camera look_at must differ from position"},
    {"look_at parallel to up",
     BYTES("camera position 0 0 0 look_at 0 5 0\nplane width 1 height 1 pixel 1\n"), 1, 23,
     "camera up (0 1 0) is parallel to direction (0 1 0)"},
    {"missing value", BYTES(BASE "sphere lambertian center 0 0 0 radius"), 3, 38,
     "expected a value for 'radius', got end of line"},
    {"missing value before comment", BYTES(BASE "sphere lambertian center 0 0 0 radius # r"), 3, 38,
     "expected a value for 'radius'"},
    {"missing second component", BYTES(BASE "light power 5 position 1"), 3, 25,
     "expected 3 numbers (x y z) for 'position', got 1"},
    {"missing third component", BYTES(BASE "light power 5 position 1 2"), 3, 27,
     "expected 3 numbers (x y z) for 'position', got 2"},
    {"key where a component belongs", BYTES(BASE "light position 1 power 5"), 3, 18,
     "expected a number for 'position', got 'power'"},
    {"key given twice", BYTES(BASE "sphere lambertian center 0 0 0 radius 1 radius 2"), 3, 41,
     "'radius' given twice"},
    {"camera given twice", BYTES(BASE "camera position 1 1 1"), 3, 1,
     "'camera' given twice (first on line 1)"},
    {"plane given twice", BYTES(BASE "\nplane width 4 height 3 pixel 0.01"), 4, 1,
     "'plane' given twice (first on line 2)"},
    {"background given twice", BYTES(BASE "background 0 0 0\n  background 0 0 0"), 4, 3,
     "'background' given twice (first on line 3)"},
    {"render given twice", BYTES(BASE "render\nrender samples 2"), 4, 1,
     "'render' given twice (first on line 3)"},
    {"not a number", BYTES(BASE "sphere lambertian center 0 0 0 radius abc"), 3, 39,
     "expected a number for 'radius', got 'abc'"},
    {"nan", BYTES(BASE "sphere lambertian center 0 0 0 radius nan"), 3, 39,
     "got 'nan' (NaN and infinities are not allowed)"},
    {"inf", BYTES(BASE "sphere lambertian center 0 0 0 radius inf"), 3, 39,
     "got 'inf' (NaN and infinities are not allowed)"},
    {"-inf", BYTES(BASE "sphere lambertian center -inf 0 0 radius 1"), 3, 26,
     "got '-inf' (NaN and infinities are not allowed)"},
    {"Infinity", BYTES(BASE "light position 0 0 0 power Infinity"), 3, 28,
     "got 'Infinity' (NaN and infinities are not allowed)"},
    {"hex float", BYTES(BASE "sphere lambertian center 0 0 0 radius 0x1p3"), 3, 39,
     "got '0x1p3' (hexadecimal numbers are not allowed)"},
    {"float overflow", BYTES(BASE "sphere lambertian center 0 0 0 radius 1e999"), 3, 39,
     "number '1e999' for 'radius' is out of range"},
    {"just above FLT_MAX", BYTES(BASE "sphere lambertian center 3.5e38 0 0 radius 1"), 3, 26,
     "number '3.5e38' for 'center' is out of range"},
    {"trailing garbage", BYTES(BASE "sphere lambertian center 0 0 0 radius 1.5x"), 3, 39,
     "expected a number for 'radius', got '1.5x'"},
    {"lone minus", BYTES(BASE "sphere lambertian center 0 - 0 radius 1"), 3, 28,
     "expected a number for 'center', got '-'"},
    {"lone dot", BYTES(BASE "sphere lambertian center 0 . 0 radius 1"), 3, 28,
     "expected a number for 'center', got '.'"},
    {"exponent without digits", BYTES(BASE "sphere lambertian center 0 1e+ 0 radius 1"), 3, 28,
     "got '1e+'"},
    {"two dots", BYTES(BASE "sphere lambertian center 0 1.2.3 0 radius 1"), 3, 28, "got '1.2.3'"},
    {"radius 0", BYTES(BASE "sphere lambertian center 0 0 0 radius 0"), 3, 39,
     "radius must be in (0, 1e+18], got 0"},
    {"radius -1", BYTES(BASE "sphere lambertian center 0 0 0 radius -1"), 3, 39,
     "radius must be in (0, 1e+18], got -1"},
    {"radius underflows to 0", BYTES(BASE "sphere lambertian center 0 0 0 radius 1e-60"), 3, 39,
     "radius must be in (0, 1e+18], got 1e-60"},
    {"ior below 1", BYTES(BASE "sphere refractive center 0 0 0 radius 1 ior 0.9"), 3, 45,
     "ior must be >= 1, got 0.9"},
    {"color above 1", BYTES(BASE "sphere lambertian center 0 0 0 radius 1 color 0.5 1.5 0"), 3, 51,
     "color must be in [0, 1], got 1.5"},
    {"color below 0", BYTES(BASE "sphere lambertian center 0 0 0 radius 1 color -0.1 0 0"), 3, 47,
     "color must be in [0, 1], got -0.1"},
    {"light color above 1", BYTES(BASE "light position 0 0 0 power 1 color 1 1 2"), 3, 40,
     "color must be in [0, 1], got 2"},
    {"negative power", BYTES(BASE "light position 0 0 0 power -1"), 3, 28,
     "power must be >= 0, got -1"},
    {"negative background", BYTES(BASE "background 0 -1 0"), 3, 14,
     "background must be >= 0, got -1"},
    {"background missing component", BYTES(BASE "background 0 0"), 3, 15,
     "expected 3 numbers (r g b) for 'background', got 2"},
    {"background extra number", BYTES(BASE "background 0 0 0 0"), 3, 18,
     "unexpected '0' after background's 3 numbers"},
    {"ks above 1", BYTES(BASE "sphere phong center 0 0 0 radius 1 ks 1.5"), 3, 39,
     "ks must be in [0, 1], got 1.5"},
    {"alpha below 0", BYTES(BASE "sphere phong center 0 0 0 radius 1 alpha -1"), 3, 42,
     "alpha must be >= 0, got -1"},
    /* Positions and radii whose float squares would overflow (a radius of 2e19 vanished). */
    {"radius over 1e18", BYTES(BASE "sphere lambertian center 0 0 0 radius 2e18"), 3, 39,
     "radius must be in (0, 1e+18], got 2e18"},
    {"light past 1e18", BYTES(BASE "light position 0 -1e19 0 power 1"), 3, 18,
     "position must be in [-1e+18, 1e+18], got -1e19"},
    {"camera past 1e18",
     BYTES("camera position 0 0 3e18\n"
           "plane width 4 height 3 pixel 0.01\n"),
     1, 21, "position must be in [-1e+18, 1e+18], got 3e18"},
    {"pixel does not divide width",
     BYTES("camera position 0 0 0\n"
           "plane width 4 height 3 pixel 0.03\n"),
     2, 30,
     "plane width 4 is not a whole number of pixels of 0.03 (133.33); nearest pixel sizes that "
     "divide it: 0.0300752 (133 px), 0.02985075 (134 px); one that divides width and height: "
     "0.03030303 (132 x 99 px)"},
    /* A suggestion is the shortest decimal that gives the count printed beside it: 0.2 and 0.01
     * divide these sides too, into other counts (5 px; 700 x 500 px). */
    {"suggested pixel gives the count printed",
     BYTES("camera position 0 0 0\n"
           "plane width 1 height 1 pixel 0.3\n"),
     2, 30,
     "plane width 1 is not a whole number of pixels of 0.3 (3.33); nearest pixel sizes that "
     "divide it: 0.3333333 (3 px), 0.25 (4 px); one that divides width and height: 0.3333333 "
     "(3 x 3 px)"},
    {"suggested pixel for both sides gives the counts printed",
     BYTES("camera position 0 0 0\n"
           "plane width 7 height 5 pixel 0.013\n"),
     2, 30,
     "plane width 7 is not a whole number of pixels of 0.013 (538.46); nearest pixel sizes that "
     "divide it: 0.01301115 (538 px), 0.01298701 (539 px); one that divides width and height: "
     "0.01298701 (539 x 385 px)"},
    {"pixel does not divide height",
     BYTES("camera position 0 0 0\n"
           "plane width 4 height 3.001 pixel 0.01\n"),
     2, 34,
     "plane height 3.001 is not a whole number of pixels of 0.01 (300.10); nearest pixel sizes "
     "that divide it: 0.01000333 (300 px), 0.0099701 (301 px)"},
    {"only one pixel count fits",
     BYTES("camera position 0 0 0\n"
           "plane width 0.7 height 1 pixel 1\n"),
     2, 32,
     "plane width 0.7 is not a whole number of pixels of 1 (0.70); the nearest pixel size that "
     "divides it is 0.7 (1 px); one that divides width and height: 0.1 (7 x 10 px)"},
    {"resolution over 16384",
     BYTES("camera position 0 0 0\n"
           "plane width 200 height 1 pixel 0.01\n"),
     2, 32, "plane width 200 at pixel 0.01 is 20000 pixels, more than the maximum 16384"},
    {"less than one pixel",
     BYTES("camera position 0 0 0\n"
           "plane width 4 height 0.001 pixel 0.01\n"),
     2, 34, "plane height 0.001 is less than one pixel of 0.01"},
    {"width 0", BYTES("camera position 0 0 0\nplane width 0 height 3 pixel 0.01\n"), 2, 13,
     "width must be in [1e-12, 1e+12], got 0"},
    {"width negative", BYTES("camera position 0 0 0\nplane width -4 height 3 pixel 0.01\n"), 2, 13,
     "width must be in [1e-12, 1e+12], got -4"},
    {"pixel 0", BYTES("camera position 0 0 0\nplane width 4 height 3 pixel 0\n"), 2, 30,
     "pixel must be in [1e-12, 1e+12], got 0"},
    {"old Mac line endings", BYTES("camera position 0 0 0\rplane width 4 height 3 pixel 1\r"), 1,
     22, "carriage return inside a line (old Mac line endings?): lines end in LF or CR LF"},
    {"old Mac line endings after a comment", BYTES("# a scene\rcamera position 0 0 0\r"), 1, 10,
     "carriage return inside a line (old Mac line endings?)"},
    /* Ray directions are normalized from plane-sized vectors: squares that overflow or vanish in
     * float would turn every ray into NaN and the image black. */
    {"plane too wide for float",
     BYTES("camera position 0 0 0\nplane width 1e19 height 1e19 pixel 1e17\n"), 2, 13,
     "width must be in [1e-12, 1e+12], got 1e19"},
    {"pixel too small for float",
     BYTES("camera position 0 0 0\nplane width 1e-12 height 1e-12 pixel 1e-27\n"), 2, 38,
     "pixel must be in [1e-12, 1e+12], got 1e-27"},
    {"plane at the float bounds",
     BYTES("camera position 0 0 0\nplane width 1e12 height 1e-12 pixel 1e-12\n"), 2, 37,
     "plane width 1e12 at pixel 1e-12 is 1e+24 pixels"},
    {"half a pixel over 16384",
     BYTES("camera position 0 0 0\nplane width 16384.5 height 1 pixel 1\n"), 2, 36,
     "plane width 16384.5 at pixel 1 is 16384.5 pixels, more than the maximum 16384"},
    {"plane missing pixel", BYTES("camera position 0 0 0\n  plane width 4 height 3\n"), 2, 3,
     "plane is missing required key 'pixel'"},
    {"missing camera", BYTES("plane width 4 height 3 pixel 0.01\n"), 2, 1,
     "missing 'camera' directive"},
    {"missing plane", BYTES("camera position 0 0 0\n"), 2, 1, "missing 'plane' directive"},
    {"missing plane, no final newline", BYTES("\n\ncamera position 0 0 0"), 3, 1,
     "missing 'plane' directive"},
    {"missing sphere center", BYTES(BASE "sphere lambertian radius 1"), 3, 1,
     "sphere is missing required key 'center'"},
    {"missing sphere radius", BYTES(BASE " sphere lambertian center 0 0 0"), 3, 2,
     "sphere is missing required key 'radius'"},
    {"missing material", BYTES(BASE "sphere"), 3, 7, "expected a material after 'sphere'"},
    {"missing light power", BYTES(BASE "light position 0 0 0"), 3, 1,
     "light is missing required key 'power'"},
    {"missing camera position", BYTES("camera\nplane width 4 height 3 pixel 0.01\n"), 1, 1,
     "camera is missing required key 'position'"},
    {"zero camera direction", BYTES("camera position 0 0 0 direction 0 0 0\n"), 1, 23,
     "camera direction must not be zero"},
    {"zero camera up", BYTES("camera position 0 0 0 up 0 0 0\n"), 1, 23,
     "camera up must not be zero"},
    {"up parallel to direction", BYTES("camera position 0 0 0 up 0 0 -2\n"), 1, 23,
     "camera up (0 0 -2) is parallel to direction (0 0 1)"},
    {"direction parallel to default up", BYTES("camera position 0 0 0 direction 0 3 0\n"), 1, 23,
     "camera up (0 1 0) is parallel to direction (0 3 0)"},
    {"samples 0", BYTES(BASE "render samples 0"), 3, 16,
     "samples must be an integer in [1, 1048576], got 0"},
    {"samples 1.5", BYTES(BASE "render samples 1.5"), 3, 16,
     "expected an integer for 'samples', got '1.5'"},
    {"samples with exponent", BYTES(BASE "render samples 1e3"), 3, 16,
     "expected an integer for 'samples', got '1e3'"},
    {"samples above maximum", BYTES(BASE "render samples 1048577"), 3, 16,
     "samples must be an integer in [1, 1048576], got 1048577"},
    {"sign without digits", BYTES(BASE "render seed +"), 3, 13,
     "expected an integer for 'seed', got '+'"},
    {"indirect maybe", BYTES(BASE "render indirect maybe"), 3, 17,
     "expected on or off for 'indirect', got 'maybe'"},
    {"bounces -1", BYTES(BASE "render bounces -1"), 3, 16,
     "bounces must be an integer in [0, 64], got -1"},
    {"bounces 65", BYTES(BASE "render bounces 65"), 3, 16,
     "bounces must be an integer in [0, 64], got 65"},
    {"seed 4294967296", BYTES(BASE "render seed 4294967296"), 3, 13,
     "seed must be an integer in [0, 4294967295], got 4294967296"},
    {"seed with 30 digits", BYTES(BASE "render seed 999999999999999999999999999999"), 3, 13,
     "seed must be an integer in [0, 4294967295]"},
    {"unknown material", BYTES(BASE "sphere glass center 0 0 0 radius 1"), 3, 8,
     "unknown material 'glass' for sphere"},
    {"empty file", BYTES(""), 1, 1, "missing 'camera' directive"},
    {"only comments", BYTES("# one\n   # two\n"), 3, 1, "missing 'camera' directive"},
    {"NUL byte mid-line", BYTES("camera position 0\0 0 0\n"), 1, 18, "NUL byte"},
    {"NUL byte in a comment", BYTES(BASE "# ab\0c\n"), 3, 5, "NUL byte in a comment"},
    {"binary garbage",
     BYTES(BASE "\x7f"
                "ELF\x02\x01\x01"),
     3, 1, "unexpected byte 0x7f"},
    {"non-ASCII byte in a token", BYTES(BASE "sphere lambertian center 0 0 0 radius 1\xc3\xa9"), 3,
     40, "unexpected byte 0xc3"},
    {"vertical tab", BYTES(BASE "render\vsamples 2"), 3, 7, "unexpected byte 0x0b"},
    {"tab counts as one column", BYTES(BASE "\tspere"), 3, 2, "unknown directive 'spere'"},
    {"CRLF keeps columns", BYTES(BASE "render samples 0\r\n"), 3, 16, "samples must be"},
    {"long token quoted short",
     BYTES(BASE "render samples "
                "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"),
     3, 16, "got 'aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa...'"},
    {"error on line 7 after valid lines",
     BYTES(BASE "light position 0 5 0 power 10\n"
                "sphere phong center 0 0 0 radius 1\n"
                "# comment\n"
                "\n"
                "sphere mirror center 0 0 0 radius -2\n"
                "sphere mirror center 0 0 0 radius 1\n"),
     7, 35, "radius must be in (0, 1e+18], got -2"},
    /* triangle and quad */
    {"triangle without material", BYTES(BASE "triangle"), 3, 9,
     "expected a material after 'triangle' (lambertian, phong, mirror), got end of line"},
    {"quad without material", BYTES(BASE "quad "), 3, 5,
     "expected a material after 'quad' (lambertian, phong, mirror), got end of line"},
    {"unknown triangle material", BYTES(BASE "triangle glass v0 0 0 0 v1 1 0 0 v2 0 1 0"), 3, 10,
     "unknown material 'glass' for triangle (expected one of: lambertian phong mirror, or "
     "lambertiana espejo)"},
    {"refractive triangle", BYTES(BASE "triangle refractive v0 0 0 0 v1 1 0 0 v2 0 1 0 ior 1.5"), 3,
     10,
     "a triangle cannot be 'refractive': glass needs a closed mesh (load one with the 'mesh' "
     "directive)"},
    {"refractada quad", BYTES(BASE "quad refractada v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0"), 3, 6,
     "a quad cannot be 'refractada': glass needs a closed mesh"},
    {"n0 on a quad", BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0 n0 0 0 1"), 3,
     53, "unknown key 'n0' for quad lambertian (expected one of: v0 v1 v2 v3 color emission)"},
    {"ior on a phong triangle", BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 ior 2"), 3,
     43,
     "unknown key 'ior' for triangle phong (expected one of: v0 v1 v2 n0 n1 n2 color ks alpha "
     "emission)"},
    {"ks on a mirror quad", BYTES(BASE "quad espejo v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0 ks 1"), 3,
     49, "unknown key 'ks' for quad espejo (expected one of: v0 v1 v2 v3 color emission)"},
    {"triangle v1 twice", BYTES(BASE "triangle mirror v0 0 0 0 v1 1 0 0 v2 0 1 0 v1 1 1 1"), 3, 44,
     "'v1' given twice"},
    {"triangle missing v2", BYTES(BASE "triangle mirror v0 0 0 0 v1 1 0 0"), 3, 1,
     "triangle is missing required key 'v2'"},
    {"quad missing v3", BYTES(BASE "quad mirror v0 0 0 0 v1 1 0 0 v2 1 1 0"), 3, 1,
     "quad is missing required key 'v3'"},
    {"triangle v1 missing a number", BYTES(BASE "triangle mirror v0 0 0 0 v2 0 1 0 v1 1 0"), 3, 41,
     "expected 3 numbers (x y z) for 'v1', got 2"},
    {"triangle coordinate out of range",
     BYTES(BASE "triangle mirror v0 0 0 0 v1 2e18 0 0 v2 0 1 0"), 3, 29,
     "v1 must be in [-1e+18, 1e+18], got 2e18"},
    {"quad coordinate out of range",
     BYTES(BASE "quad mirror v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 -1.5e18"), 3, 47,
     "v3 must be in [-1e+18, 1e+18], got -1.5e18"},
    {"triangle NaN", BYTES(BASE "triangle mirror v0 0 nan 0 v1 1 0 0 v2 0 1 0"), 3, 22,
     "(NaN and infinities are not allowed)"},
    {"quad infinity", BYTES(BASE "quad mirror v0 0 0 0 v1 1 0 0 v2 1 inf 0 v3 0 1 0"), 3, 36,
     "(NaN and infinities are not allowed)"},
    {"normal infinity",
     BYTES(BASE "triangle mirror v0 0 0 0 v1 1 0 0 v2 0 1 0 n0 0 0 1 n1 0 0 1 n2 0 -inf 1"), 3, 67,
     "(NaN and infinities are not allowed)"},
    {"triangle overflowing float", BYTES(BASE "triangle mirror v0 0 0 0 v1 1e39 0 0 v2 0 1 0"), 3,
     29, "number '1e39' for 'v1' is out of range"},
    {"collinear triangle", BYTES(BASE "triangle lambertian v0 0 0 0 v1 1 1 1 v2 2 2 2"), 3, 1,
     "triangle is degenerate: its corners are on a line (zero area)"},
    {"triangle with two equal corners",
     BYTES(BASE "triangle lambertian v0 0 0 0 v1 1 1 1 v2 1 1 1"), 3, 1,
     "triangle is degenerate: two of its corners are the same point (zero area)"},
    {"triangle of one point", BYTES(BASE "triangle lambertian v0 5 5 5 v1 5 5 5 v2 5 5 5"), 3, 1,
     "triangle is degenerate: its corners are one point (zero area)"},
    {"sliver triangle", BYTES(BASE "triangle lambertian v0 0 0 0 v1 1 0 0 v2 0.5 9e-6 0"), 3, 1,
     "triangle is degenerate: its height is 9e-06 of its longest edge, under the 1e-05 that single "
     "precision needs"},
    {"tiny triangle", BYTES(BASE "triangle lambertian v0 0 0 0 v1 3e-10 0 0 v2 0 3e-10 0"), 3, 1,
     "triangle is too small for single precision: twice its area (the length of the cross product "
     "of two edges) is 9e-20, and must be from 1.5334e-19 to 1.3043e+19"},
    {"huge triangle", BYTES(BASE "triangle lambertian v0 0 0 0 v1 4e9 0 0 v2 0 4e9 0"), 3, 1,
     "triangle is too large for single precision: twice its area (the length of the cross product "
     "of two edges) is 1.6e+19"},
    {"n0 alone", BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 n0 0 0 1"), 3, 43,
     "triangle n0 needs n1: shading normals come all three (n0 n1 n2) or none"},
    {"n0 and n2", BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 n2 0 0 1 n0 0 0 1"), 3, 52,
     "triangle n0 needs n1"},
    {"n1 and n2", BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 n1 0 0 1 n2 0 0 1"), 3, 43,
     "triangle n1 needs n0"},
    {"zero normal",
     BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 n0 0 0 1 n1 0 1 0 n2 0 0 0"), 3, 61,
     "triangle n2 must not be zero (a shading normal is a direction)"},
    {"negative zero normal",
     BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 n0 -0 0 -0 n1 0 1 0 n2 0 0 1"), 3, 43,
     "triangle n0 must not be zero"},
    {"normal too small for float",
     BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 n0 0 0 1 n1 1e-50 0 0 n2 0 0 1"), 3, 52,
     "triangle n1 must not be zero"},
    {"quad not flat", BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0.0001"), 3, 44,
     "quad is not flat: v3 is 0.0001 off the plane of v0 v1 v2, more than 1e-05 times its longest "
     "diagonal (1.41)"},
    {"quad not convex at v3", BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0.7 0.3 0"),
     3, 44,
     "quad is not convex at v3: its corners v0 v1 v2 v3 must go once around it, turning the same "
     "way at each"},
    {"quad not convex at v0", BYTES(BASE "quad lambertian v0 0.6 0.6 0 v1 1 0 0 v2 1 1 0 v3 0 1 0"),
     3, 17, "quad is not convex at v0"},
    {"quad straight at v0", BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 -1 0 0"), 3,
     17, "quad is not convex at v0"},
    {"bow-tie quad", BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 0 1 0 v3 1 1 0"), 3, 35,
     "quad is not convex at v2"},
    {"quad with v3 on v0", BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 0 0"), 3, 1,
     "quad half v0 v2 v3 is degenerate: two of its corners are the same point (zero area)"},
    {"quad with v3 on its diagonal",
     BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0.5 0.5 0"), 3, 1,
     "quad half v0 v2 v3 is degenerate: its corners are on a line (zero area)"},
    {"quad with a degenerate first half",
     BYTES(BASE "quad lambertian v0 0 0 0 v1 1 1 0 v2 2 2 0 v3 0 1 0"), 3, 1,
     "quad half v0 v1 v2 is degenerate: its corners are on a line (zero area)"},
    {"quad with a sliver half",
     BYTES(BASE "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0.5 0.500001 0"), 3, 1,
     "quad half v0 v2 v3 is degenerate: its height is"},
    {"triangle emission in report mode",
     BYTES(BASE "triangle lambertian v0 0 0 0 v1 1 0 0 v2 0 1 0 emission 1 1 1"), 3, 48,
     "emission needs path mode: add 'render mode path'"},
    {"quad emission in report mode",
     BYTES(BASE
           "quad lambertiana v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0 emission 0 0 5\nrender seed 3\n"),
     3, 54, "emission needs path mode"},
    {"negative face emission",
     BYTES(
         BASE
         "quad lambertian v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0 emission 0 -1 5\nrender mode path\n"),
     3, 64, "emission must be >= 0, got -1"},
    {"face color above 1", BYTES(BASE "triangle phong v0 0 0 0 v1 1 0 0 v2 0 1 0 color 1 1.5 0"), 3,
     51, "color must be in [0, 1], got 1.5"},
};

/* Parses text that must fail at line:col with `message` in the error, and leave *out alone. */
static void expect_error(const char *name, const char *text, size_t length, int line, int col,
                         const char *message) {
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

/* Cases whose text is built at run time: too long, too many, too big. */
static void test_generated(void) {
    /* A 1 MB line fails at the first byte past the limit, without a quadratic scan. */
    size_t big = 1 << 20;
    char *text = malloc(big + 64);
    strcpy(text, "camera position 0 0 0\n");
    size_t used = strlen(text);
    memset(text + used, 'a', big);
    expect_error("line of 1 MB", text, used + big, 2, SCENE_MAX_LINE + 1,
                 "line is longer than 4096 bytes");

    /* Exactly SCENE_MAX_LINE bytes is fine, with LF or CRLF; one more is not. */
    used = (size_t)sprintf(text, "%s", BASE);
    size_t line_start = used;
    used += (size_t)sprintf(text + used, "render samples 2 #");
    memset(text + used, 'c', SCENE_MAX_LINE - (used - line_start));
    used = line_start + SCENE_MAX_LINE;
    memcpy(text + used, "\r\n", 2);
    scene s;
    if (parse_ok("line of exactly SCENE_MAX_LINE bytes", text, used + 2, &s)) scene_free(&s);
    text[used] = 'c';
    expect_error("line of SCENE_MAX_LINE + 1 bytes", text, used + 1, 3, SCENE_MAX_LINE + 1,
                 "line is longer than 4096 bytes");

    /* Any number of digits is a number; only its float value matters. */
    used = (size_t)sprintf(text, "%slight power 1 position 0 0 0.", BASE);
    memset(text + used, '5', 500);
    if (parse_ok("500-digit number", text, used + 500, &s)) {
        check(s.lights[0].position.z == 0.5555556f, "500-digit number", "%.9g",
              s.lights[0].position.z);
        scene_free(&s);
    }
    free(text);

    /* One light past the limit fails on its own line. */
    size_t line_length = strlen("light position 0 0 0 power 1\n");
    size_t length = strlen(BASE) + (SCENE_MAX_LIGHTS + 1) * line_length;
    text = malloc(length + 1);
    used = (size_t)sprintf(text, "%s", BASE);
    for (int i = 0; i <= SCENE_MAX_LIGHTS; i++) {
        used += (size_t)sprintf(text + used, "light position 0 0 0 power 1\n");
    }
    expect_error("too many lights", text, length, SCENE_MAX_LIGHTS + 3, 1,
                 "too many lights (the maximum is 4096)");
    if (parse_ok("SCENE_MAX_LIGHTS lights", text, length - line_length, &s)) {
        check(s.light_count == SCENE_MAX_LIGHTS, "SCENE_MAX_LIGHTS lights", "%d", s.light_count);
        scene_free(&s);
    }
    free(text);

    /* Many spheres: the arrays grow past many doublings with every value in place. */
    int count = 100000;
    text = malloc(strlen(BASE) + (size_t)count * 80);
    used = (size_t)sprintf(text, "%s", BASE);
    for (int i = 0; i < count; i++) {
        used +=
            (size_t)sprintf(text + used, "sphere lambertian center %d 0 %d radius 0.5\n", i, -i);
    }
    if (parse_ok("100000 spheres", text, used, &s)) {
        bool all = s.sphere_count == count;
        for (int i = 0; all && i < count; i++) {
            all = vec_is(s.spheres[i].center, (float)i, 0, (float)-i);
        }
        check(all, "100000 spheres", "count %d or a center is wrong", s.sphere_count);
        scene_free(&s);
    }
    free(text);

    /* Lengths past the limit are refused before a byte is read (this buffer is tiny). */
    if (sizeof(size_t) > 4) {
        scene_error err;
        bool ok = scene_parse_string("", (size_t)INT_MAX + 10, "huge", &s, &err);
        check(!ok && err.line == 0 && err.col == 0 && strstr(err.message, "too large"),
              "text over 2 GiB", "%d:%d %s", err.line, err.col, err.message);
    }
}

/* A text of BASE and `lines` lines, mostly spheres (some with CR LF, comments and blank lines
 * between), where line number `tiny` (0: none) and every 997th line after it hold tiny spheres;
 * *line_at[k] is where line k + 1 starts. */
static char *chunked_text(int lines, int tiny, size_t *length, size_t *line_at) {
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
static void replace_line(char *text, const size_t *line_at, int k, const char *line) {
    size_t room = line_at[k] - line_at[k - 1] - 1, n = strlen(line);
    if (n > room) abort(); /* the test's own mistake: pick a longer line */
    memcpy(text + line_at[k - 1], line, n);
    memset(text + line_at[k - 1] + n, ' ', room - n); /* trailing blanks are whitespace */
}

/* Parses text on 1 and on several threads: both fail or succeed alike, with the same error or
 * the same spheres, triangles (bytes: the parser zeroes their padding), lights and warnings;
 * returns the one-thread result (*err set on failure). */
static bool parse_all_threads(const char *name, const char *text, size_t length, scene_error *err,
                              scene *s) {
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
        check(
            t.sphere_count == s->sphere_count && t.light_count == s->light_count &&
                !memcmp(t.spheres, s->spheres, (size_t)s->sphere_count * sizeof *s->spheres) &&
                t.triangle_count == s->triangle_count &&
                (!s->triangle_count || !memcmp(t.triangles, s->triangles,
                                               (size_t)s->triangle_count * sizeof *s->triangles)) &&
                t.warning_count == s->warning_count &&
                !memcmp(t.warnings, s->warnings, (size_t)s->warning_count * sizeof *t.warnings),
            name, "%d threads: %d spheres, %d triangles, %d warnings; one thread: %d, %d, %d",
            counts[k], t.sphere_count, t.triangle_count, t.warning_count, s->sphere_count,
            s->triangle_count, s->warning_count);
        scene_free(&t);
    }
    return ok;
}

/* Texts of several MB, which the parser cuts into chunks: the scene, its tiny-sphere warning
 * and the first error (wherever it is, whatever comes after it) match one pass in order. */
static void test_chunks(void) {
    int lines = 40000;
    size_t length, *line_at = malloc(((size_t)lines + 1) * sizeof *line_at);
    scene s;
    scene_error err;
    const int tiny[] = {0, 10, 25000, 39990};
    for (size_t k = 0; k < sizeof tiny / sizeof tiny[0]; k++) {
        char *text = chunked_text(lines, tiny[k], &length, line_at);
        char name[64];
        snprintf(name, sizeof name, "chunks, tiny spheres from line %d", tiny[k]);
        if (check(parse_all_threads(name, text, length, &err, &s), name, "%s", err.message)) {
            check(s.warning_count == (tiny[k] > 0) && (!tiny[k] || s.warnings[0].line == tiny[k]),
                  name, "%d warnings, the first at line %d: %s", s.warning_count,
                  s.warning_count ? s.warnings[0].line : 0,
                  s.warning_count ? s.warnings[0].message : "");
            scene_free(&s);
        }
        free(text);
    }
    /* Errors anywhere, alone and before a second one; other directives late in the text. */
    typedef struct bad_line {
        const char *line, *message;
        int col;
    } bad_line;
    const bad_line bad[] = {
        {"sphere lambertian center 0 0 0 radiu 1", "unknown key 'radiu' for sphere lambertian", 32},
        {"bogus 1 2 3", "unknown directive 'bogus'", 1},
        {"sphere mirror center 0 0 0 radius -2", "radius must be in (0, 1e+18], got -2", 35},
        {"camera position 1 2 3", "'camera' given twice (first on line 1)", 1},
        {"# a NUL \001 here", "", 0},
        {"light position 0 0 0 power 1", NULL, 0},
    };
    const int at[] = {3, 777, 13334, 20000, 20001, 29999, 40000};
    for (size_t b = 0; b < sizeof bad / sizeof bad[0]; b++) {
        for (size_t a = 0; a < sizeof at / sizeof at[0]; a++) {
            char *text = chunked_text(lines, 0, &length, line_at);
            replace_line(text, line_at, at[a], bad[b].line);
            if (bad[b].message && !bad[b].message[0]) /* the NUL byte itself */
                text[line_at[at[a] - 1] + strlen("# a NUL ")] = '\0';
            int second = at[a] + 1234 <= lines ? at[a] + 1234 : 0;
            for (int twice = 0; twice < 2; twice++) {
                if (twice && !second) break;
                if (twice) replace_line(text, line_at, second, "bogus");
                char name[96];
                snprintf(name, sizeof name, "chunks, '%s' at line %d%s", bad[b].line, at[a],
                         twice ? " and another error after it" : "");
                bool ok = parse_all_threads(name, text, length, &err, &s);
                if (!bad[b].message && !twice) {
                    if (check(ok, name, "%s", err.message)) {
                        check(s.light_count == 1, name, "%d lights", s.light_count);
                        scene_free(&s);
                    }
                } else if (!bad[b].message) {
                    check(!ok && err.line == second, name, "error at line %d", err.line);
                } else {
                    check(!ok && err.line == at[a] &&
                              (!bad[b].message[0] || err.col == bad[b].col) &&
                              strstr(err.message, bad[b].message),
                          name, "%d:%d %s", err.line, err.col, err.message);
                }
                if (ok) scene_free(&s);
            }
            free(text);
        }
    }
    free(line_at);
    /* Emission in report mode, found by a chunk parsed ahead, is reported at its own line. */
    size_t size = 64u * 30000u, used = 0;
    char *text = malloc(size);
    used += (size_t)sprintf(text, "camera position 0 0 0\nplane width 4 height 3 pixel 0.01\n");
    for (int k = 3; k <= 30000; k++)
        used += (size_t)sprintf(text + used, "sphere lambertian center %d 0 9 radius 0.5%s\n", k,
                                k == 22222 ? " emission 1 1 1" : "");
    bool ok = parse_all_threads("chunks, emission in report mode", text, used, &err, &s);
    check(!ok && err.line == 22222 && strstr(err.message, "emission needs path mode"),
          "chunks, emission in report mode", "%d:%d %s", err.line, err.col, err.message);
    if (ok) scene_free(&s);
    free(text);
}

/* A text of several MB mixing spheres, triangles (some smooth, some emitting) and quads: any
 * thread count gives the faces in file order, bit for bit, and the same first error. */
static void test_chunks_faces(void) {
    int lines = 40000;
    size_t size = (size_t)lines * 128, used = 0;
    char *text = malloc(size);
    size_t *line_at = malloc(((size_t)lines + 1) * sizeof *line_at);
    for (int k = 1; k <= lines; k++) {
        line_at[k - 1] = used;
        const char *line = "";
        char buffer[128];
        if (k == 1) {
            line = "camera position 0 0 0";
        } else if (k == 2) {
            line = "plane width 4 height 3 pixel 0.01";
        } else if (k == 3) {
            line = "render mode path";
        } else if (k % 101 == 0) {
            line = "# comment";
        } else if (k % 3 == 0) {
            snprintf(buffer, sizeof buffer, "sphere phong center %d.5 %d 9 radius 0.25", k % 1000,
                     k % 17);
            line = buffer;
        } else if (k % 3 == 1) {
            snprintf(buffer, sizeof buffer, "triangle mirror v0 %d 0 0 v1 %d.5 0 1 v2 0 %d 2%s%s",
                     k, k, k % 97 + 1, k % 7 ? "" : " n0 0 0 1 n1 0 1 1 n2 1 0.5 0",
                     k % 11 ? "" : " emission 1 1 1");
            line = buffer;
        } else {
            snprintf(buffer, sizeof buffer,
                     "quad lambertiana v0 0 0 %d v1 %d 0 %d v2 %d 1 %d v3 0 1 %d color 0.5 0.5 0.5",
                     k, k % 50 + 1, k, k % 50 + 1, k, k);
            line = buffer;
        }
        used += (size_t)snprintf(text + used, size - used, "%s\n", line);
    }
    line_at[lines] = used;
    scene s;
    scene_error err;
    const char *name = "chunks of mixed primitives";
    if (check(parse_all_threads(name, text, used, &err, &s), name, "%d:%d %s", err.line, err.col,
              err.message)) {
        /* Lines 3k+1 are triangles, 3k+2 quads (both halves): file order, halves in order. */
        int expected = 0;
        for (int k = 4; k <= lines; k++)
            if (k % 101 && k % 3 != 0) expected += k % 3 == 1 ? 1 : 2;
        check(s.triangle_count == expected && s.triangles[0].v[0].x == 4.0f &&
                  s.triangles[1].v[0].z == 5.0f && s.triangles[2].v[0].z == 5.0f &&
                  s.triangles[2].v[1].x == 6.0f &&
                  s.triangles[s.triangle_count - 1].v[0].x == (float)lines,
              name, "%d triangles, expected %d", s.triangle_count, expected);
        scene_free(&s);
    }
    /* A bad face late, found by a chunk parsed ahead, and a face emitting in report mode. */
    char *bad = malloc(used + 1);
    const struct {
        int line;
        const char *text, *message;
        int col;
    } cases[] = {
        {29999, "quad mirror v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0.5 0.5 1", "quad is not flat", 40},
        {20002, "triangle mirror v0 0 0 0 v1 1 1 1 v2 2 2 2", "triangle is degenerate", 1},
        {3, "render seed 2", "emission needs path mode", 0},
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        memcpy(bad, text, used);
        replace_line(bad, line_at, cases[c].line, cases[c].text);
        char case_name[96];
        snprintf(case_name, sizeof case_name, "%s, '%s' at line %d", name, cases[c].text,
                 cases[c].line);
        bool ok = parse_all_threads(case_name, bad, used, &err, &s);
        /* in report mode the first emitting triangle (line 22: 3k+1 and a multiple of 11) fails */
        int line = cases[c].col ? cases[c].line : 22;
        check(!ok && err.line == line && (!cases[c].col || err.col == cases[c].col) &&
                  strstr(err.message, cases[c].message),
              case_name, "%d:%d %s", err.line, err.col, err.message);
        if (ok) scene_free(&s);
    }
    free(bad);
    free(line_at);
    free(text);
}

static bool write_file(const char *path, const char *text, size_t length) {
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fwrite(text, 1, length, f) == length;
    return fclose(f) == 0 && ok;
}

/* Parses a file that must fail with line 0 (no position), `message` in the error. */
static void expect_file_error(const char *name, const char *path, const char *message) {
    scene s, sentinel;
    memset(&s, 0xcd, sizeof s);
    memcpy(&sentinel, &s, sizeof s);
    scene_error err;
    if (!check(!scene_parse_file(path, &s, &err), name, "parsed without error")) {
        scene_free(&s);
        return;
    }
    check(strcmp(err.file, path) == 0, name, "file '%s', expected '%s'", err.file, path);
    check(err.line == 0 && err.col == 0, name, "at %d:%d, expected 0:0", err.line, err.col);
    check(strstr(err.message, message) != NULL, name, "message '%s' lacks '%s'", err.message,
          message);
    check(memcmp(&s, &sentinel, sizeof s) == 0, name, "*out was modified on failure");
}

static void test_files(void) {
    char dir[] = "/tmp/test_parse.XXXXXX";
    if (!check(mkdtemp(dir) != NULL, "temp dir", "mkdtemp: %s", strerror(errno))) return;
    char path[512], other[600];

    snprintf(path, sizeof path, "%s/missing.scene", dir);
    expect_file_error("missing file", path, "cannot open: No such file or directory");
    expect_file_error("directory", "/tmp", "is a directory");

    snprintf(path, sizeof path, "%s/example.scene", dir);
    check(write_file(path, BYTES(full_example)), "write example", "%s", strerror(errno));
    scene s;
    scene_error err;
    if (check(scene_parse_file(path, &s, &err), "file round trip", "%s:%d:%d: %s", err.file,
              err.line, err.col, err.message)) {
        check_full_example("file round trip", &s);
        scene_free(&s);
    }

    /* A path through a regular file cannot be opened, even by root. */
    snprintf(other, sizeof other, "%s/x.scene", path);
    expect_file_error("unreadable path", other, "cannot open: Not a directory");
    if (geteuid() != 0) {
        chmod(path, 0);
        expect_file_error("file without read permission", path, "Permission denied");
        chmod(path, 0644);
    }

    snprintf(path, sizeof path, "%s/bad.scene", dir);
    check(write_file(path, BYTES(BASE "\nsphere mirror center 0 0 0\n")), "write bad", "%s",
          strerror(errno));
    if (check(!scene_parse_file(path, &s, &err), "error in a file", "parsed")) {
        check(strcmp(err.file, path) == 0 && err.line == 4 && err.col == 1 &&
                  strstr(err.message, "missing required key 'radius'"),
              "error in a file", "%s:%d:%d: %s", err.file, err.line, err.col, err.message);
    }

    /* Files past 2 GiB are refused from their size alone; this one is sparse. */
    snprintf(path, sizeof path, "%s/huge.scene", dir);
    int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0 && ftruncate(fd, (off_t)3 << 30) == 0) {
        expect_file_error("file over 2 GiB", path, "file is too large");
    }
    if (fd >= 0) close(fd);
    unlink(path);

    /* A FIFO has no size up front: the reader grows its buffer until end of file. */
    snprintf(path, sizeof path, "%s/fifo.scene", dir);
    if (mkfifo(path, 0600) == 0) {
        pid_t child = fork();
        if (child == 0) {
            int out = open(path, O_WRONLY);
            /* Comments pad the text past the first buffer so the reader must grow it. */
            bool ok =
                out >= 0 && write(out, BYTES(full_example)) == (ssize_t)sizeof full_example - 1;
            for (int i = 0; ok && i < 5000; i++) {
                ok = write(out, BYTES("# padding padding padding\n")) == 26;
            }
            _exit(ok ? 0 : 1);
        }
        bool ok = scene_parse_file(path, &s, &err);
        int status = 0;
        waitpid(child, &status, 0);
        if (check(ok && WIFEXITED(status) && WEXITSTATUS(status) == 0, "FIFO", "%s", err.message)) {
            check_full_example("FIFO", &s);
            scene_free(&s);
        }
        unlink(path);
    }

    snprintf(path, sizeof path, "%s/example.scene", dir);
    unlink(path);
    snprintf(path, sizeof path, "%s/bad.scene", dir);
    unlink(path);
    rmdir(dir);
}

int main(void) {
    test_valid();
    test_faces();
    for (size_t i = 0; i < sizeof invalid_cases / sizeof invalid_cases[0]; i++) {
        const invalid_case *c = &invalid_cases[i];
        expect_error(c->name, c->text, c->length, c->line, c->col, c->message);
    }
    test_generated();
    test_chunks();
    test_chunks_faces();
    test_files();
    printf("test_parse: %d passed, %d failed (%zu invalid-input cases)\n", passed, failed,
           sizeof invalid_cases / sizeof invalid_cases[0]);
    return failed ? 1 : 0;
}
