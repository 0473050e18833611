/* sampler_lanes_check.c: draw_lanes_1d and draw_lanes_2d of src/render/cpu/sampler_lanes.h at
 * one vector level (compiled once per level by tests/CMakeLists.txt, as the packet builds are)
 * against sample_1d and sample_2d of the shared text, number for number: random lane states,
 * random lanes taking, both samplers. Returns the count of differences. */
#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "common/sampler.h"

#define LANES CHECK_LANES
#define LANE_FN static inline __attribute__((always_inline))
#include "render/cpu/sampler_lanes.h"

#define CHECK_NAME_OF(build) sampler_lanes_check_##build
#define CHECK_NAME(build) CHECK_NAME_OF(build)

long CHECK_NAME(CHECK_BUILD)(int rounds);

long CHECK_NAME(CHECK_BUILD)(int rounds) {
    long wrong = 0;
    uint32_t x = 0x1234567u;
    for (int r = 0; r < rounds; r++) {
        uint32_t flags = (r & 1) ? TZ_FLAG_SOBOL : 0u;
        sampler_lanes lanes;
        sampler_state one[LANES];
        int take[LANES];
        for (int k = 0; k < LANES; k++) {
            x = rng_hash(x);
            one[k] = sampler_start(flags, x, x >> 7, rng_hash(x) & 0xffffu);
            one[k].dimension = x % 40u;
            take[k] = (rng_hash(x + 1u) & 3u) != 0u;
            lane_sampler_set(&lanes, k, 1, one[k]);
        }
        float u[LANES], v[LANES];
        bool two = (r >> 1) & 1;
        if (two)
            draw_lanes_2d(flags, &lanes, take, u, v);
        else
            draw_lanes_1d(flags, &lanes, take, u);
        for (int k = 0; k < LANES; k++) {
            sampler_state s = one[k];
            float a = 0.0f, b = 0.0f;
            if (take[k] && two) sample_2d(flags, &s, &a, &b);
            if (take[k] && !two) a = sample_1d(flags, &s);
            sampler_state got = lane_sampler(&lanes, k);
            wrong += memcmp(&a, &u[k], sizeof a) != 0 ||
                     (two && memcmp(&b, &v[k], sizeof b) != 0) || got.state != s.state ||
                     got.reversed != s.reversed || got.dimension != s.dimension;
        }
    }
    return wrong;
}
