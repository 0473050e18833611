/* chunk_push.h: a closed chunk's value onto a pixel's stack of chunk-tree blocks
 * (src/render/chunk_tree.h), one text for C and GLSL (dialect.h): placed at block `top`, then
 * merged `merges` times into the blocks below it, each merge left + right in float. The includer
 * names the stack: CHUNK_STACK_PARAM and CHUNK_STACK_ARG (its leading parameters and arguments)
 * and CHUNK_STACK_FLOAT(k, c), the lvalue of component c (0..2, RGB) of block k. */
#ifndef TRAZADOR_COMMON_CHUNK_PUSH_H
#define TRAZADOR_COMMON_CHUNK_PUSH_H

#include "dialect.h"

/* Block k of the stack, as RGB. */
TZ_FN vec3 chunk_stack_load(CHUNK_STACK_PARAM TZ_UINT k) {
    return v3(CHUNK_STACK_FLOAT(k, 0u), CHUNK_STACK_FLOAT(k, 1u), CHUNK_STACK_FLOAT(k, 2u));
}

/* Sets block k of the stack to v. */
TZ_FN void chunk_stack_store(CHUNK_STACK_PARAM TZ_UINT k, vec3 v) {
    CHUNK_STACK_FLOAT(k, 0u) = v.x;
    CHUNK_STACK_FLOAT(k, 1u) = v.y;
    CHUNK_STACK_FLOAT(k, 2u) = v.z;
}

/* Pushes chunk_value at block top, merging as chunk_stack_push reported; never fails. */
TZ_FN void chunk_push(CHUNK_STACK_PARAM TZ_UINT top, TZ_UINT merges, vec3 chunk_value) {
    TZ_PRECISE vec3 sum = chunk_value;
    for (TZ_UINT m = 0u; m < merges; m++) {
        top -= 1u;
        TZ_PRECISE vec3 left = chunk_stack_load(CHUNK_STACK_ARG top);
        sum = v3_add(left, sum);
    }
    chunk_stack_store(CHUNK_STACK_ARG top, sum);
}

/* The total of the stack's first n blocks, folded as chunk_sum_fold does: the top, then each
 * block below added on its left; zero for n = 0. */
TZ_FN vec3 chunk_stack_total(CHUNK_STACK_PARAM TZ_UINT n) {
    /* Not precise: sums alone have nothing to contract, and glslang's propagation of precise
     * through this loop into main multiplied its compile time by twelve. */
    vec3 total = v3(0.0f, 0.0f, 0.0f);
    if (n > 0u) total = chunk_stack_load(CHUNK_STACK_ARG n - 1u);
    for (TZ_UINT k = n - 1u; n > 0u && k > 0u; k--)
        total = v3_add(chunk_stack_load(CHUNK_STACK_ARG k - 1u), total);
    return total;
}

#endif
