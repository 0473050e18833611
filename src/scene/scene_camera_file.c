/* scene_camera_file.c: `camera file PATH [index N | name NAME] [scale ...] [rotate ...]
 * [translate ...]`: a model file's camera (mesh_cameras.c, in trazador's space) taken into a
 * scene, moved by the transform its mesh line gives the model (scenes/README.md, `camera`). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/mesh_cache.h"
#include "scene/mesh_load.h"
#include "scene/parser.h"

enum { CF_FILE, CF_INDEX, CF_NAME, CF_SCALE, CF_ROTATE, CF_TRANSLATE, CF_KEY_COUNT };
static const key_spec camera_file_keys[CF_KEY_COUNT] = {
    {"file", NULL, VALUE_WORD, NO_RANGE},
    {"index", NULL, VALUE_INTEGER, 0.0, MESH_MAX_CAMERAS - 1, false},
    {"name", NULL, VALUE_WORD, NO_RANGE},
    {"scale", NULL, VALUE_NUMBER, COORD_RANGE},
    {"rotate", NULL, VALUE_NUMBER, NO_RANGE},
    {"translate", "x y z", VALUE_NUMBER, COORD_RANGE},
};

/* Whether the token can start a number (scale's second value or the next key). */
static bool numeric(const token *t) {
    char c = t->text[0];
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

/* Reads the line's keys: the path and name tokens in *file and *name (-1: none), the index, the
 * transform's numbers. False (reported) on an unknown key, one given twice or a bad value. */
static bool read_keys(parser *p, int *file, int *name, int *index, double scale[3],
                      double rotate[4], double translate[3], int cols[CF_KEY_COUNT]) {
    unsigned given = 0;
    for (int next = 1; next < p->token_count;) {
        const token *t = &p->tokens[next++];
        int key = 0;
        while (key < CF_KEY_COUNT && !parser_token_is(t, camera_file_keys[key].name)) key++;
        if (key == CF_KEY_COUNT)
            return parser_fail(p, t->col,
                               "unknown key '%s' for camera file (expected one of: file index "
                               "name scale rotate translate)",
                               parser_quote(p, t));
        if (given & BIT(key))
            return parser_fail(p, t->col, "'%s' given twice", camera_file_keys[key].name);
        given |= BIT(key);
        cols[key] = t->col;
        if (key == CF_FILE || key == CF_NAME) {
            if (next >= p->token_count)
                return parser_fail(p, parser_end_col(p), "expected a %s after '%s'",
                                   key == CF_FILE ? "path" : "camera's name",
                                   camera_file_keys[key].name);
            *(key == CF_FILE ? file : name) = next++;
            continue;
        }
        int count = key == CF_ROTATE ? 4 : key == CF_INDEX ? 1 : 3;
        double *out = key == CF_ROTATE ? rotate : key == CF_SCALE ? scale : translate, one[3];
        int value_token[3];
        if (key == CF_INDEX || key == CF_TRANSLATE) {
            if (!parser_values(p, &camera_file_keys[key], &next, one, value_token)) return false;
            if (key == CF_INDEX) *index = (int)one[0];
            for (int c = 0; c < 3 && key == CF_TRANSLATE; c++) out[c] = one[c];
            continue;
        }
        for (int c = 0; c < count; c++) {
            if (key == CF_SCALE && c == 1 &&
                (next >= p->token_count || !numeric(&p->tokens[next]))) {
                out[1] = out[2] = out[0];
                break;
            }
            if (!parser_values(p, &camera_file_keys[key], &next, one, value_token)) return false;
            out[c] = one[0];
        }
    }
    if (*file < 0) return parser_fail(p, p->tokens[0].col, "camera file needs 'file PATH'");
    if ((given & BIT(CF_INDEX)) && (given & BIT(CF_NAME)))
        return parser_fail(p, cols[CF_NAME], "camera file takes index or name, not both");
    if (scale[0] == 0.0 || scale[1] == 0.0 || scale[2] == 0.0)
        return parser_fail(p, cols[CF_SCALE], "camera file scale must not be zero");
    if (rotate[0] == 0.0 && rotate[1] == 0.0 && rotate[2] == 0.0)
        return parser_fail(p, cols[CF_ROTATE], "camera file rotate axis must not be zero");
    return true;
}

/* The camera the line names (by index or name; the first without either) in *k; false
 * (reported at col, the cameras listed) when the file has no such camera. */
static bool pick(parser *p, const mesh *me, const char *path, int index, const char *name, int col,
                 int *k) {
    *k = -1;
    for (int c = 0; c < me->camera_count && *k < 0; c++)
        if (name ? !strcmp(me->cameras[c].name, name) : c == (index < 0 ? 0 : index)) *k = c;
    if (*k >= 0) return true;
    char list[384] = "";
    for (int c = 0; c < me->camera_count; c++)
        directive_append(list, sizeof list, "%s%d '%s'", c ? ", " : "", c, me->cameras[c].name);
    return parser_fail(p, col, "camera file '%s' has %d camera%s%s%s", path, me->camera_count,
                       me->camera_count == 1 ? "" : "s", me->camera_count ? ": " : "", list);
}

bool directive_camera_file(parser *p) {
    int file = -1, name = -1, index = -1, cols[CF_KEY_COUNT] = {0};
    double scale[3] = {1, 1, 1}, rotate[4] = {0, 0, 1, 0}, translate[3] = {0, 0, 0};
    if (!read_keys(p, &file, &name, &index, scale, rotate, translate, cols)) return false;
    const token *ft = &p->tokens[file];
    char named[PATH_MAX], path[PATH_MAX], camera_name[64] = "";
    if (!parser_path(p, ft, named, sizeof named)) return false;
    if (name >= 0 && !parser_path(p, &p->tokens[name], camera_name, sizeof camera_name))
        return false;
    /* relative to the scene file's folder, as a mesh line's */
    const char *slash = strrchr(p->filename, '/');
    int dir =
        named[0] == '/' || p->filename[0] == '<' || !slash ? 0 : (int)(slash - p->filename) + 1;
    int n = snprintf(path, sizeof path, "%.*s%s", dir, p->filename, named);
    if (n < 0 || (size_t)n >= sizeof path) return parser_fail(p, ft->col, "path is too long");
    mesh me;
    char error[512];
    if (!mesh_cache_load(&p->meshes, path, false, &me, error, sizeof error))
        return parser_fail(p, ft->col, "camera file '%s': %s", path, error);
    int k;
    int col = name >= 0 ? p->tokens[name].col : index >= 0 ? cols[CF_INDEX] : ft->col;
    bool ok = pick(p, &me, path, index, name >= 0 ? camera_name : NULL, col, &k);
    mesh_camera c = ok ? me.cameras[k] : (mesh_camera){0};
    mesh_free(&me);
    if (!ok) return false;
    if (!c.orthographic && (!isfinite(c.fov) || !(c.fov > 0.0) || c.fov > 179.0))
        return parser_fail(p, col,
                           "camera %d '%s' of '%s' has a horizontal field of view of %g degrees: "
                           "it must be finite, above 0 and at most 179",
                           k, c.name, path, c.fov);
    mesh_transform xf = mesh_transform_make(scale, rotate, translate);
    vec3 position, direction = mesh_transform_direction(&xf, c.direction),
                   up = mesh_transform_direction(&xf, c.up);
    if (!mesh_transform_point(&xf, c.position, &position))
        return parser_fail(p, ft->col, "camera %d '%s' leaves the coordinate range (1e18)", k,
                           c.name);
    /* the frame the renderer builds: right = up x direction, which must not vanish */
    double dl = v3_length(direction), ul = v3_length(up), cl = v3_length(v3_cross(up, direction));
    if (!(dl > 0.0) || !(ul > 0.0) || !(cl >= 1e-4 * dl * ul) || !isfinite(dl * ul))
        return parser_fail(p, ft->col,
                           "camera %d '%s' of '%s' has no frame: its direction (%g %g %g) and up "
                           "(%g %g %g) are zero or parallel",
                           k, c.name, path, direction.x, direction.y, direction.z, up.x, up.y,
                           up.z);
    p->s.camera_position = position;
    p->s.camera_direction = direction;
    p->s.camera_up = up;
    /* an orthographic camera's view is the scene's plane, as its image is */
    p->s.camera_fov = c.orthographic ? 0.0f : (float)c.fov;
    p->s.camera_orthographic = c.orthographic;
    p->s.camera_near = 0.0f;
    p->camera_col = p->fov_col = ft->col;
    if (!c.orthographic) p->fov_line = p->line;
    return true;
}
