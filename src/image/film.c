/* film.c: allocating and freeing a film, and saying what it cannot show. */
#include "image/film.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "util/big_memory.h"
#include "util/log.h"

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
    aov_free(&f->aov);
    *f = (film){0};
}

void film_warn_problems(const film *f) {
    size_t pixels = (size_t)f->width * (size_t)f->height, empty = 0, overflowed = 0;
    for (size_t k = 0; k < pixels; k++) {
        const float *px = &f->accum[4 * k];
        empty += !(px[3] > 0.0f);
        overflowed += !isfinite(px[0]) || !isfinite(px[1]) || !isfinite(px[2]);
    }
    if (f->nonfinite) {
        char black[96] = "";
        if (empty)
            snprintf(black, sizeof black, "; %zu pixel%s kept no sample and %s black", empty,
                     empty == 1 ? "" : "s", empty == 1 ? "is" : "are");
        log_warn("%llu sample%s had non-finite radiance and %s not accumulated%s",
                 (unsigned long long)f->nonfinite, f->nonfinite == 1 ? "" : "s",
                 f->nonfinite == 1 ? "was" : "were", black);
    }
    if (overflowed)
        log_warn(
            "%zu pixel%s summed %s samples past the float range (radiance near 3.4e38): "
            "%s infinite in PFM and white in 8-bit images",
            overflowed, overflowed == 1 ? "" : "s", overflowed == 1 ? "its" : "their",
            overflowed == 1 ? "it is" : "they are");
}
