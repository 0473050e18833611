/* test_rng.c: pins the first numbers of a few streams of the counter-based RNG (DESIGN section 4),
 * so that any change to its one text, shaders/common/rng.h (compiled by C and GLSL alike), is
 * caught. The values were computed by an independent Python implementation of the same
 * definition. */
#include <string.h>

#include "check.h"
#include "common/rng.h"

int main(void) {
    CHECK(rng_hash(0u) == 0x07bb2fe2u, "rng_hash(0) = 0x%08x", rng_hash(0u));
    CHECK(rng_hash(1u) == 0xa8beea3cu, "rng_hash(1) = 0x%08x", rng_hash(1u));
    static const struct {
        uint32_t seed, pixel, sample, state;
        float first[4];
    } streams[] = {
        {1u,
         0u,
         0u,
         0x2370168fu,
         {0.12928366661071777f, 0.7215718626976013f, 0.7166843414306641f, 0.8453775644302368f}},
        {1u,
         12345u,
         7u,
         0x461c9bb5u,
         {0.17032700777053833f, 0.5803965926170349f, 0.7612467408180237f, 0.08671325445175171f}},
        {42u,
         0u,
         63u,
         0xb8e61839u,
         {0.5494966506958008f, 0.03054577112197876f, 0.08852815628051758f, 0.24574631452560425f}},
        {4294967295u,
         16777215u,
         1048575u,
         0xe047ceb7u,
         {0.8209831714630127f, 0.8779606819152832f, 0.0030795931816101074f, 0.8107886910438538f}},
    };
    for (size_t k = 0; k < sizeof streams / sizeof streams[0]; k++) {
        uint32_t state = rng_seed(streams[k].seed, streams[k].pixel, streams[k].sample);
        CHECK(state == streams[k].state, "stream %zu state 0x%08x", k, state);
        for (int n = 0; n < 4; n++) {
            float x = rng_next(&state);
            CHECK(x == streams[k].first[n], "stream %zu number %d = %.9g", k, n, x);
        }
    }
    /* Floats lie in [0, 1) and cover it: a coarse histogram of one long stream. */
    uint32_t state = rng_seed(7u, 0u, 0u);
    int bins[16];
    memset(bins, 0, sizeof bins);
    for (int n = 0; n < 160000; n++) {
        float x = rng_next(&state);
        if (x < 0.0f || x >= 1.0f) {
            CHECK(0, "number %d out of [0,1): %g", n, x);
            break;
        }
        bins[(int)(x * 16.0f)]++;
    }
    for (int b = 0; b < 16; b++)
        CHECK(bins[b] > 9500 && bins[b] < 10500, "bin %d has %d", b, bins[b]);
    return check_summary("test_rng");
}
