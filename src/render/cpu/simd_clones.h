/* simd_clones.h: SIMD_CLONES marks a function compiled once per x86-64 vector level (AVX-512,
 * AVX2, baseline), the best one for the processor chosen at load time; elsewhere it is compiled
 * once. Every clone computes bit-identical results (no FP contraction, IEEE operations only). */
#ifndef TRAZADOR_SIMD_CLONES_H
#define TRAZADOR_SIMD_CLONES_H

/* target_clones with x86-64-v4 needs GCC 11 or clang 14. */
#if defined(__x86_64__) && ((defined(__clang__) && __clang_major__ >= 14) || \
                            (!defined(__clang__) && defined(__GNUC__) && __GNUC__ >= 11))
#define SIMD_CLONES __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#else
#define SIMD_CLONES
#endif

#endif
