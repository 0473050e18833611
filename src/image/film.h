/* film.h: the per-pixel accumulation a render resolves into an image. */
#ifndef TRAZADOR_FILM_H
#define TRAZADOR_FILM_H

#include <stdbool.h>
#include <stdint.h>

#include "image/aov.h"

/* Per-pixel accumulation: 4 floats a pixel, RGB sums and the count of finite samples. */
typedef struct film {
    int width, height;
    float *accum;
    uint64_t nonfinite; /* samples dropped because their radiance was NaN or infinite */
    aov_set aov;        /* the feature images asked for (--aov), each pixel's */
} film;

/* Allocates a zeroed film; false on out-of-memory. */
bool film_init(film *f, int width, int height);
/* Frees the film; safe on a zeroed film. */
void film_free(film *f);
/* Warns of what f cannot show as rendered: samples dropped as non-finite (and the pixels they
 * left with no sample, black), and pixels whose finite samples summed past the float range
 * (radiance near 3.4e38), written as infinity (PFM) or white. One pass over the film. */
void film_warn_problems(const film *f);

#endif
