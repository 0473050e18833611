/* film.c: allocating and freeing a film. */
#include "image/film.h"

#include <stdlib.h>

#include "util/big_memory.h"

bool film_init(film *f, int width, int height) {
    *f = (film){0};
    f->accum = big_calloc((size_t)width * (size_t)height * 4, sizeof(float));
    if (!f->accum) return false;
    f->width = width;
    f->height = height;
    return true;
}

void film_free(film *f) {
    free(f->accum);
    *f = (film){0};
}
