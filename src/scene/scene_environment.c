/* scene_environment.c: `environment color R G B` (and `background R G B`, its older name) and
 * `environment file PATH [rotate AX AY AZ DEG] [intensity S]`: the light of the world beyond the
 * scene, constant or an equirectangular HDR map (image/image_hdr.h) checked here: 2:1, every
 * value finite and >= 0 (scenes/README.md). */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image_hdr.h"
#include "scene/directives.h"
#include "scene/parser.h"

enum { ENV_FILE, ENV_ROTATE, ENV_INTENSITY, ENV_KEY_COUNT };
static const key_spec environment_keys[ENV_KEY_COUNT] = {
    {"file", NULL, VALUE_WORD, NO_RANGE},
    {"rotate", NULL, VALUE_NUMBER, NO_RANGE},
    {"intensity", NULL, VALUE_NUMBER, 0.0, FLT_MAX, true},
};
/* The constant environment's three numbers (no key after `background`). */
static const key_spec color_spec = {"color", "r g b", VALUE_NUMBER, 0.0, FLT_MAX, false};
static const key_spec background_spec = {"background", "r g b", VALUE_NUMBER, 0.0, FLT_MAX, false};

/* Only one of background and environment, once. */
static bool claim_environment(parser *p) {
    if (p->background_line) {
        return parser_fail(p, p->tokens[0].col,
                           "'%s' given twice (first on line %d), background and environment being "
                           "one directive",
                           parser_quote(p, &p->tokens[0]), p->background_line);
    }
    p->background_line = p->line;
    return true;
}

/* The three numbers of the constant environment from token *next on, nothing after them. */
static bool read_color(parser *p, const key_spec *spec, int next) {
    double value[3];
    int value_token[3];
    if (!parser_values(p, spec, &next, value, value_token)) return false;
    if (next < p->token_count) {
        return parser_fail(p, p->tokens[next].col, "unexpected '%s' after %s's 3 numbers",
                           parser_quote(p, &p->tokens[next]), spec->name);
    }
    p->s.background = v3((float)value[0], (float)value[1], (float)value[2]);
    return true;
}

bool directive_background(parser *p) {
    return claim_environment(p) && read_color(p, &background_spec, 1);
}

/* Reads the file form's keys: the path's token in *file, rotate's axis and angle, the
 * intensity; their columns in cols. False (reported) on an unknown key, one given twice or a bad
 * value. */
static bool read_keys(parser *p, int *file, double rotate[4], double *intensity,
                      int cols[ENV_KEY_COUNT]) {
    unsigned given = 0;
    for (int next = 1; next < p->token_count;) {
        const token *t = &p->tokens[next++];
        int key = 0;
        while (key < ENV_KEY_COUNT && !parser_token_is(t, environment_keys[key].name)) key++;
        if (key == ENV_KEY_COUNT)
            return parser_fail(p, t->col,
                               "unknown key '%s' for environment (expected color R G B, or file "
                               "PATH with rotate AX AY AZ DEG and intensity S)",
                               parser_quote(p, t));
        if (given & BIT(key))
            return parser_fail(p, t->col, "'%s' given twice", environment_keys[key].name);
        given |= BIT(key);
        cols[key] = t->col;
        if (key == ENV_FILE) {
            if (next >= p->token_count)
                return parser_fail(p, parser_end_col(p), "expected a path after 'file'");
            *file = next++;
            continue;
        }
        double value[3];
        int value_token[3];
        for (int c = 0; c < (key == ENV_ROTATE ? 4 : 1); c++) {
            if (!parser_values(p, &environment_keys[key], &next, value, value_token)) return false;
            if (key == ENV_ROTATE) rotate[c] = value[0];
        }
        if (key == ENV_INTENSITY) *intensity = value[0];
    }
    if (*file < 0)
        return parser_fail(p, p->tokens[0].col, "environment needs 'file PATH' or 'color R G B'");
    if ((given & BIT(ENV_ROTATE)) && rotate[0] == 0.0 && rotate[1] == 0.0 && rotate[2] == 0.0)
        return parser_fail(p, cols[ENV_ROTATE], "environment rotate axis must not be zero");
    return true;
}

/* Whether the map is 2:1 and every value finite and >= 0, its intensity applied (in double,
 * rounded once); false (reported at col, naming the file) where it is not. */
static bool check_map(parser *p, int col, const char *path, image *img, double intensity) {
    if (img->width != 2 * img->height) {
        return parser_fail(p, col,
                           "environment '%s' is %d x %d pixels: an equirectangular map is twice "
                           "as wide as it is high",
                           path, img->width, img->height);
    }
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    for (size_t i = 0; i < n; i++) {
        float v = img->rgb[i];
        double scaled = (double)v * intensity;
        if (!(v >= 0.0f) || !(scaled <= FLT_MAX)) {
            size_t pixel = i / 3;
            return parser_fail(p, col,
                               "environment '%s' has radiance %g at pixel (%zu, %zu): each value "
                               "must be finite and >= 0 (times the intensity)",
                               path, (double)v, pixel % (size_t)img->width,
                               pixel / (size_t)img->width);
        }
        img->rgb[i] = (float)scaled;
    }
    return true;
}

/* The rows of the map's frame: the transpose of the rotation rotate gives the map. */
static void map_frame(parser *p, const double rotate[4]) {
    double one[3] = {1.0, 1.0, 1.0}, none[3] = {0.0, 0.0, 0.0};
    mesh_transform xf = mesh_transform_make(one, rotate, none);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) p->s.environment.to_map[i][j] = (float)xf.r[j][i];
}

bool directive_environment(parser *p) {
    if (!claim_environment(p)) return false;
    if (p->token_count > 1 && parser_token_is(&p->tokens[1], "color"))
        return read_color(p, &color_spec, 2);
    int file = -1, cols[ENV_KEY_COUNT] = {0};
    double rotate[4] = {0.0, 1.0, 0.0, 0.0}, intensity = 1.0;
    if (!read_keys(p, &file, rotate, &intensity, cols)) return false;
    char path[PATH_MAX], why[512];
    if (!directive_file_path(p, &p->tokens[file], "environment", path, sizeof path)) return false;
    image img;
    if (!image_load_hdr(path, &img, why, sizeof why))
        return parser_fail(p, p->tokens[file].col, "environment '%s': %s", path, why);
    if (!check_map(p, p->tokens[file].col, path, &img, intensity)) {
        image_free(&img);
        return false;
    }
    p->s.environment.rgb = img.rgb;
    p->s.environment.width = img.width;
    p->s.environment.height = img.height;
    map_frame(p, rotate);
    return true;
}
