/* render_common.c: what both back ends share: options from the scene and the film. */
#include <stdlib.h>

#include "render/render.h"

void render_opts_from_scene(const scene *s, render_opts *opts) {
    *opts = (render_opts){0};
    opts->samples = s->samples;
    opts->seed = s->seed;
    opts->indirect = s->indirect;
    opts->bounces = s->bounces;
    opts->mode = s->mode;
    opts->roulette = s->roulette;
    opts->device = -1;
}

bool film_init(film *f, int width, int height) {
    *f = (film){0};
    f->accum = calloc((size_t)width * (size_t)height * 4, sizeof(float));
    if (!f->accum) return false;
    f->width = width;
    f->height = height;
    return true;
}

void film_free(film *f) {
    free(f->accum);
    *f = (film){0};
}
