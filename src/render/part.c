/* part.c: render parts' chunk-tree sums (part.h): start, copy, push a chunk, the film they
 * make. Their files are part_file.c, their merge part_merge.c. */
#include "render/part.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/image.h"
#include "render/part_internal.h"
#include "util/big_memory.h"
#include "util/log.h"

bool part_meta_valid(const part_meta *m, const char *where) {
    const char *why = NULL;
    if (m->width < 1 || m->height < 1 || m->width > IMAGE_MAX_DIM || m->height > IMAGE_MAX_DIM)
        why = "image size outside 1..16384";
    else if (m->x0 < 0 || m->x0 >= m->x1 || m->x1 > m->width || m->y0 < 0 || m->y0 >= m->y1 ||
             m->y1 > m->height)
        why = "region is empty or outside the image";
    else if (m->spp < 1 || m->spp > SCENE_MAX_SAMPLES)
        why = "samples per pixel outside 1..1048576";
    else if (m->sample_begin > m->sample_end || m->sample_end > m->spp)
        why = "sample range ends before it begins or past the samples per pixel";
    else if (m->sample_begin % TZ_CHUNK_SAMPLES != 0 && m->sample_begin != m->spp)
        why = "sample range does not begin at a chunk (a multiple of 16 samples)";
    else if (m->chunk != TZ_CHUNK_SAMPLES)
        why = "chunk size is not this trazador's 16 samples";
    else if (!m->digest[0] || !m->mode[0] || !m->version[0])
        why = "scene digest, mode or version missing";
    else if (m->adaptive && m->sample_begin != 0)
        why =
            "a noise threshold's part begins past sample 0 (its decisions need the samples "
            "before)";
    if (why)
        log_error("%s: %s (region %d,%d,%d,%d of %dx%d, samples %" PRIu32 ":%" PRIu32 " of %" PRIu32
                  ", chunk %" PRIu32 ")",
                  where, why, m->x0, m->x1, m->y0, m->y1, m->width, m->height, m->sample_begin,
                  m->sample_end, m->spp, m->chunk);
    return !why;
}

uint32_t part_sample_of(const part *p, uint32_t k) {
    uint64_t s = (uint64_t)k * TZ_CHUNK_SAMPLES;
    return s < p->meta.spp ? (uint32_t)s : p->meta.spp;
}

uint32_t part_chunk_of(const part *p, uint32_t s) {
    return s == p->meta.spp ? (p->meta.spp + TZ_CHUNK_SAMPLES - 1u) / TZ_CHUNK_SAMPLES
                            : s / TZ_CHUNK_SAMPLES;
}

bool part_init(part *p, const part_meta *meta) {
    *p = (part){.meta = *meta};
    p->meta.sample_end = p->meta.sample_begin;
    if (!part_meta_valid(&p->meta, "part")) return false;
    p->stack = chunk_stack_at(chunk_at(&p->meta, p->meta.sample_begin));
    p->count = big_calloc(region_pixels(&p->meta), sizeof *p->count);
    if (p->count && p->meta.adaptive &&
        !(p->adaptive = big_calloc(region_pixels(&p->meta) * 4, sizeof(float)))) {
        free(p->count);
        p->count = NULL;
    }
    if (!p->count) {
        log_error("out of memory for a part of %zu pixels", region_pixels(&p->meta));
        return false;
    }
    return true;
}

bool part_copy(const part *src, part *dst) {
    *dst = (part){.meta = src->meta, .stack = src->stack};
    size_t n = region_pixels(&src->meta);
    bool ok = (dst->count = big_malloc(n * sizeof *dst->count)) != NULL;
    if (ok) memcpy(dst->count, src->count, n * sizeof *dst->count);
    for (int k = 0; ok && k < src->stack.count; k++)
        if ((ok = (dst->block[k] = big_malloc(n * 3 * sizeof(float))) != NULL))
            memcpy(dst->block[k], src->block[k], n * 3 * sizeof(float));
    if (ok && src->open && (ok = (dst->open = big_malloc(n * 6 * sizeof(float))) != NULL))
        memcpy(dst->open, src->open, n * 6 * sizeof(float));
    if (ok && src->adaptive && (ok = (dst->adaptive = big_malloc(n * 4 * sizeof(float))) != NULL))
        memcpy(dst->adaptive, src->adaptive, n * 4 * sizeof(float));
    if (ok && src->aov.mask && (ok = aov_alloc(&dst->aov, src->aov.mask, n)))
        for (int k = 0; k < AOV_COUNT; k++)
            if (src->aov.plane[k])
                memcpy(dst->aov.plane[k], src->aov.plane[k],
                       n * (size_t)aov_channels((aov_kind)k) * sizeof(float));
    if (!ok) {
        log_error("out of memory for a copy of a part of %zu pixels", n);
        part_free(dst);
    }
    return ok;
}

void part_free(part *p) {
    for (int k = 0; k < CHUNK_STACK_MAX; k++) free(p->block[k]);
    free(p->count);
    free(p->open);
    free(p->adaptive);
    aov_free(&p->aov);
    *p = (part){0};
}

bool part_push_chunk(part *p, const float *rgb, const uint32_t *count) {
    part_meta *m = &p->meta;
    if (m->sample_end == m->spp || !chunk_aligned(m, m->sample_end)) {
        log_error("part: no whole chunk follows sample %" PRIu32 " of %" PRIu32, m->sample_end,
                  m->spp);
        return false;
    }
    size_t n = region_pixels(m);
    int top = p->stack.count;
    float *plane = big_malloc(n * 3 * sizeof *plane);
    if (!plane) {
        log_error("out of memory for a part of %zu pixels", n);
        return false;
    }
    int merges = chunk_stack_push(&p->stack, (chunk_block){0, p->stack.end});
    if (merges < 0) { /* past 2^32 chunks: part_meta_valid's sample limit rules it out */
        free(plane);
        log_error("part: chunk %" PRIu32 " does not fit the chunk tree", p->stack.end);
        return false;
    }
    memcpy(plane, rgb, n * 3 * sizeof *plane);
    p->block[top] = plane;
    for (int k = 0; k < merges; k++, top--) {
        for (size_t i = 0; i < n; i++)
            chunk_sum_combine(&p->block[top - 1][3 * i], &p->block[top][3 * i]);
        free(p->block[top]);
        p->block[top] = NULL;
    }
    for (size_t i = 0; i < n; i++) p->count[i] += count[i];
    uint32_t next = m->sample_end + TZ_CHUNK_SAMPLES;
    m->sample_end = next < m->spp && next > m->sample_end ? next : m->spp;
    return true;
}

void part_pixel_total(const part *p, size_t i, float out[3]) {
    const float *value[CHUNK_STACK_MAX];
    for (int k = 0; k < p->stack.count; k++) value[k] = &p->block[k][3 * i];
    chunk_sum_fold(value, p->stack.count, out);
}

static bool part_whole(const part_meta *m) {
    return m->x0 == 0 && m->y0 == 0 && m->x1 == m->width && m->y1 == m->height &&
           m->sample_begin == 0 && m->sample_end == m->spp;
}

/* The film of samples 0 to sample_end - 1 of every pixel; false (logged) on another part. */
static bool film_of(const part *p, film *out, bool whole) {
    *out = (film){0};
    const part_meta *m = &p->meta;
    bool all_pixels = m->x0 == 0 && m->y0 == 0 && m->x1 == m->width && m->y1 == m->height;
    if (!all_pixels || m->sample_begin != 0 || (whole && !part_whole(m))) {
        log_error("part: not a whole render (every pixel, samples 0:%" PRIu32 ")",
                  whole ? m->spp : m->sample_end);
        return false;
    }
    if (!film_init(out, p->meta.width, p->meta.height)) {
        log_error("out of memory for a %dx%d film", p->meta.width, p->meta.height);
        return false;
    }
    size_t n = region_pixels(&p->meta);
    for (size_t i = 0; i < n; i++) {
        part_pixel_total(p, i, &out->accum[4 * i]);
        out->accum[4 * i + 3] = (float)p->count[i];
    }
    out->nonfinite = p->meta.nonfinite;
    if (p->aov.mask && !aov_alloc(&out->aov, p->aov.mask, n)) {
        film_free(out);
        return false;
    }
    for (int k = 0; k < AOV_COUNT; k++)
        if (p->aov.plane[k])
            memcpy(out->aov.plane[k], p->aov.plane[k],
                   n * (size_t)aov_channels((aov_kind)k) * sizeof(float));
    return true;
}

bool part_film(const part *p, film *out) { return film_of(p, out, true); }

bool part_film_so_far(const part *p, film *out) { return film_of(p, out, false); }
