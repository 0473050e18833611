/* chunk_values.h: common/chunk_push.h over one pixel's stack of block values held as
 * value[k][0..2], block k's RGB (the CPU back end's lanes, the merge's pixels). */
#ifndef TRAZADOR_CHUNK_VALUES_H
#define TRAZADOR_CHUNK_VALUES_H

#include <stdint.h>

#include "util/vec3.h"

/* Block k of the stack, as chunk_push reads it. */
static inline vec3 chunk_stack_load(float (*value)[3], uint32_t k) {
    return v3(value[k][0], value[k][1], value[k][2]);
}

/* Block k of the stack, as chunk_push writes it. */
static inline void chunk_stack_store(float (*value)[3], uint32_t k, vec3 v) {
    value[k][0] = v.x;
    value[k][1] = v.y;
    value[k][2] = v.z;
}

#define CHUNK_STACK_PARAM float(*blocks)[3],
#define CHUNK_STACK_ARG blocks,
#include "common/chunk_push.h"

#endif
