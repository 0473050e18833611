/* rng.h: the counter-based RNG of DESIGN section 4, one text for C and GLSL (dialect.h); 32-bit
 * unsigned arithmetic wraps the same way in both, so every back end draws the same numbers. */
#ifndef TRAZADOR_COMMON_RNG_H
#define TRAZADOR_COMMON_RNG_H

#include "dialect.h"

/* PCG-style 32-bit hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020). */
TZ_FN TZ_UINT rng_hash(TZ_UINT v) {
    TZ_UINT state = v * 747796405u + 2891336453u;
    TZ_UINT word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* Returns the stream state of one sample of one pixel; any sample can be computed alone. */
TZ_FN TZ_UINT rng_seed(TZ_UINT seed, TZ_UINT pixel_index, TZ_UINT sample_index) {
    return rng_hash(rng_hash(rng_hash(seed) ^ pixel_index) ^ sample_index);
}

/* Advances the state by one PCG step and returns a uniform float in [0, 1) from its top 24 bits
 * (exact in float). */
TZ_FN float rng_next(TZ_INOUT(TZ_UINT) state) {
    TZ_DEREF(state) = TZ_DEREF(state) * 747796405u + 2891336453u;
    TZ_UINT s = TZ_DEREF(state);
    TZ_UINT word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return TZ_FLOAT(((word >> 22u) ^ word) >> 8u) * (1.0f / 16777216.0f);
}

#endif
