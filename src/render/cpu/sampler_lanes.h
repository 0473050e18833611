/* sampler_lanes.h: shaders/common/sampler.h over the LANES lanes of a packet build, each lane its
 * own sample's sampler, kept as arrays of its fields (an array of structs keeps gcc from
 * vectorizing the loops that copy them). The includer defines LANES and LANE_FN first. */
#ifndef TRAZADOR_RENDER_CPU_SAMPLER_LANES_H
#define TRAZADOR_RENDER_CPU_SAMPLER_LANES_H

#include "common/sampler.h"

#ifdef __AVX2__
#include <immintrin.h>
#endif

typedef struct sampler_lanes {
    uint32_t state[LANES], reversed[LANES], dimension[LANES];
} sampler_lanes;

/* Lane k's sampler_state. */
LANE_FN sampler_state lane_sampler(const sampler_lanes *s, int k) {
    sampler_state one = {s->state[k], s->reversed[k], s->dimension[k]};
    return one;
}

/* Lane k takes one where on, else keeps its sampler. */
LANE_FN void lane_sampler_set(sampler_lanes *s, int k, int on, sampler_state one) {
    s->state[k] = on ? one.state : s->state[k];
    s->reversed[k] = on ? one.reversed : s->reversed[k];
    s->dimension[k] = on ? one.dimension : s->dimension[k];
}

/* bit_reverse of each lane's x in place: with AVX2, each byte's bits through two nibble tables
 * and the bytes' order by byte shuffles (7 operations for 8 lanes, against bit_reverse's 19,
 * which were a tenth of path mode's time on smallpt's scene); bit_reverse elsewhere. */
LANE_FN void lanes_bit_reverse(uint32_t *x) {
#ifdef __AVX2__
    _Static_assert(LANES % 8 == 0, "lanes in whole AVX2 registers");
    /* nibble n reversed, in the high and in the low half of a byte; the bytes of a word
     * reversed (byte shuffles index within each 16-byte half) */
    static const uint8_t tables[3][32] = {
        {0x00, 0x80, 0x40, 0xc0, 0x20, 0xa0, 0x60, 0xe0, 0x10, 0x90, 0x50,
         0xd0, 0x30, 0xb0, 0x70, 0xf0, 0x00, 0x80, 0x40, 0xc0, 0x20, 0xa0,
         0x60, 0xe0, 0x10, 0x90, 0x50, 0xd0, 0x30, 0xb0, 0x70, 0xf0},
        {0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf,
         0x0, 0x8, 0x4, 0xc, 0x2, 0xa, 0x6, 0xe, 0x1, 0x9, 0x5, 0xd, 0x3, 0xb, 0x7, 0xf},
        {3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12,
         3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12}};
    const __m256i low = _mm256_set1_epi8(0x0f);
    const __m256i high_of = _mm256_loadu_si256((const __m256i *)tables[0]);
    const __m256i low_of = _mm256_loadu_si256((const __m256i *)tables[1]);
    const __m256i bytes_reversed = _mm256_loadu_si256((const __m256i *)tables[2]);
#if defined(__AVX512BW__)
    if (LANES % 16 == 0) {
        const __m512i low16 = _mm512_set1_epi8(0x0f);
        const __m512i high16 = _mm512_broadcast_i64x4(high_of),
                      low16_of = _mm512_broadcast_i64x4(low_of);
        const __m512i bytes16 = _mm512_broadcast_i64x4(bytes_reversed);
        for (int k = 0; k < LANES; k += 16) {
            __m512i v = _mm512_loadu_si512((const void *)(x + k));
            __m512i lo = _mm512_and_si512(v, low16),
                    hi = _mm512_and_si512(_mm512_srli_epi16(v, 4), low16);
            __m512i bits =
                _mm512_or_si512(_mm512_shuffle_epi8(high16, lo), _mm512_shuffle_epi8(low16_of, hi));
            _mm512_storeu_si512((void *)(x + k), _mm512_shuffle_epi8(bits, bytes16));
        }
        return;
    }
#endif
    for (int k = 0; k < LANES; k += 8) {
        __m256i v = _mm256_loadu_si256((const __m256i *)(x + k));
        __m256i lo = _mm256_and_si256(v, low), hi = _mm256_and_si256(_mm256_srli_epi16(v, 4), low);
        __m256i bits =
            _mm256_or_si256(_mm256_shuffle_epi8(high_of, lo), _mm256_shuffle_epi8(low_of, hi));
        _mm256_storeu_si256((__m256i *)(x + k), _mm256_shuffle_epi8(bits, bytes_reversed));
    }
#else
    for (int k = 0; k < LANES; k++) x[k] = bit_reverse(x[k]);
#endif
}

/* sample_1d of each lane where take[k], else 0 with its sampler left as it is: the loops over
 * lanes stay branch-free, so they compile to SIMD. */
LANE_FN void draw_lanes_1d(uint32_t flags, sampler_lanes *s, const int *take, float *u) {
    if ((flags & TZ_FLAG_SOBOL) == 0u) { /* the stream: only its state moves */
        for (int k = 0; k < LANES; k++) {
            sampler_state one = {s->state[k], 0u, 0u};
            float x = sample_1d(0u, &one);
            s->state[k] = take[k] ? one.state : s->state[k];
            u[k] = take[k] ? x : 0.0f;
        }
        return;
    }
    /* sample_1d's sobol draw, its bit reversals across the lanes */
    uint32_t i[LANES], key[LANES], point[LANES];
    for (int k = 0; k < LANES; k++) {
        sampler_state one = lane_sampler(s, k);
        i[k] = sobol_draw_reversed(&one, &key[k]);
        lane_sampler_set(s, k, take[k], one);
    }
    lanes_bit_reverse(i);
    for (int k = 0; k < LANES; k++) point[k] = owen_hash(i[k], key[k]);
    lanes_bit_reverse(point);
    for (int k = 0; k < LANES; k++) u[k] = take[k] ? number_of_bits(point[k]) : 0.0f;
}

/* sample_2d of each lane where take[k] into u and v, else 0 and 0, as draw_lanes_1d. */
LANE_FN void draw_lanes_2d(uint32_t flags, sampler_lanes *s, const int *take, float *u, float *v) {
    if ((flags & TZ_FLAG_SOBOL) == 0u) {
        for (int k = 0; k < LANES; k++) {
            sampler_state one = {s->state[k], 0u, 0u};
            float x, y;
            sample_2d(0u, &one, &x, &y);
            s->state[k] = take[k] ? one.state : s->state[k];
            u[k] = take[k] ? x : 0.0f;
            v[k] = take[k] ? y : 0.0f;
        }
        return;
    }
    /* sample_2d's sobol draw, its bit reversals across the lanes */
    uint32_t i[LANES], key[LANES], first[LANES], second[LANES];
    for (int k = 0; k < LANES; k++) {
        sampler_state one = lane_sampler(s, k);
        i[k] = sobol_draw_reversed(&one, &key[k]);
        lane_sampler_set(s, k, take[k], one);
    }
    lanes_bit_reverse(i);
    for (int k = 0; k < LANES; k++) {
        first[k] = owen_hash(i[k], key[k]);
        second[k] = owen_hash(sobol_second_reversed(i[k]), rng_hash(key[k]));
    }
    lanes_bit_reverse(first);
    lanes_bit_reverse(second);
    for (int k = 0; k < LANES; k++) {
        u[k] = take[k] ? number_of_bits(first[k]) : 0.0f;
        v[k] = take[k] ? number_of_bits(second[k]) : 0.0f;
    }
}

#endif
