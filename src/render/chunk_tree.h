/* chunk_tree.h: how a pixel's samples are summed so that any split of a render merges back to
 * the very sums one machine makes (docs/DESIGN.md, "Parts and exact merging"). Samples come in
 * chunks of TZ_CHUNK_SAMPLES (chunk k: samples k*C to min((k+1)*C, N) - 1), each summed in sample
 * order with compensation (common/film_sum.h) into one float per channel. Chunks are combined along
 * a fixed binary tree over the chunk index: block (level l, index m) covers chunks m*2^l to
 * (m+1)*2^l - 1, and its value is left + right of its two halves, in float. A stack of blocks,
 * merging siblings as soon as both are there, holds any chunk-aligned range; its values depend
 * only on the blocks, so parts pushed in sample order rebuild the whole render's stack, which is
 * finally folded from the right (top + below, ...). */
#ifndef TRAZADOR_CHUNK_TREE_H
#define TRAZADOR_CHUNK_TREE_H

#include <stdbool.h>
#include <stdint.h>

#include "shared_layout.h" /* TZ_CHUNK_SAMPLES: samples a chunk holds */

/* Most blocks a stack holds: two per level of a 32-bit chunk index. */
#define CHUNK_STACK_MAX 64

/* Chunks index << level to ((index + 1) << level) - 1. */
typedef struct chunk_block {
    uint32_t level, index;
} chunk_block;

/* The blocks that hold chunks first to end - 1, bottom to top. */
typedef struct chunk_stack {
    uint32_t first, end;
    int count;
    chunk_block block[CHUNK_STACK_MAX];
} chunk_stack;

/* The first chunk of block b; never fails. */
static inline uint64_t chunk_block_first(chunk_block b) { return (uint64_t)b.index << b.level; }
/* One past the last chunk of block b; never fails. */
static inline uint64_t chunk_block_end(chunk_block b) { return ((uint64_t)b.index + 1) << b.level; }

/* An empty stack that starts at chunk first; never fails. */
static inline chunk_stack chunk_stack_at(uint32_t first) {
    chunk_stack s = {.first = first, .end = first, .count = 0};
    return s;
}

/* Pushes block b, which must begin where the stack ends, then merges the top two blocks while
 * they are siblings. Returns how many merges were made (the caller combines its values alike,
 * chunk_sum_combine on the top two, that many times); -1 if b does not begin at s->end or would
 * pass chunk 2^32 - 1, leaving s as it was. */
static inline int chunk_stack_push(chunk_stack *s, chunk_block b) {
    if (b.level > 31 || chunk_block_first(b) != s->end || chunk_block_end(b) > UINT32_MAX ||
        s->count >= CHUNK_STACK_MAX)
        return -1;
    s->end = (uint32_t)chunk_block_end(b);
    s->block[s->count++] = b;
    int merges = 0;
    while (s->count >= 2) {
        chunk_block *top = &s->block[s->count - 1], *below = top - 1;
        if (below->level != top->level || (top->index & 1u) == 0 || below->index + 1 != top->index)
            break;
        below->level++;
        below->index >>= 1;
        s->count--;
        merges++;
    }
    return merges;
}

/* The stack of chunks first to end - 1 (the canonical blocks, as chunks pushed one by one leave
 * them); false if end < first. */
static inline bool chunk_stack_of(uint32_t first, uint32_t end, chunk_stack *out) {
    *out = chunk_stack_at(first);
    if (end < first) return false;
    for (uint32_t k = first; k < end; k++) chunk_stack_push(out, (chunk_block){0, k});
    return true;
}

/* Merges right into left: left = left + right, channel by channel; never fails. */
static inline void chunk_sum_combine(float left[3], const float right[3]) {
    for (int c = 0; c < 3; c++) left[c] = left[c] + right[c];
}

/* The total of a stack of n values (value[k] of block k): the top, then each block below added on
 * its left, value[k] + total; 0 for n = 0. Never fails. */
static inline void chunk_sum_fold(const float *const *value, int n, float out[3]) {
    for (int c = 0; c < 3; c++) out[c] = n > 0 ? value[n - 1][c] : 0.0f;
    for (int k = n - 2; k >= 0; k--)
        for (int c = 0; c < 3; c++) out[c] = value[k][c] + out[c];
}

#endif
