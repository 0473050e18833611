/* chunk_values.h: common/chunk_push.h over one pixel's stack of block values held as
 * value[k][0..2], block k's RGB (the CPU back end's lanes, the merge's pixels). */
#ifndef TRAZADOR_CHUNK_VALUES_H
#define TRAZADOR_CHUNK_VALUES_H

#include <stdint.h>

#include "util/vec3.h"

#define CHUNK_STACK_PARAM float(*blocks)[3],
#define CHUNK_STACK_ARG blocks,
#define CHUNK_STACK_FLOAT(k, c) blocks[k][c]
#include "common/chunk_push.h"

#endif
