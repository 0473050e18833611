/* sampler.h: the numbers a sample draws, one text for C and GLSL (dialect.h), from its pixel and
 * index alone, so that any sample can be computed alone on any back end (DESIGN section 4): the
 * random stream of rng.h, or (TZ_FLAG_SOBOL) Owen-scrambled Sobol points drawn as Burley's
 * padded sequence ("Practical Hash-based Owen Scrambling", JCGT 2020): every draw is a dimension
 * of its own, one number (sobol's first dimension) or a pair (its first two), each draw's index
 * shuffled and its points scrambled by hashes of the pixel and the draw. */
#ifndef TRAZADOR_COMMON_SAMPLER_H
#define TRAZADOR_COMMON_SAMPLER_H

#include "dialect.h"
#include "rng.h"

TZ_STRUCT(sampler_state) {
    TZ_UINT state;     /* random: the stream's state; sobol: the pixel's key */
    TZ_UINT reversed;  /* sobol: the sample's index, its bits reversed */
    TZ_UINT dimension; /* sobol: the draws so far, the next draw's dimension */
}
TZ_STRUCT_END(sampler_state)

/* The sampler of sample sample_index of pixel pixel_index; random's state is rng_seed's. */
TZ_FN sampler_state sampler_start(TZ_UINT flags, TZ_UINT seed, TZ_UINT pixel_index,
                                  TZ_UINT sample_index) {
    TZ_UINT key = rng_hash(rng_hash(seed) ^ pixel_index);
    sampler_state s;
    s.state = (flags & TZ_FLAG_SOBOL) != 0u ? key : rng_hash(key ^ sample_index);
    s.reversed = bit_reverse(sample_index);
    s.dimension = 0u;
    return s;
}

/* A nested uniform scramble of the bits of x read from the lowest (Laine and Karras' hash with
 * the constants of Vegdahl's "Building a Better LK Hash", 2021): bit k of the result depends on
 * bits 0..k of x alone, a bijection for every seed. */
TZ_FN TZ_UINT owen_hash(TZ_UINT x, TZ_UINT seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16u) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/* Sobol's second dimension of index i, its bits reversed: digit j of the point is the xor of the
 * index bits b that hold every bit of j (the direction numbers are Pascal's triangle mod 2,
 * Lucas), a sum over supersets in five steps. */
TZ_FN TZ_UINT sobol_second_reversed(TZ_UINT i) {
    i ^= (i >> 1u) & 0x55555555u;
    i ^= (i >> 2u) & 0x33333333u;
    i ^= (i >> 4u) & 0x0f0f0f0fu;
    i ^= (i >> 8u) & 0x00ff00ffu;
    i ^= (i >> 16u) & 0x0000ffffu;
    return i;
}

/* A float in [0, 1) from the top 24 bits of x (exact), as rng_next's. */
TZ_FN float number_of_bits(TZ_UINT x) { return TZ_FLOAT(x >> 8u) * (1.0f / 16777216.0f); }

/* The number of a Sobol point given with its bits reversed, Owen-scrambled by seed. */
TZ_FN float owen_number(TZ_UINT reversed_point, TZ_UINT seed) {
    return number_of_bits(bit_reverse(owen_hash(reversed_point, seed)));
}

/* The next sobol draw's shuffled index with its bits reversed (an Owen scramble of the index,
 * which maps the first 2^m indices onto an aligned block of 2^m, so every power-of-two prefix is
 * still a net); key gets the draw's own hash for the points' scrambles. */
TZ_FN TZ_UINT sobol_draw_reversed(TZ_INOUT(sampler_state) s, TZ_INOUT(TZ_UINT) key) {
    TZ_UINT k = rng_hash(TZ_DEREF(s).state ^ rng_hash(TZ_DEREF(s).dimension));
    TZ_DEREF(s).dimension += 1u;
    TZ_DEREF(key) = rng_hash(k);
    return owen_hash(TZ_DEREF(s).reversed, k);
}

/* The next number in [0, 1). */
TZ_FN float sample_1d(TZ_UINT flags, TZ_INOUT(sampler_state) s) {
    if ((flags & TZ_FLAG_SOBOL) == 0u) return rng_next(TZ_REF(TZ_DEREF(s).state));
    TZ_UINT key;
    TZ_UINT i = bit_reverse(sobol_draw_reversed(s, TZ_REF(key)));
    return owen_number(i, key);
}

/* The next pair of numbers in [0, 1) into u and v (random: two numbers of the stream in turn). */
TZ_FN void sample_2d(TZ_UINT flags, TZ_INOUT(sampler_state) s, TZ_INOUT(float) u,
                     TZ_INOUT(float) v) {
    if ((flags & TZ_FLAG_SOBOL) == 0u) {
        TZ_DEREF(u) = rng_next(TZ_REF(TZ_DEREF(s).state));
        TZ_DEREF(v) = rng_next(TZ_REF(TZ_DEREF(s).state));
        return;
    }
    TZ_UINT key;
    TZ_UINT i = bit_reverse(sobol_draw_reversed(s, TZ_REF(key)));
    TZ_DEREF(u) = owen_number(i, key);
    TZ_DEREF(v) = owen_number(sobol_second_reversed(i), rng_hash(key));
}

#endif
