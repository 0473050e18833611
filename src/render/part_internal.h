/* part_internal.h: what the three files of render parts share (not an API): region and chunk
 * arithmetic, the check of a part's description and a pixel's chunk-tree total. part.c holds
 * the sums, part_file.c their EXR files, part_merge.c the exact merge. */
#ifndef TRAZADOR_PART_INTERNAL_H
#define TRAZADOR_PART_INTERNAL_H

#include "render/chunk_tree.h"
#include "render/part.h"

/* The region's pixels. */
static inline size_t region_pixels(const part_meta *m) {
    return (size_t)(m->x1 - m->x0) * (size_t)(m->y1 - m->y0);
}

/* Chunks in a render of spp samples. */
static inline uint32_t chunk_count(uint32_t spp) {
    return spp / TZ_CHUNK_SAMPLES + (spp % TZ_CHUNK_SAMPLES != 0);
}

/* Whether sample s ends a chunk (or the render). */
static inline bool chunk_aligned(const part_meta *m, uint32_t s) {
    return s % TZ_CHUNK_SAMPLES == 0 || s == m->spp;
}

/* The chunk that sample s begins (s aligned), or the chunk count at the end. */
static inline uint32_t chunk_at(const part_meta *m, uint32_t s) {
    return s == m->spp ? chunk_count(m->spp) : s / TZ_CHUNK_SAMPLES;
}

/* Whether m describes a part; false (logged, `where` first) if not. */
bool part_meta_valid(const part_meta *m, const char *where);
/* The chunk-tree total of region pixel i; never fails. */
void part_pixel_total(const part *p, size_t i, float out[3]);

#endif
