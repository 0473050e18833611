/* render_common.c: what both back ends share: options from the scene, the film and the progress
 * line. */
#include <stdio.h>
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

void render_progress_print(double share, double seconds, double samples) {
    char rate[48] = "", left[48] = "";
    if (seconds > 0.0 && share > 0.0) {
        snprintf(rate, sizeof rate, ", %.2f Msamples/s", share * samples / seconds * 1e-6);
        snprintf(left, sizeof left, ", %.1f s left", seconds * (1.0 - share) / share);
    }
    fprintf(stderr, "\r\033[Ktrazador: rendering %5.1f%%, %.1f s%s%s", 100.0 * share, seconds, rate,
            left);
}

void render_progress_clear(void) { fprintf(stderr, "\r\033[K"); }
