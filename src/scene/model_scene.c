/* model_scene.c: a model file as the scene: the model loaded once (mesh_load.c) for its cameras,
 * lights and box, then a scene text written from them and parsed, so that the camera, the lights
 * and the mesh get every check and default a scene file's lines get. */
#include "scene/model_scene.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "scene/mesh_cache.h"
#include "scene/mesh_load.h"
#include "scene/model_formats.h"
#include "scene/parser.h"
#include "util/log.h"

/* The camera that frames a model without one: this horizontal fov (degrees), this image shape,
 * looking at the box's centre from along FRAME_FROM (the model's front right, above: trazador's
 * -z is the file's front). */
#define FRAME_FOV 50.0
#define FRAME_ASPECT (4.0 / 3.0)
static const double frame_from[3] = {1.0, 1.0, -1.0};
/* An orthographic camera's view width, within what a plane line takes at any image width. */
#define ORTHO_MIN_WIDTH 1e-6
#define ORTHO_MAX_WIDTH 1e12
/* The scene text: a camera, a plane and a mesh line and two more. */
#define LINE_BYTES (PATH_MAX * 2 + 256)

static bool fail(scene_error *err, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bool fail(scene_error *err, const char *path, const char *fmt, ...) {
    memset(err, 0, sizeof *err);
    snprintf(err->file, sizeof err->file, "%s", path);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    return false;
}

/* One camera as info and the lists of messages show it. */
static void camera_text(const mesh_camera *c, int index, char *out, size_t size) {
    if (c->orthographic) {
        snprintf(out, size, "camera %d '%s': orthographic, at %g %g %g looking along %g %g %g",
                 index, c->name, c->position.x, c->position.y, c->position.z, c->direction.x,
                 c->direction.y, c->direction.z);
        return;
    }
    snprintf(out, size,
             "camera %d '%s': at %g %g %g looking along %g %g %g, up %g %g %g, fov %g, aspect %g",
             index, c->name, c->position.x, c->position.y, c->position.z, c->direction.x,
             c->direction.y, c->direction.z, c->up.x, c->up.y, c->up.z, c->fov, c->aspect);
}

static void light_text(const mesh_light *l, int index, char *out, size_t size) {
    snprintf(out, size, "light %d '%s': %s, at %g %g %g, colour x intensity %g %g %g", index,
             l->name, l->kind, l->position.x, l->position.y, l->position.z, l->color[0],
             l->color[1], l->color[2]);
}

/* The file's cameras, for a message that asks for one it has not. */
static void camera_list(const mesh *m, char *out, size_t size) {
    size_t used = 0;
    out[0] = '\0';
    for (int k = 0; k < m->camera_count && used < size; k++)
        used += (size_t)snprintf(out + used, size - used, "%s%d '%s'%s", k ? ", " : "", k,
                                 m->cameras[k].name,
                                 m->cameras[k].orthographic ? " (orthographic)" : "");
}

/* The camera --camera names (an index or a name) in *index; false (err) when there is none. */
static bool pick_camera(const char *path, const mesh *m, const char *named, int *index,
                        scene_error *err) {
    char list[384];
    camera_list(m, list, sizeof list);
    if (!named) {
        *index = m->camera_count > 0 ? 0 : -1;
        return true;
    }
    char *end;
    errno = 0;
    long k = strtol(named, &end, 10);
    bool number = *named >= '0' && *named <= '9' && !*end && errno == 0;
    for (int c = 0; c < m->camera_count && !number; c++)
        if (!strcmp(m->cameras[c].name, named)) {
            *index = c;
            return true;
        }
    if (number && k < m->camera_count) {
        *index = (int)k;
        return true;
    }
    if (m->camera_count == 0)
        return fail(err, path,
                    "--camera %s: the file has no camera (without --camera one "
                    "frames the model)",
                    named);
    return fail(err, path, "--camera %s: the file has %d camera%s: %s", named, m->camera_count,
                m->camera_count == 1 ? "" : "s", list);
}

/* False (err) unless camera k can be rendered: its aspect finite and above 0, and a perspective
 * camera's fov in (0, 179] degrees or an orthographic one's view width finite and above 0. */
static bool check_camera(const char *path, const mesh_camera *c, int k, scene_error *err) {
    if (!isfinite(c->aspect) || !(c->aspect > 0.0))
        return fail(err, path,
                    "camera %d '%s' has an aspect ratio of %g: it must be finite and above 0", k,
                    c->name, c->aspect);
    if (c->orthographic && (!isfinite(c->view_width) || !(c->view_width >= ORTHO_MIN_WIDTH) ||
                            c->view_width > ORTHO_MAX_WIDTH))
        return fail(err, path,
                    "orthographic camera %d '%s' has a view %g wide: it must be from %g to %g", k,
                    c->name, c->view_width, ORTHO_MIN_WIDTH, ORTHO_MAX_WIDTH);
    if (!c->orthographic && (!isfinite(c->fov) || !(c->fov > 0.0) || c->fov > 179.0))
        return fail(err, path,
                    "camera %d '%s' has a horizontal field of view of %g degrees: it must be "
                    "finite, above 0 and at most 179",
                    k, c->name, c->fov);
    return true;
}

/* Appends to the text, false when it is full. */
static bool add(char *text, size_t size, size_t *used, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static bool add(char *text, size_t size, size_t *used, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(text + *used, size - *used, fmt, ap);
    va_end(ap);
    if (n < 0 || (size_t)n >= size - *used) return false;
    *used += (size_t)n;
    return true;
}

/* path as a scene's `mesh file` reads it: quoted, with \" and \\, where a word would not hold it.
 */
static void quoted_path(const char *path, char *out, size_t size) {
    size_t n = 0;
    out[n++] = '"';
    for (const char *c = path; *c && n + 4 < size; c++) {
        if (*c == '"' || *c == '\\') out[n++] = '\\';
        out[n++] = *c;
    }
    out[n++] = '"';
    out[n] = '\0';
}

/* The camera and plane lines of camera k (-1: the framing camera of the model's box). */
static bool view_lines(const char *path, const mesh *m, int k, long long width, char *text,
                       size_t size, size_t *used, scene_error *err) {
    double aspect = k >= 0 ? m->cameras[k].aspect : FRAME_ASPECT;
    double rows = llround((double)width / aspect);
    if (rows < 1.0 || rows > SCENE_MAX_RESOLUTION)
        return fail(err, path,
                    "a width of %lld pixels at the camera's aspect %g gives %g rows: "
                    "they must be 1 to %d",
                    width, aspect, rows, SCENE_MAX_RESOLUTION);
    if (k >= 0 && m->cameras[k].orthographic) {
        const mesh_camera *c = &m->cameras[k];
        add(text, size, used,
            "camera position %.9g %.9g %.9g direction %.9g %.9g %.9g up %.9g %.9g %.9g "
            "projection orthographic\n",
            c->position.x, c->position.y, c->position.z, c->direction.x, c->direction.y,
            c->direction.z, c->up.x, c->up.y, c->up.z);
        /* the view the file gives, width pixels across: whole pixels of a float's size */
        double pixel = (float)(c->view_width / (double)width);
        return add(text, size, used, "plane width %.17g height %.17g pixel %.9g\n",
                   (double)width * pixel, rows * pixel, pixel);
    }
    if (k >= 0) {
        const mesh_camera *c = &m->cameras[k];
        add(text, size, used,
            "camera position %.9g %.9g %.9g direction %.9g %.9g %.9g up %.9g %.9g %.9g fov %.9g\n",
            c->position.x, c->position.y, c->position.z, c->direction.x, c->direction.y,
            c->direction.z, c->up.x, c->up.y, c->up.z, (double)(float)c->fov);
    } else {
        vec3 lo = v3(0, 0, 0), hi = lo;
        mesh_bounds(m, &lo, &hi); /* (a loaded model has a face) */
        double c[3] = {0.5 * ((double)lo.x + hi.x), 0.5 * ((double)lo.y + hi.y),
                       0.5 * ((double)lo.z + hi.z)};
        double e[3] = {(double)hi.x - lo.x, (double)hi.y - lo.y, (double)hi.z - lo.z};
        double r = 0.5 * sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        if (!(r > 0.0)) r = 1.0;
        double pi = 3.14159265358979323846, half_h = FRAME_FOV * pi / 360.0;
        double half_v = atan(tan(half_h) * rows / (double)width);
        double d = r / sin(fmin(half_h, half_v)), l = sqrt(3.0);
        add(text, size, used, "camera position %.9g %.9g %.9g look_at %.9g %.9g %.9g fov %g\n",
            c[0] + d * frame_from[0] / l, c[1] + d * frame_from[1] / l,
            c[2] + d * frame_from[2] / l, c[0], c[1], c[2], FRAME_FOV);
    }
    return add(text, size, used, "plane width %lld height %.0f pixel 1\n", width, rows);
}

/* Whether the mesh line's `lights on` brings file light l in (mesh_lights.c). */
static bool renders(const mesh_light *l) {
    return !strcmp(l->kind, "point") || !strcmp(l->kind, "spot") || !strcmp(l->kind, "directional");
}

/* False (err) when a light the scene takes has a negative or non-finite intensity; *lit: how
 * many lights it takes. */
static bool check_lights(const char *path, const mesh *m, int *lit, scene_error *err) {
    *lit = 0;
    for (int k = 0; k < m->light_count; k++) {
        const mesh_light *l = &m->lights[k];
        float power;
        vec3 color;
        if (!renders(l)) continue;
        if (!mesh_light_power(l, &power, &color))
            return fail(err, path,
                        "light %d '%s' (%s) has colour x intensity %g %g %g: each must be finite "
                        "and at least 0",
                        k, l->name, l->kind, l->color[0], l->color[1], l->color[2]);
        (*lit)++;
    }
    return true;
}

/* Loads path; false (err) when it cannot be. */
static bool load(const char *path, mesh *m, scene_error *err) {
    char error[512];
    if (mesh_load(path, false, m, error, sizeof error)) return true;
    const char *dot = strrchr(path, '.');
    if (dot && !strcasecmp(dot, ".blend") && !strncmp(error, "cannot load", 11))
        return fail(err, path, "%s (assimp: %s)", MODEL_BLENDER_ADVICE, error);
    return fail(err, path, "%s", error);
}

bool model_scene_parse(const char *path, const model_scene_opts *o, scene *out, scene_error *err) {
    mesh m;
    if (!load(path, &m, err)) return false;
    for (int k = 0; k < m.camera_count; k++) {
        char line[512];
        camera_text(&m.cameras[k], k, line, sizeof line);
        log_debug("%s: %s", path, line);
    }
    for (int k = 0; k < m.light_count; k++) {
        char line[512];
        light_text(&m.lights[k], k, line, sizeof line);
        log_debug("%s: %s", path, line);
    }
    int camera = -1;
    long long width = o->width > 0 ? o->width : MODEL_DEFAULT_WIDTH;
    size_t size = LINE_BYTES * 4, used = 0;
    char *text = malloc(size), quoted[PATH_MAX * 2 + 4];
    int lit = 0;
    bool ok = text && pick_camera(path, &m, o->camera, &camera, err) &&
              (camera < 0 || check_camera(path, &m.cameras[camera], camera, err)) &&
              view_lines(path, &m, camera, width, text, size, &used, err) &&
              check_lights(path, &m, &lit, err);
    if (!text) fail(err, path, "out of memory");
    if (ok && camera >= 0)
        log_debug("%s: rendered from camera %d '%s'", path, camera, m.cameras[camera].name);
    if (ok && camera < 0) log_debug("%s: no camera: one frames the model", path);
    /* the mesh line takes the model loaded here rather than import it again */
    mesh_cache *cache = NULL;
    if (!ok || !mesh_cache_adopt(&cache, path, false, &m)) mesh_free(&m);
    if (ok) {
        quoted_path(path, quoted, sizeof quoted);
        ok = add(text, size, &used, "mesh file %s lights on\n", quoted);
        if (ok && o->environment) {
            quoted_path(o->environment, quoted, sizeof quoted);
            ok = add(text, size, &used, "environment file %s\n", quoted);
        } else if (ok && !lit) {
            ok = add(text, size, &used, "background 1 1 1\n");
        }
        ok = ok && add(text, size, &used, "render mode path\n");
        if (!ok) fail(err, path, "its path is too long");
    }
    if (ok) {
        char name[300];
        snprintf(name, sizeof name, "<%s as a scene>", path);
        ok = parser_run_cached(text, used, name, o->mode, cache, out, err);
        cache = NULL;
        for (int k = 0; ok && k < out->warning_count; k++) { /* as the errors below */
            snprintf(out->warnings[k].file, sizeof out->warnings[k].file, "%s", path);
            out->warnings[k].line = out->warnings[k].col = 0;
        }
        if (!ok && !err->out_of_memory) {
            /* the text is ours: its line and column would mean nothing to the user */
            char message[sizeof err->message];
            snprintf(message, sizeof message, "%s", err->message);
            fail(err, path, "%s", message);
        }
    }
    mesh_cache_free(cache);
    free(text);
    return ok;
}

bool model_scene_list(const char *path, FILE *out, scene_error *err) {
    mesh m;
    if (!load(path, &m, err)) return false;
    size_t placed = m.face_count;
    for (int k = 0; k < m.instance_count; k++) placed += m.parts[m.instances[k].part].count;
    char shared[160] = "";
    if (m.instance_count)
        snprintf(shared, sizeof shared,
                 " (%zu unique: %zu placed once, %zu in %d meshes that %d instances share)",
                 m.face_count + m.part_face_count, m.face_count, m.part_face_count, m.part_count,
                 m.instance_count);
    fprintf(out, "%s: %zu faces%s, %d camera%s, %d light%s\n", path, placed, shared, m.camera_count,
            m.camera_count == 1 ? "" : "s", m.light_count, m.light_count == 1 ? "" : "s");
    char line[512];
    for (int k = 0; k < m.camera_count; k++) {
        camera_text(&m.cameras[k], k, line, sizeof line);
        fprintf(out, "  %s\n", line);
    }
    for (int k = 0; k < m.light_count; k++) {
        light_text(&m.lights[k], k, line, sizeof line);
        fprintf(out, "  %s\n", line);
    }
    mesh_free(&m);
    return true;
}
