/* test_scenes.h: small scenes built in code for the tests: a sphere and a view along +z. */
#ifndef TRAZADOR_TEST_SCENES_H
#define TRAZADOR_TEST_SCENES_H

#include <dirent.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "render/render.h"
#include "scene/scene.h"

/* Parses scene text into s and opts from its settings, validation on; false (the error
 * printed) when it does not parse. */
static inline bool parse_scene_text(const char *text, scene *s, render_opts *opts) {
    scene_error err;
    if (!scene_parse_string(text, strlen(text), "test", s, &err)) {
        scene_error_print(&err);
        return false;
    }
    render_opts_from_scene(s, opts);
    opts->validate = true;
    return true;
}

/* Expects the scene text to fail at line:col with a message containing `part`. */
static inline void expect_parse_error(const char *text, int line, int col, const char *part) {
    scene s;
    scene_error err;
    bool ok = scene_parse_string(text, strlen(text), "t.scene", &s, &err);
    CHECK(!ok, "parsed: %s", text);
    if (ok) {
        scene_free(&s);
        return;
    }
    CHECK(err.line == line && err.col == col && strstr(err.message, part),
          "%s: got %d:%d: %s, want %d:%d ... %s", text, err.line, err.col, err.message, line, col,
          part);
}

/* Renders on the Vulkan or the CPU back end into f; false on failure. */
static inline bool render_on(bool vulkan, const scene *s, const render_opts *opts, film *f) {
    return vulkan ? render_film(&render_backend_vulkan, s, opts, f)
                  : render_film(&render_backend_cpu, s, opts, f);
}

/* Renders scene text on the CPU and the Vulkan back ends in report mode and in path mode (4
 * bounces), expecting the same film bit for bit in each. */
static inline void expect_back_ends_agree(const char *text) {
    for (int mode = 0; mode < 2; mode++) {
        scene s;
        render_opts o;
        film a = {0}, b = {0};
        if (!parse_scene_text(text, &s, &o)) continue;
        o.mode = mode ? RENDER_MODE_PATH : RENDER_MODE_REPORT;
        if (mode) o.bounces = 4;
        CHECK(render_on(false, &s, &o, &a) && render_on(true, &s, &o, &b), "mode %d", mode);
        CHECK(a.accum && b.accum &&
                  !memcmp(a.accum, b.accum, (size_t)a.width * a.height * 4 * sizeof(float)),
              "mode %d: the CPU and Vulkan films differ", mode);
        film_free(&a);
        film_free(&b);
        scene_free(&s);
    }
}

/* The materials of the spheres ball() makes, one each, for every scene view() makes (they hold
 * the whole table): TEST_MATERIALS of them, the oldest reused past that. */
#define TEST_MATERIALS 65536
static inline material *test_materials(void) {
    static material table[TEST_MATERIALS];
    return table;
}

/* A sphere of a material of its own: Phong parameters 0 and ior 1, 1.5 for glass (callers set
 * others through ball_material). */
static inline sphere ball(float x, float y, float z, float radius, material_kind kind, float r,
                          float g, float b) {
    static uint32_t next;
    uint32_t index = next++ % TEST_MATERIALS;
    test_materials()[index] = (material){
        .kind = kind, .color = {r, g, b}, .ior = kind == TZ_MATERIAL_REFRACTIVE ? 1.5f : 1.0f};
    return (sphere){.center = {x, y, z}, .radius = radius, .material = index};
}

/* The material of a sphere ball() made. */
static inline material *ball_material(const sphere *b) { return &test_materials()[b->material]; }

/* A view from `camera` along +z (up +y) through a plane_w x plane_h plane, `width` pixels
 * across, indirect light on, 5 bounces; the spheres and lights are the caller's. */
static inline scene view(float camera_z, float plane_w, float plane_h, int width, int samples,
                         uint32_t seed, sphere *spheres, int sphere_count, light *lights,
                         int light_count) {
    float pixel = plane_w / (float)width;
    return (scene){.camera_position = {0.0f, 0.0f, camera_z},
                   .camera_direction = {0.0f, 0.0f, 1.0f},
                   .camera_up = {0.0f, 1.0f, 0.0f},
                   .plane_width = plane_w,
                   .plane_height = plane_h,
                   .pixel_size = pixel,
                   .width = width,
                   .height = (int)lroundf(plane_h / pixel),
                   .spp = samples,
                   .indirect = true,
                   .bounces = 5,
                   .seed = seed,
                   .spheres = spheres,
                   .sphere_count = sphere_count,
                   .materials = test_materials(),
                   .material_count = TEST_MATERIALS,
                   .lights = lights,
                   .light_count = light_count};
}

/* Makes s `width` pixels across its own plane, the height following the plane's shape. */
static inline void set_width(scene *s, int width) {
    s->pixel_size = s->plane_width / (float)width;
    s->width = width;
    s->height = (int)lroundf(s->plane_height / s->pixel_size);
    s->plane_height = (float)s->height * s->pixel_size;
}

/* Every scene in scenes/, parsed and `width` pixels across, through check(file name, scene,
 * its options with `samples` samples); checks that each parses and that there is one. */
static inline void each_example_scene(int width, int samples,
                                      void (*check)(const char *name, const scene *s,
                                                    const render_opts *opts)) {
    const char *folder = TRAZADOR_SOURCE_DIR "/scenes";
    DIR *dir = opendir(folder);
    CHECK(dir != NULL, "cannot open %s", folder);
    if (!dir) return;
    int count = 0;
    for (struct dirent *e; (e = readdir(dir)) != NULL;) {
        size_t len = strlen(e->d_name);
        if (len < 7 || strcmp(e->d_name + len - 6, ".scene") != 0) continue;
        char path[1024];
        snprintf(path, sizeof path, "%s/%s", folder, e->d_name);
        scene s;
        scene_error err;
        bool parsed = scene_parse_file(path, &s, &err);
        CHECK(parsed, "%s:%d:%d: %s", err.file, err.line, err.col, err.message);
        if (!parsed) continue;
        set_width(&s, width);
        render_opts opts;
        render_opts_from_scene(&s, &opts);
        opts.spp = samples;
        check(e->d_name, &s, &opts);
        scene_free(&s);
        count++;
    }
    closedir(dir);
    CHECK(count > 0, "no scene in %s", folder);
}

#endif
