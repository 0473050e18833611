/* mesh_test.h: what the mesh tests (tests/test_mesh.c, tests/test_mesh_render.c) share: model
 * files written into the test's temporary folder, scene texts parsed as a file there (so that
 * mesh paths are relative to it), renders on the CPU back end by packet build, and the instance
 * tests' (tests/test_instances.c, tests/test_mesh_nodes.c) comparison of every Vulkan walk. */
#ifndef TRAZADOR_MESH_TEST_H
#define TRAZADOR_MESH_TEST_H

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "render/render.h"
#include "scene/scene.h"
#include "tmp_dir.h"

/* Writes text as the file tmpdir/name. */
static inline void write_text(const char *name, const char *text) {
    tmp_file_write(tmp_path(name), text, strlen(text));
}

/* A UV sphere of radius 1 (closed: the poles are single vertices) as an OBJ. */
static inline void write_sphere(int rings, int segments) {
    const double pi = 3.14159265358979323846;
    size_t size = 1 << 20, n = 0;
    char *obj = malloc(size);
    n += (size_t)snprintf(obj + n, size - n, "v 0 1 0\nv 0 -1 0\n");
    for (int r = 1; r < rings; r++) {
        for (int s = 0; s < segments; s++) {
            double t = pi * r / rings, p = 2 * pi * s / segments;
            n += (size_t)snprintf(obj + n, size - n, "v %.9f %.9f %.9f\n", sin(t) * cos(p), cos(t),
                                  sin(t) * sin(p));
        }
    }
#define RING(r, s) (3 + ((r)-1) * segments + ((s) % segments))
    for (int s = 0; s < segments; s++) {
        n += (size_t)snprintf(obj + n, size - n, "f 1 %d %d\n", RING(1, s + 1), RING(1, s));
        n += (size_t)snprintf(obj + n, size - n, "f 2 %d %d\n", RING(rings - 1, s),
                              RING(rings - 1, s + 1));
        for (int r = 1; r < rings - 1; r++)
            n += (size_t)snprintf(obj + n, size - n, "f %d %d %d %d\n", RING(r, s), RING(r, s + 1),
                                  RING(r + 1, s + 1), RING(r + 1, s));
    }
#undef RING
    tmp_file_write(tmp_path("sphere.obj"), obj, n);
    free(obj);
}

/* Parses text as the file tmpdir/scene.scene (so that mesh paths are relative to tmpdir) on
 * `threads` threads; false with *err filled on an error. */
static inline bool parse(const char *text, int threads, scene *s, scene_error *err) {
    return scene_parse_string_threads(text, strlen(text), tmp_path("scene.scene"), threads, s, err);
}

/* Renders the scene on the CPU back end; false on failure. */
static inline bool render(const scene *s, film *f) {
    render_opts o;
    render_opts_from_scene(s, &o);
    return render_film(&render_backend_cpu, s, &o, f);
}

/* Renders s with the packet build named (NULL: the fastest) into *f; false on failure. */
static inline bool render_with(const scene *s, const char *build, film *f) {
    if (build)
        setenv("TRAZADOR_PACKET_BUILD", build, 1);
    else
        unsetenv("TRAZADOR_PACKET_BUILD");
    bool ok = render(s, f);
    unsetenv("TRAZADOR_PACKET_BUILD");
    return ok;
}

/* Whether two films hold the same bits. */
static inline bool same_film(const film *a, const film *b) {
    return a->width == b->width && a->height == b->height &&
           !memcmp(a->accum, b->accum, (size_t)a->width * a->height * 4 * sizeof *a->accum);
}

/* Scene s (named what) on the CPU back end and on every Vulkan walk the device has, in report
 * mode (with the indirect bounce) and path mode: the same film bit for bit. */
static inline void expect_walks_agree(const char *what, const scene *s) {
    static const render_walk walks[] = {RENDER_WALK_COMPUTE, RENDER_WALK_COOPERATIVE,
                                        RENDER_WALK_RAY_QUERY};
    static const char *const walk_names[] = {"compute", "cooperative", "rayquery"};
    for (int path = 0; path < 2; path++) {
        render_opts o;
        render_opts_from_scene(s, &o);
        o.mode = path ? RENDER_MODE_PATH : RENDER_MODE_REPORT;
        o.indirect = !path;
        o.bounces = 4;
        o.validate = true;
        film cpu = {0};
        CHECK(render_film(&render_backend_cpu, s, &o, &cpu), "%s: the CPU render failed", what);
        for (size_t w = 0; w < sizeof walks / sizeof walks[0]; w++) {
            o.walk = walks[w];
            film gpu = {0};
            bool rendered = render_film(&render_backend_vulkan, s, &o, &gpu);
            /* a device without ray queries refuses that walk (test_vk_rayquery checks it) */
            if (!rendered && walks[w] == RENDER_WALK_RAY_QUERY) continue;
            CHECK(rendered, "%s: the %s walk failed", what, walk_names[w]);
            CHECK(rendered && cpu.accum && same_film(&cpu, &gpu) && cpu.nonfinite == gpu.nonfinite,
                  "%s, %s mode: the %s walk differs from the CPU back end", what,
                  path ? "path" : "report", walk_names[w]);
            printf("%s, %s mode, %s walk: %s\n", what, path ? "path" : "report", walk_names[w],
                   rendered ? "the CPU's bits" : "failed");
            film_free(&gpu);
        }
        film_free(&cpu);
    }
}

#endif
