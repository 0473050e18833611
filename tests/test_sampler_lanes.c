/* test_sampler_lanes.c: the packet builds' lane draws (src/render/cpu/sampler_lanes.h: the Sobol
 * points' bit reversals done across the lanes, with byte shuffles where the build has AVX2 or
 * AVX-512) give sample_1d's and sample_2d's numbers and sampler states bit for bit, at every
 * vector level this processor runs (tests/sampler_lanes_check.c, compiled once per level). */
#include <stdbool.h>
#include <stdio.h>

#include "check.h"

long sampler_lanes_check_baseline(int rounds);
#ifdef TRAZADOR_CHECK_AVX2
long sampler_lanes_check_avx2(int rounds);
#endif
#ifdef TRAZADOR_CHECK_X86_64_V4
long sampler_lanes_check_x86_64_v4(int rounds);
#endif

#define ROUNDS 200000

static void test_builds(void) {
    long wrong = sampler_lanes_check_baseline(ROUNDS);
    CHECK(wrong == 0, "baseline: %ld lanes differ from the shared text", wrong);
    __builtin_cpu_init();
#ifdef TRAZADOR_CHECK_AVX2
    if (__builtin_cpu_supports("avx2")) {
        wrong = sampler_lanes_check_avx2(ROUNDS);
        CHECK(wrong == 0, "avx2: %ld lanes differ from the shared text", wrong);
    } else {
        printf("test_sampler_lanes: this processor has no AVX2: that build not checked here\n");
    }
#endif
#ifdef TRAZADOR_CHECK_X86_64_V4
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
        __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx2")) {
        wrong = sampler_lanes_check_x86_64_v4(ROUNDS);
        CHECK(wrong == 0, "x86-64-v4: %ld lanes differ from the shared text", wrong);
    } else {
        printf(
            "test_sampler_lanes: this processor has no x86-64-v4: that build not checked here\n");
    }
#endif
}

int main(void) {
    CHECK_CASE(test_builds);
    return check_summary("test_sampler_lanes");
}
