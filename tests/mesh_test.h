/* mesh_test.h: what the mesh tests (tests/test_mesh.c, tests/test_mesh_render.c) share: model
 * files written into the test's temporary folder, scene texts parsed as a file there (so that
 * mesh paths are relative to it), and renders on the CPU back end. */
#ifndef TRAZADOR_MESH_TEST_H
#define TRAZADOR_MESH_TEST_H

#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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

#endif
