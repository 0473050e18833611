/* test_sobol.c: the Sobol sampler of shaders/common/sampler.h: its second dimension against
 * Sobol's direction numbers, the stratification of its points (every elementary interval of
 * every power-of-two block of samples holds its one point, in 1D and 2D, for many pixels and
 * draws), draws that do not repeat one another, and the random sampler equal to rng.h's stream. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "common/sampler.h"

/* Sobol's second dimension of index i by its direction numbers (v_1 = 2^31, v_k = v_(k-1) xor
 * v_(k-1) / 2: the primitive polynomial x + 1), the textbook way. */
static uint32_t sobol_second_by_directions(uint32_t i) {
    uint32_t x = 0, v = 1u << 31;
    for (; i; i >>= 1, v ^= v >> 1)
        if (i & 1u) x ^= v;
    return x;
}

static uint32_t reverse_by_bits(uint32_t x) {
    uint32_t r = 0;
    for (int b = 0; b < 32; b++) r |= ((x >> b) & 1u) << (31 - b);
    return r;
}

static void test_bits(void) {
    uint32_t x = 12345u;
    int bad_reverse = 0, bad_sobol = 0;
    for (int k = 0; k < 1 << 20; k++) {
        x = rng_hash(x);
        uint32_t i = k < 1 << 16 ? (uint32_t)k : x;
        bad_reverse += bit_reverse(x) != reverse_by_bits(x);
        bad_sobol += bit_reverse(sobol_second_reversed(i)) != sobol_second_by_directions(i);
    }
    CHECK(bad_reverse == 0, "%d of 2^20 bit reversals wrong", bad_reverse);
    CHECK(bad_sobol == 0, "%d of 2^20 second-dimension points differ from the direction numbers",
          bad_sobol);
}

/* The points of draw `draw` (after draw draws of the other kind) of samples first..first+n-1. */
static void points(uint32_t seed, uint32_t pixel, uint32_t first, uint32_t n, int draw, int two,
                   float *u, float *v) {
    for (uint32_t k = 0; k < n; k++) {
        sampler_state s = sampler_start(TZ_FLAG_SOBOL, seed, pixel, first + k);
        for (int d = 0; d < draw; d++) (void)sample_1d(TZ_FLAG_SOBOL, &s);
        if (two)
            sample_2d(TZ_FLAG_SOBOL, &s, &u[k], &v[k]);
        else
            u[k] = sample_1d(TZ_FLAG_SOBOL, &s);
    }
}

/* Whether the 2^m points hold one point in every elementary interval 2^-a x 2^-(m-a) (a (0, m,
 * 2)-net), or in 1D in every interval 2^-m. */
static bool is_net(const float *u, const float *v, int m, int two) {
    uint32_t n = 1u << m;
    unsigned char *seen = malloc(n);
    bool ok = true;
    for (int a = 0; a <= (two ? m : 0) && ok; a++) {
        memset(seen, 0, n);
        for (uint32_t k = 0; k < n; k++) {
            uint32_t cx = (uint32_t)(u[k] * (float)(1u << (two ? a : m)));
            uint32_t cy = two ? (uint32_t)(v[k] * (float)(1u << (m - a))) : 0u;
            uint32_t cell = two ? (cx << (m - a)) | cy : cx;
            if (seen[cell]++) ok = false;
        }
    }
    free(seen);
    return ok;
}

static void test_stratification(void) {
    enum { MAX_M = 12 };
    static float u[1 << MAX_M], v[1 << MAX_M];
    int nets = 0, failures = 0;
    for (uint32_t pixel = 0; pixel < 24; pixel++) {
        for (int draw = 0; draw < 6; draw++) {
            for (int two = 0; two < 2; two++) {
                for (int m = 0; m <= MAX_M; m += pixel < 4 ? 1 : 4) {
                    /* the first samples, and blocks further on (--samples A:B parts start at
                     * multiples of 16) */
                    uint32_t block = (pixel * 7u + (uint32_t)draw) % 5u;
                    points(3u, pixel * 1031u, block << m, 1u << m, draw, two, u, v);
                    nets++;
                    if (!is_net(u, v, m, two)) {
                        failures++;
                        if (failures < 5)
                            fprintf(stderr, "pixel %u draw %d %dD: block %u of 2^%d not a net\n",
                                    pixel, draw, two ? 2 : 1, block, m);
                    }
                }
            }
        }
    }
    CHECK(failures == 0, "%d of %d blocks of points are not nets", failures, nets);
}

/* Draws of one sample are not the same numbers over again: between two draws, and between the
 * same draw of two pixels, the correlation over 4096 samples is small and the values differ. */
static void test_independence(void) {
    enum { N = 4096 };
    static float a[N], b[N], c[N], d[N], pa[N], pb[N];
    points(9u, 5u, 0u, N, 0, 1, a, b);
    points(9u, 5u, 0u, N, 1, 1, c, d);
    points(9u, 6u, 0u, N, 0, 1, pa, pb);
    const float *pairs[][2] = {{a, c}, {b, d}, {a, d}, {a, b}, {a, pa}, {b, pb}};
    for (size_t p = 0; p < sizeof pairs / sizeof pairs[0]; p++) {
        double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
        int same = 0;
        for (int k = 0; k < N; k++) {
            double x = pairs[p][0][k], y = pairs[p][1][k];
            sx += x;
            sy += y;
            sxx += x * x;
            syy += y * y;
            sxy += x * y;
            same += pairs[p][0][k] == pairs[p][1][k];
        }
        double cov = sxy / N - sx / N * sy / N;
        double r = cov / sqrt((sxx / N - sx / N * sx / N) * (syy / N - sy / N * sy / N));
        CHECK(fabs(r) < 0.05, "pair %zu: correlation %.4f", p, r);
        CHECK(same < 8, "pair %zu: %d equal values", p, same);
        CHECK(fabs(sx / N - 0.5) < 1e-3, "pair %zu: mean %.5f", p, sx / N);
    }
}

/* Without TZ_FLAG_SOBOL the sampler is rng.h's stream: the same numbers as before it existed. */
static void test_random_is_the_stream(void) {
    int differ = 0;
    for (uint32_t k = 0; k < 1000; k++) {
        uint32_t state = rng_seed(k * 7u, k * 13u, k);
        sampler_state s = sampler_start(TZ_FLAG_PATH, k * 7u, k * 13u, k);
        float u, v;
        sample_2d(TZ_FLAG_PATH, &s, &u, &v);
        differ += u != rng_next(&state);
        differ += v != rng_next(&state);
        differ += sample_1d(TZ_FLAG_PATH, &s) != rng_next(&state);
        differ += s.state != state;
    }
    CHECK(differ == 0, "%d numbers differ from the stream", differ);
}

/* The sobol numbers of a sample depend on its seed, pixel and index only, in [0, 1). */
static void test_range_and_seed(void) {
    int out = 0, same_seed = 0;
    for (uint32_t k = 0; k < 100000; k++) {
        sampler_state s = sampler_start(TZ_FLAG_SOBOL, 1u, k % 97u, k);
        sampler_state t = sampler_start(TZ_FLAG_SOBOL, 2u, k % 97u, k);
        for (int d = 0; d < 8; d++) {
            float x = sample_1d(TZ_FLAG_SOBOL, &s), y = sample_1d(TZ_FLAG_SOBOL, &t);
            out += !(x >= 0.0f && x < 1.0f);
            same_seed += x == y;
        }
    }
    CHECK(out == 0, "%d numbers outside [0, 1)", out);
    CHECK(same_seed < 100, "%d of 800000 numbers equal under another seed", same_seed);
}

int main(void) {
    CHECK_CASE(test_bits);
    CHECK_CASE(test_stratification);
    CHECK_CASE(test_independence);
    CHECK_CASE(test_random_is_the_stream);
    CHECK_CASE(test_range_and_seed);
    return check_summary("test_sobol");
}
