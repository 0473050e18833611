/* dialect.h: what differs between C11 and GLSL 4.50 for the shared steps of shaders/common/, so
 * that one text compiles as both. The steps use vec3, v3(), the v3_* helpers, select3(), xyz(),
 * these TZ_ macros and TZ_UINT and TZ_VEC4 of shared_layout.h; each language gets the same
 * operations in the same order (C through util/vec3.h, GLSL through its operators), so both
 * back ends compute the same bits. */
#ifndef TRAZADOR_COMMON_DIALECT_H
#define TRAZADOR_COMMON_DIALECT_H

#include "../shared_layout.h"

#ifdef GL_core_profile

/* precise forbids glslang and the driver to fuse (a * b + c) or reorder: the C compiler does
 * neither (-ffp-contract=off), and without it lavapipe's images change. */
#define TZ_PRECISE /* every float operation is exact: tools/spirv_exact.c */
#define TZ_FN
#define TZ_LANE_FN
#define TZ_BOOL bool
/* C's branch-free & and | on 0/1 ints are && and || on GLSL bools. */
#define TZ_AND &&
#define TZ_OR ||
/* TZ_BRANCH_IF(c) { block }: a branch in GLSL, which lavapipe skips where a whole subgroup has c
 * false; in C the block always runs (its results must be selected by c inside), so that loops
 * over SIMD lanes stay branch-free. */
#define TZ_BRANCH_IF(c) if (c)
#define TZ_INOUT(type) inout type
#define TZ_DEREF(x) (x)
#define TZ_INFINITY uintBitsToFloat(0x7f800000u)
#define TZ_FLOAT(x) float(x)
#define TZ_SQRT(x) sqrt(x)
#define TZ_FLOOR(x) floor(x)
#define TZ_ABS(x) abs(x)
#define TZ_MAX(a, b) max(a, b)
#define TZ_MIN(a, b) min(a, b)
#define TZ_INT(x) int(x)
#define TZ_UINT_OF(x) uint(x)
#define TZ_TRUE true
#define TZ_FALSE false
/* An argument to a TZ_INOUT parameter, from a local variable. */
#define TZ_REF(x) (x)
/* A parameter a function does not read (yet): C warns, GLSL has no cast to void. */
#define TZ_UNUSED(x)
#define TZ_UNROLL [[unroll]]
/* The scene: globals of the shader (frame, the accessors), so no parameter. */
#define TZ_SCENE_PARAM
#define TZ_SCENE_ARG
#define TZ_SCENE_ONLY
#define TZ_FRAME frame
#define TZ_VEC4_ZERO vec4(0.0)
/* The frame's flags: the includer's specialization constant FLAGS, equal to frame.flags, so
 * that the compiler drops the code of the modes a render does not use. */
#define TZ_FLAGS FLAGS
/* A struct type: `TZ_STRUCT(name) { ... } TZ_STRUCT_END(name)`. */
#define TZ_STRUCT(name) struct name
#define TZ_STRUCT_END(name) ;

#define v3 vec3
#define v3_add(a, b) ((a) + (b))
#define v3_sub(a, b) ((a) - (b))
#define v3_mul(a, b) ((a) * (b))
#define v3_scale(a, s) ((a) * (s))
#define select3(c, a, b) ((c) ? (a) : (b))
#define xyz(v) ((v).xyz)
#define uint_bits(f) floatBitsToUint(f)
#define float_from_bits(u) uintBitsToFloat(u)
#define bit_reverse(x) bitfieldReverse(x)

/* Written out so that every sum runs in the C order: GLSL's dot(), length() and normalize()
 * promise neither an order nor a rounding. */
float v3_dot(vec3 a, vec3 b) {
    precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
    return r;
}

float v3_length(vec3 a) {
    precise float r = sqrt(v3_dot(a, a));
    return r;
}

vec3 v3_normalize(vec3 a) {
    precise vec3 r = a * (1.0 / v3_length(a));
    return r;
}

vec3 v3_cross(vec3 a, vec3 b) {
    precise vec3 r = vec3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
    return r;
}

float v3_max_abs(vec3 a) { return max(abs(a.x), max(abs(a.y), abs(a.z))); }

#else

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "util/vec3.h"

#define TZ_PRECISE
#define TZ_FN static inline
/* A TZ_FN that the CPU packet builds call inside their lane loops, always inlined: called, it
 * keeps the loop from being vectorized, and gcc stops inlining it when its caller grows. */
#define TZ_LANE_FN static inline __attribute__((always_inline))
#define TZ_BOOL int
#define TZ_AND &
#define TZ_OR |
#define TZ_BRANCH_IF(c)
#define TZ_INOUT(type) type *
#define TZ_DEREF(x) (*(x))
#define TZ_INFINITY INFINITY
#define TZ_FLOAT(x) ((float)(x))
#define TZ_SQRT(x) sqrtf(x)
#define TZ_FLOOR(x) floorf(x)
/* Selects rather than fabsf and fmaxf: the code the C integrator was measured with. */
#define TZ_ABS(x) ((x) < 0.0f ? -(x) : (x))
#define TZ_MAX(a, b) ((a) > (b) ? (a) : (b))
#define TZ_MIN(a, b) ((a) < (b) ? (a) : (b))
#define TZ_INT(x) ((int)(x))
#define TZ_UINT_OF(x) ((uint32_t)(x))
#define TZ_TRUE 1
#define TZ_FALSE 0
#define TZ_REF(x) (&(x))
#define TZ_UNUSED(x) (void)(x)
#define TZ_UNROLL
/* The scene: a packed_scene parameter named scene, first (the includer declares the type and
 * the accessors). */
#define TZ_SCENE_PARAM const packed_scene *scene,
#define TZ_SCENE_ARG scene,
#define TZ_SCENE_ONLY scene
#define TZ_FRAME (scene->frame)
#define TZ_VEC4_ZERO ((tz_vec4){0.0f, 0.0f, 0.0f, 0.0f})
#define TZ_FLAGS (scene->frame.flags)
#define TZ_STRUCT(name) typedef struct name
#define TZ_STRUCT_END(name) name;

/* a where c is true, else b, component by component (selects, not branches: SIMD-friendly). */
static inline vec3 select3(int c, vec3 a, vec3 b) {
    return v3(c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z);
}

/* xyz of a packed vec4. */
static inline vec3 xyz(tz_vec4 v) { return v3(v.x, v.y, v.z); }

/* The bits of a float (the BVH stores child references in floats' places; GLSL reads them as
 * uints). */
static inline uint32_t uint_bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* x with its 32 bits in reverse order (GLSL's bitfieldReverse; sampler.h's Sobol points). */
static inline uint32_t bit_reverse(uint32_t x) {
    x = ((x >> 1) & 0x55555555u) | ((x & 0x55555555u) << 1);
    x = ((x >> 2) & 0x33333333u) | ((x & 0x33333333u) << 2);
    x = ((x >> 4) & 0x0f0f0f0fu) | ((x & 0x0f0f0f0fu) << 4);
    x = ((x >> 8) & 0x00ff00ffu) | ((x & 0x00ff00ffu) << 8);
    return (x >> 16) | (x << 16);
}

/* The float of the bits u (transcendental.h builds powers of two from their exponent). */
static inline float float_from_bits(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

#endif

#endif
