/* test_parse.c: the scene parser on valid input (exact struct values, defaults, layout freedom),
 * on input built at run time (too long, too many, too big), on files, and the same scene,
 * warnings and first error for every thread count on texts big enough to be parsed in chunks.
 * Invalid input: test_parse_invalid.c; faces: test_parse_faces.c. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "parse_check.h"

/* The material of sphere k of s. */
static const material *mat_of(const scene *s, int k) { return sphere_material(s, &s->spheres[k]); }

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
    check(mat_of(s, 0)->kind == TZ_MATERIAL_LAMBERTIAN && vec_is(p[0].center, 0, -1001, 0) &&
              p[0].radius == 1000.0f && vec_is(mat_of(s, 0)->color, 0.8f, 0.8f, 0.8f) &&
              mat_of(s, 0)->ks == 0 && mat_of(s, 0)->alpha == 0 && mat_of(s, 0)->ior == 1.0f &&
              vec_is(mat_of(s, 0)->emission, 0, 0, 0),
          name, "lambertian sphere");
    check(mat_of(s, 1)->kind == TZ_MATERIAL_PHONG && vec_is(p[1].center, -1, 0, 2) &&
              p[1].radius == 1 && vec_is(mat_of(s, 1)->color, 0.6f, 0.1f, 0.1f) &&
              mat_of(s, 1)->ks == 0.3f && mat_of(s, 1)->alpha == 40.0f &&
              mat_of(s, 1)->ior == 1.0f && vec_is(mat_of(s, 1)->emission, 0, 0, 0),
          name, "phong sphere");
    check(mat_of(s, 2)->kind == TZ_MATERIAL_MIRROR && vec_is(p[2].center, 1, 0, 3) &&
              p[2].radius == 1 && vec_is(mat_of(s, 2)->color, 1, 1, 1) && mat_of(s, 2)->ks == 0 &&
              mat_of(s, 2)->alpha == 0 && mat_of(s, 2)->ior == 1.0f &&
              vec_is(mat_of(s, 2)->emission, 0, 0, 0),
          name, "mirror sphere");
    check(mat_of(s, 3)->kind == TZ_MATERIAL_REFRACTIVE && vec_is(p[3].center, 0, 0, 1) &&
              p[3].radius == 0.7f && vec_is(mat_of(s, 3)->color, 1, 1, 1) &&
              mat_of(s, 3)->ks == 0 && mat_of(s, 3)->alpha == 0 && mat_of(s, 3)->ior == 1.5f &&
              vec_is(mat_of(s, 3)->emission, 0, 0, 0),
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
        check(mat_of(&s, 0)->kind == TZ_MATERIAL_PHONG &&
                  vec_is(mat_of(&s, 0)->color, 0.8f, 0.8f, 0.8f) && mat_of(&s, 0)->ks == 0.5f &&
                  mat_of(&s, 0)->alpha == 32.0f && mat_of(&s, 0)->ior == 1.0f,
              n, "phong defaults");
        check(mat_of(&s, 1)->kind == TZ_MATERIAL_LAMBERTIAN &&
                  vec_is(mat_of(&s, 1)->color, 0.8f, 0.8f, 0.8f) && mat_of(&s, 1)->ks == 0 &&
                  mat_of(&s, 1)->alpha == 0 && mat_of(&s, 1)->ior == 1.0f,
              n, "lambertiana");
        check(mat_of(&s, 2)->kind == TZ_MATERIAL_MIRROR && vec_is(mat_of(&s, 2)->color, 1, 1, 1) &&
                  mat_of(&s, 2)->ior == 1.0f,
              n, "espejo");
        check(mat_of(&s, 3)->kind == TZ_MATERIAL_REFRACTIVE &&
                  vec_is(mat_of(&s, 3)->color, 1, 1, 1) && mat_of(&s, 3)->ior == 1.5f,
              n, "refractada");
        check(mat_of(&s, 4)->kind == TZ_MATERIAL_LAMBERTIAN &&
                  vec_is(mat_of(&s, 4)->color, 0.8f, 0.8f, 0.8f),
              n, "lambertian color");
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
                  vec_is(mat_of(&s, 0)->color, 0.5f, 0.25f, 0),
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
        /* a quoted path (issue 49, defect 7): '#' and spaces inside it, and one left open */
        {"mesh file \"no such # model.ply\"", "mesh 'no such # model.ply': cannot open", 11},
        {"mesh file \"open # quote", "unterminated quoted path", 11},
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

/* One text's warnings: `count` of them, the first at line:col holding `want`. */
static void expect_warning(const char *name, const char *text, int count, int line, int col,
                           const char *want) {
    scene s;
    scene_error err;
    if (!check(parse_all_threads(name, text, strlen(text), &err, &s), name, "%s", err.message))
        return;
    check(s.warning_count == count &&
              (!count || (s.warnings[0].line == line && s.warnings[0].col == col &&
                          strstr(s.warnings[0].message, want))),
          name, "%d warnings, the first %d:%d %s", s.warning_count,
          s.warning_count ? s.warnings[0].line : 0, s.warning_count ? s.warnings[0].col : 0,
          s.warning_count ? s.warnings[0].message : "");
    scene_free(&s);
}

/* A Phong material whose max(color) + ks is above 1 reflects more than it receives: path mode
 * warns once, at the first such line (its ks, else its color, else its material word), on any
 * number of threads; report mode (the course report's model, its scenes use them) does not. */
static void test_bright_phong(void) {
#define TOP "camera position 0 0 -5\nplane width 1 height 1 pixel 0.25\n"
    expect_warning("bright sphere",
                   TOP
                   "render mode path\n"
                   "sphere phong center 0 0 0 radius 1 color 0.9 0.5 0.5 ks 0.5\n"
                   "sphere phong center 0 3 0 radius 1 color 1 1 1 ks 1\n",
                   1, 4, 54, "sphere phong: max(color) 0.9 + ks 0.5 = 1.4 is above 1");
    expect_warning("bright quad by default",
                   TOP
                   "render mode path\n"
                   "quad phong v0 0 0 0 v1 1 0 0 v2 1 1 0 v3 0 1 0\n",
                   1, 4, 6, "quad phong: max(color) 0.8 + ks 0.5 = 1.3 is above 1");
    expect_warning("bright triangle colour",
                   TOP
                   "render mode path\n"
                   "triangle phong v0 0 0 0 v1 1 0 0 v2 1 1 0 color 0.7 0.9 0.1\n",
                   1, 4, 43, "triangle phong: max(color) 0.9 + ks 0.5");
    expect_warning("at most 1",
                   TOP
                   "render mode path\n"
                   "sphere phong center 0 0 0 radius 1 color 0.7 0.5 0.5 ks 0.3\n",
                   0, 0, 0, "");
    expect_warning("report mode", TOP "sphere phong center 0 0 0 radius 1 color 1 1 1 ks 1\n", 0, 0,
                   0, "");
#undef TOP
    /* in a text cut into chunks, the first bright line deep in a chunk parsed ahead */
    int lines = 40000;
    size_t size = (size_t)lines * 64 + 128, used = 0;
    char *text = malloc(size);
    used += (size_t)snprintf(text, size,
                             "camera position 0 0 -5\nplane width 4 height 3 "
                             "pixel 0.01\nrender mode path\n");
    for (int k = 4; k <= lines; k++)
        used += (size_t)snprintf(text + used, size - used,
                                 k == 25000 || k == 30000
                                     ? "sphere phong center %d.5 0 9 radius 0.25 ks 0.9\n"
                                     : "sphere lambertian center %d.5 0 9 radius 0.25\n",
                                 k % 1000);
    expect_warning("bright in a chunk", text, 1, 25000, 41,
                   "sphere phong: max(color) 0.8 + ks 0.9");
    free(text);
}

int main(void) {
    test_valid();
    test_generated();
    test_chunks();
    test_files();
    test_bright_phong();
    return parse_check_summary("test_parse");
}
