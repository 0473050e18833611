/* rng.h: the counter-based RNG of DESIGN section 4; twin of shaders/rng.glsl, bit for bit. */
#ifndef TRAZADOR_RNG_H
#define TRAZADOR_RNG_H

#include <stdint.h>

/* PCG-style 32-bit hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020). */
static inline uint32_t rng_hash(uint32_t v) {
    uint32_t state = v * 747796405u + 2891336453u;
    uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* Returns the stream state of one sample of one pixel; any sample can be computed alone. */
static inline uint32_t rng_seed(uint32_t seed, uint32_t pixel_index, uint32_t sample_index) {
    return rng_hash(rng_hash(rng_hash(seed) ^ pixel_index) ^ sample_index);
}

/* Advances the state by one PCG step and returns a uniform float in [0, 1). */
static inline float rng_next(uint32_t *state) {
    *state = *state * 747796405u + 2891336453u;
    uint32_t s = *state;
    uint32_t word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (float)(((word >> 22u) ^ word) >> 8) * (1.0f / 16777216.0f);
}

#endif
