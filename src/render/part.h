/* part.h: parts of a render (a region of pixels, a range of samples) as the chunk tree of
 * chunk_tree.h holds them; their OpenEXR files (viewable mean, plus what an exact merge needs);
 * and the merge that checks a set of parts and combines them into the whole render's sums. */
#ifndef TRAZADOR_PART_H
#define TRAZADOR_PART_H

#include <stdbool.h>
#include <stdint.h>

#include "image/aov.h"
#include "render/chunk_tree.h"
#include "render/render.h"

/* Longest digest, mode or version text. */
#define PART_TEXT_MAX 255

/* What a part is of. Parts merge only when every field but the region, the range and nonfinite
 * is equal. */
typedef struct part_meta {
    char digest[PART_TEXT_MAX + 1];  /* the scene and every setting that changes a sample */
    char mode[PART_TEXT_MAX + 1];    /* integrator mode, "report" or "path" */
    char version[PART_TEXT_MAX + 1]; /* trazador's version (TRAZADOR_VERSION) */
    /* The back end that rendered it, "cpu" or "vulkan: DEVICE, driver NAME, version N"; "" while
     * nothing is rendered. The two back ends (and two Vulkan drivers) differ by rounding, so
     * their parts do not mix. */
    char backend[PART_TEXT_MAX + 1];
    uint32_t seed;
    uint32_t spp;                      /* samples per pixel of the whole render, N */
    uint32_t sample_begin, sample_end; /* the samples summed here: sample_begin to sample_end - 1 */
    uint32_t chunk;                    /* TZ_CHUNK_SAMPLES of the trazador that wrote it */
    int width, height;                 /* the whole image */
    int x0, x1, y0, y1;                /* the region: x0 <= x < x1, y0 <= y < y1 */
    uint64_t nonfinite;                /* samples dropped as NaN or infinite */
    /* Rendered with a noise threshold (the digest has its value): each pixel keeps its adaptive
     * state, and the part begins at sample 0. */
    bool adaptive;
} part_meta;

/* A part's sums. Block k of the stack has 3 floats (RGB) a region pixel, rows top to bottom, in
 * block[k]; count has each pixel's finite samples. When sample_end ends no chunk (a checkpoint
 * mid-chunk), open has the unfinished chunk's compensated sums: sum RGB then compensation RGB, 6
 * floats a pixel; otherwise it is NULL. */
typedef struct part {
    part_meta meta;
    chunk_stack stack;
    float *block[CHUNK_STACK_MAX];
    uint32_t *count;
    float *open;
    /* The feature images (image/aov.h) of the region, of samples 0 to min(RENDER_AOV_SAMPLES,
     * spp) - 1 (in chunk 0): only a part that begins at sample 0 has them. */
    aov_set aov;
    /* With meta.adaptive, each pixel's state (common/adaptive.h): its odd chunks' RGB sum and the
     * chunk it stopped at (0 while sampled), 4 floats; otherwise NULL. */
    float *adaptive;
} part;

/* The first sample of chunk k of part p, or its spp past the last chunk. */
uint32_t part_sample_of(const part *p, uint32_t k);
/* The chunk that sample s of part p ends at: s / TZ_CHUNK_SAMPLES, or the chunk count at spp. */
uint32_t part_chunk_of(const part *p, uint32_t s);
/* Starts an empty part (meta's sample_end is set to its sample_begin) of zero sums; false
 * (logged) on invalid metadata or out of memory. */
bool part_init(part *p, const part_meta *meta);
/* A deep copy of src into dst; false (logged) on out of memory, with dst zeroed. */
bool part_copy(const part *src, part *dst);
/* Frees the sums (open too); safe on a zeroed part. */
void part_free(part *p);
/* Appends the next chunk: rgb has its compensated sum (film_sum_value) and count its finite
 * samples, for every region pixel; false (logged) when the part already ends at spp, ends inside
 * a chunk, or on out of memory. */
bool part_push_chunk(part *p, const float *rgb, const uint32_t *count);
/* The final sums of a whole part (all pixels, samples 0 to spp - 1) as the film a single render
 * makes; false (logged) on another part or out of memory. */
bool part_film(const part *p, film *out);
/* part_film of a part that may end early (a time limit): every pixel, samples 0 to sample_end -
 * 1; false (logged) on another part or out of memory. */
bool part_film_so_far(const part *p, film *out);

/* Writes p as an EXR part file, atomically; false (logged) on failure. */
bool part_write(const char *path, const part *p);
/* Reads and checks a part file; false (logged, naming the file) on an unreadable file or one
 * that is not a consistent trazador part. */
bool part_read(const char *path, part *out);

/* Merges n parts (names[i] names parts[i] in messages) into out, the whole render; false
 * (logged) when two parts differ in scene, seed, mode, version or settings, when two parts hold a
 * sample of the same pixel, when samples of some pixels are missing (listed), or out of memory. */
bool part_merge(const part *parts, const char *const *names, int n, part *out);
/* part_merge into a part that may be partial (a merged part is a bigger part): the smallest
 * region and sample range holding every part, which they must fill (gaps inside it are refused,
 * listed). */
bool part_merge_box(const part *parts, const char *const *names, int n, part *out);
/* Reads the n part files (part_read) and merges them (part_merge, or part_merge_box when whole
 * is false; each named by its path) into out; false (logged) on an unreadable file, a refused
 * merge or out of memory. */
bool part_merge_files(const char *const *paths, int n, bool whole, part *out);

#endif
