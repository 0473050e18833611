/* adaptive.h: the noise threshold's decision (render --noise-threshold), one text for C and GLSL
 * (dialect.h), so that both back ends stop a pixel at the same chunk. Before chunk k of a pixel
 * still sampled (from TZ_ADAPTIVE_MIN_CHUNKS on), its error is estimated from what the chunks
 * so far left: the mean I of all of them (the chunk tree's total) against the mean A of the odd
 * chunks (a second film of half the samples), |I - A| summed over the channels over
 * 1e-4 + sqrt(I.r + I.g + I.b), Cycles' measure (chunks: the first k are whole). A pixel at or
 * under the threshold renders no further sample: its later chunks are zero, so its sums stay those
 * of its samples, and the decision, a function of those alone, is the same on any split by regions,
 * thread count and back end. */
#ifndef TRAZADOR_COMMON_ADAPTIVE_H
#define TRAZADOR_COMMON_ADAPTIVE_H

#include "dialect.h"

/* Chunks every pixel renders before its error is first estimated. */
#define TZ_ADAPTIVE_MIN_CHUNKS 4u

/* The estimated error of a pixel whose first `chunks` whole chunks sum to total, their odd ones
 * to odd. */
TZ_FN float adaptive_error(vec3 total, vec3 odd, TZ_UINT chunks) {
    float all = TZ_FLOAT(chunks * TZ_CHUNK_SAMPLES);
    float odd_samples = TZ_FLOAT((chunks / 2u) * TZ_CHUNK_SAMPLES);
    TZ_PRECISE vec3 i = v3_scale(total, 1.0f / all);
    TZ_PRECISE vec3 a = v3_scale(odd, 1.0f / odd_samples);
    TZ_PRECISE float diff = TZ_ABS(i.x - a.x) + TZ_ABS(i.y - a.y) + TZ_ABS(i.z - a.z);
    TZ_PRECISE float scale = 0.0001f + TZ_SQRT(TZ_MAX(i.x + i.y + i.z, 0.0f));
    TZ_PRECISE float error = diff / scale;
    return error;
}

/* Whether a pixel still sampled takes chunk k, its first k chunks summing to total and odd:
 * always before TZ_ADAPTIVE_MIN_CHUNKS, then while its error is above threshold (a NaN error,
 * of sums past the float range, stops it). */
TZ_FN TZ_BOOL adaptive_goes_on(vec3 total, vec3 odd, TZ_UINT k, float threshold) {
    if (k < TZ_ADAPTIVE_MIN_CHUNKS) return TZ_TRUE;
    return adaptive_error(total, odd, k) > threshold;
}

#endif
