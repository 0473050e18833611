/* rng.glsl: the counter-based RNG of DESIGN section 4; twin of src/rng.h, bit for bit
 * (32-bit unsigned arithmetic wraps the same way in C and GLSL). */
#ifndef TRAZADOR_RNG_GLSL
#define TRAZADOR_RNG_GLSL

/* PCG-style 32-bit hash (Jarzynski and Olano, "Hash Functions for GPU Rendering", 2020). */
uint rng_hash(uint v) {
    uint state = v * 747796405u + 2891336453u;
    uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

/* The stream state of one sample of one pixel. */
uint rng_seed(uint seed, uint pixel_index, uint sample_index) {
    return rng_hash(rng_hash(rng_hash(seed) ^ pixel_index) ^ sample_index);
}

/* One PCG step; a uniform float in [0, 1) from the top 24 bits (exact in float). */
float rng_next(inout uint state) {
    state = state * 747796405u + 2891336453u;
    uint s = state;
    uint word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return float(((word >> 22u) ^ word) >> 8u) * (1.0 / 16777216.0);
}

#endif
