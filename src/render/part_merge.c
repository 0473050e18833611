/* part_merge.c: the exact merge of render parts: refused for parts of other renders, parts that
 * overlap, leave gaps (listed) or end inside a chunk; else the single render's very sums. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/chunk_values.h"
#include "render/part_internal.h"
#include "util/big_memory.h"
#include "util/log.h"

/* Most missing pieces a refused merge lists. */
#define MISSING_LISTED 16

/* What differs between two parts' renders ("" if nothing) into why: the fields the digest covers
 * first, by name, and the digest (the scene and the other settings) only when they agree. */
static void meta_difference(const part_meta *a, const part_meta *b, char *why, size_t size) {
    why[0] = '\0';
    if (strcmp(a->version, b->version))
        snprintf(why, size, "trazador version %s against %s", a->version, b->version);
    else if (a->seed != b->seed)
        snprintf(why, size, "seed %" PRIu32 " against %" PRIu32, a->seed, b->seed);
    else if (strcmp(a->mode, b->mode))
        snprintf(why, size, "mode %s against %s", a->mode, b->mode);
    else if (a->spp != b->spp)
        snprintf(why, size, "%" PRIu32 " against %" PRIu32 " samples per pixel", a->spp, b->spp);
    else if (a->width != b->width || a->height != b->height)
        snprintf(why, size, "image %dx%d against %dx%d", a->width, a->height, b->width, b->height);
    else if (a->chunk != b->chunk)
        snprintf(why, size, "chunk size %" PRIu32 " against %" PRIu32, a->chunk, b->chunk);
    else if (strcmp(a->backend, b->backend))
        snprintf(why, size,
                 "back end %s against %s (back ends and Vulkan drivers differ by rounding: "
                 "render every part on one)",
                 a->backend, b->backend);
    else if (strcmp(a->digest, b->digest))
        snprintf(why, size,
                 "scene digest %s against %s (the scene or a setting that changes "
                 "samples: bounces, indirect, jitter, roulette, sampler, light_samples)",
                 a->digest, b->digest);
}

/* Whether two parts hold a sample of the same pixel. */
static bool parts_overlap(const part_meta *a, const part_meta *b) {
    return a->x0 < b->x1 && b->x0 < a->x1 && a->y0 < b->y1 && b->y0 < a->y1 &&
           a->sample_begin < b->sample_end && b->sample_begin < a->sample_end;
}

/* Sorted distinct values of a list; returns how many remain. */
static int sort_unique(int64_t *v, int n) {
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && v[j - 1] > v[j]; j--) {
            int64_t t = v[j];
            v[j] = v[j - 1];
            v[j - 1] = t;
        }
    int m = 0;
    for (int i = 0; i < n; i++)
        if (m == 0 || v[m - 1] != v[i]) v[m++] = v[i];
    return m;
}

/* The index of value x in the sorted list v of n. */
static int index_of(const int64_t *v, int n, int64_t x) {
    int lo = 0, hi = n - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (v[mid] < x)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

/* The breakpoints of a merge: the regions' edges (xs, ys) and the ranges' ends (ss). */
typedef struct merge_grid {
    int nx, ny, ns;
    int64_t *xs, *ys, *ss;
} merge_grid;

static bool grid_init(merge_grid *g, const part *parts, int n, const part_meta *box) {
    *g = (merge_grid){0};
    size_t len = 2 * (size_t)n + 2;
    g->xs = malloc(len * sizeof *g->xs);
    g->ys = malloc(len * sizeof *g->ys);
    g->ss = malloc(len * sizeof *g->ss);
    if (!g->xs || !g->ys || !g->ss) return false;
    g->xs[0] = box->x0, g->xs[1] = box->x1, g->ys[0] = box->y0, g->ys[1] = box->y1;
    g->ss[0] = box->sample_begin, g->ss[1] = box->sample_end;
    for (int i = 0; i < n; i++) {
        const part_meta *m = &parts[i].meta;
        g->xs[2 + 2 * i] = m->x0, g->xs[3 + 2 * i] = m->x1;
        g->ys[2 + 2 * i] = m->y0, g->ys[3 + 2 * i] = m->y1;
        g->ss[2 + 2 * i] = m->sample_begin, g->ss[3 + 2 * i] = m->sample_end;
    }
    g->nx = sort_unique(g->xs, (int)len);
    g->ny = sort_unique(g->ys, (int)len);
    g->ns = sort_unique(g->ss, (int)len);
    return true;
}

static void grid_free(merge_grid *g) {
    free(g->xs);
    free(g->ys);
    free(g->ss);
}

/* A piece no part holds: pixels x0 <= x < x1, y0 <= y < y1, samples s0 to s1 - 1. */
typedef struct missing_piece {
    int64_t x0, x1, y0, y1, s0, s1;
} missing_piece;

/* Adds a piece to the list, joined to one it continues (below it, or the next samples of the
 * same pixels); returns the new count. */
static int missing_add(missing_piece *list, int count, int cap, missing_piece p) {
    for (int k = count - 1; k >= 0; k--) {
        missing_piece *q = &list[k];
        if (q->x0 == p.x0 && q->x1 == p.x1 && q->s0 == p.s0 && q->s1 == p.s1 && q->y1 == p.y0) {
            q->y1 = p.y1;
            return count;
        }
        if (q->x0 == p.x0 && q->x1 == p.x1 && q->y0 == p.y0 && q->y1 == p.y1 && q->s1 == p.s0) {
            q->s1 = p.s1;
            return count;
        }
    }
    if (count < cap) list[count] = p;
    return count + 1;
}

/* Checks that every sample of every pixel is in some part (they do not overlap); false (logged,
 * listing what is missing) if not. */
static bool merge_covers(const part *parts, int n, const merge_grid *g) {
    int cells = (g->nx - 1) * (g->ny - 1);
    unsigned char *held = malloc((size_t)cells);
    missing_piece list[MISSING_LISTED];
    int missing = 0;
    if (!held) {
        log_error("merge: out of memory");
        return false;
    }
    for (int t = 0; t + 1 < g->ns; t++) {
        memset(held, 0, (size_t)cells);
        for (int i = 0; i < n; i++) {
            const part_meta *m = &parts[i].meta;
            if (m->sample_begin > g->ss[t] || m->sample_end < g->ss[t + 1]) continue;
            int ix0 = index_of(g->xs, g->nx, m->x0), ix1 = index_of(g->xs, g->nx, m->x1);
            int iy0 = index_of(g->ys, g->ny, m->y0), iy1 = index_of(g->ys, g->ny, m->y1);
            for (int y = iy0; y < iy1; y++)
                memset(held + y * (g->nx - 1) + ix0, 1, (size_t)(ix1 - ix0));
        }
        for (int y = 0; y + 1 < g->ny; y++)
            for (int x = 0; x + 1 < g->nx; x++) {
                if (held[y * (g->nx - 1) + x]) continue;
                int x_end = x;
                while (x_end + 1 < g->nx - 1 && !held[y * (g->nx - 1) + x_end + 1]) x_end++;
                missing = missing_add(list, missing, MISSING_LISTED,
                                      (missing_piece){g->xs[x], g->xs[x_end + 1], g->ys[y],
                                                      g->ys[y + 1], g->ss[t], g->ss[t + 1]});
                x = x_end;
            }
    }
    free(held);
    if (!missing) return true;
    log_error(
        "merge: the parts leave samples of some pixels out; missing (region x0,x1,y0,y1 "
        "and samples A:B):");
    for (int k = 0; k < missing && k < MISSING_LISTED; k++)
        log_error("  region %" PRId64 ",%" PRId64 ",%" PRId64 ",%" PRId64 " samples %" PRId64
                  ":%" PRId64,
                  list[k].x0, list[k].x1, list[k].y0, list[k].y1, list[k].s0, list[k].s1);
    if (missing > MISSING_LISTED) log_error("  and %d more pieces", missing - MISSING_LISTED);
    return false;
}

/* Whether the parts can merge: one render, whole chunks, no overlap; false (logged) if not. */
static bool merge_check(const part *parts, const char *const *names, int n) {
    char why[2 * PART_TEXT_MAX + 128];
    for (int i = 1; i < n; i++) {
        meta_difference(&parts[0].meta, &parts[i].meta, why, sizeof why);
        if (why[0]) {
            log_error("merge: %s and %s are parts of different renders: %s", names[0], names[i],
                      why);
            return false;
        }
    }
    int first = -1; /* the first part of chunk 0: they all hold the same feature images */
    for (int i = 0; i < n; i++) {
        if (parts[i].meta.sample_begin != 0) continue;
        if (first < 0) first = i;
        if (parts[i].aov.mask == parts[first].aov.mask) continue;
        log_error("merge: %s and %s hold other feature images (--aov): render them alike",
                  names[first], names[i]);
        return false;
    }
    for (int i = 0; i < n; i++)
        if (!chunk_aligned(&parts[i].meta, parts[i].meta.sample_end)) {
            log_error("merge: %s ends inside a chunk, at sample %" PRIu32
                      " (parts merge in whole chunks of %u samples): resume it to finish",
                      names[i], parts[i].meta.sample_end, TZ_CHUNK_SAMPLES);
            return false;
        }
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++) {
            const part_meta *a = &parts[i].meta, *b = &parts[j].meta;
            if (!parts_overlap(a, b)) continue;
            log_error("merge: %s and %s both hold samples %" PRIu32 ":%" PRIu32
                      " of region %d,%d,%d,%d",
                      names[i], names[j],
                      a->sample_begin > b->sample_begin ? a->sample_begin : b->sample_begin,
                      a->sample_end < b->sample_end ? a->sample_end : b->sample_end,
                      a->x0 > b->x0 ? a->x0 : b->x0, a->x1 < b->x1 ? a->x1 : b->x1,
                      a->y0 > b->y0 ? a->y0 : b->y0, a->y1 < b->y1 ? a->y1 : b->y1);
            return false;
        }
    return true;
}

/* Rebuilds pixel (x, y) of out from the parts that hold it (order: theirs by first sample),
 * pushing their blocks as the single render pushed its chunks; false if the blocks do not
 * continue one another (which merge_check rules out). */
static bool merge_pixel(const part *parts, const int *order, int held, int x, int y, part *out) {
    chunk_stack s = chunk_stack_at(out->stack.first);
    float value[CHUNK_STACK_MAX][3];
    uint32_t count = 0;
    for (int h = 0; h < held; h++) {
        const part *q = &parts[order[h]];
        size_t i =
            (size_t)(y - q->meta.y0) * (size_t)(q->meta.x1 - q->meta.x0) + (size_t)(x - q->meta.x0);
        for (int k = 0; k < q->stack.count; k++) {
            int top = s.count, merges = chunk_stack_push(&s, q->stack.block[k]);
            if (merges < 0) return false;
            const float *v = &q->block[k][3 * i];
            chunk_push(value, (uint32_t)top, (uint32_t)merges, v3(v[0], v[1], v[2]));
        }
        count += q->count[i];
    }
    if (s.count != out->stack.count) return false;
    const part_meta *m = &out->meta;
    size_t o = (size_t)(y - m->y0) * (size_t)(m->x1 - m->x0) + (size_t)(x - m->x0);
    for (int h = 0; h < held && out->adaptive; h++) { /* the noise threshold's state */
        const part *q = &parts[order[h]];
        size_t i =
            (size_t)(y - q->meta.y0) * (size_t)(q->meta.x1 - q->meta.x0) + (size_t)(x - q->meta.x0);
        if (q->adaptive) memcpy(&out->adaptive[4 * o], &q->adaptive[4 * i], 4 * sizeof(float));
    }
    for (int h = 0; h < held && out->aov.mask; h++) { /* the part of chunk 0 has them */
        const part *q = &parts[order[h]];
        if (q->meta.sample_begin != 0) continue;
        size_t i =
            (size_t)(y - q->meta.y0) * (size_t)(q->meta.x1 - q->meta.x0) + (size_t)(x - q->meta.x0);
        for (int k = 0; k < AOV_COUNT; k++) {
            size_t w = (size_t)aov_channels((aov_kind)k);
            if (out->aov.plane[k])
                memcpy(&out->aov.plane[k][w * o], &q->aov.plane[k][w * i], w * sizeof(float));
        }
    }
    for (int k = 0; k < s.count; k++) memcpy(&out->block[k][3 * o], value[k], sizeof value[k]);
    out->count[o] = count;
    return true;
}

/* Fills out's sums, cell by cell of the grid of region edges; false (logged) on failure. */
static bool merge_sums(const part *parts, int n, const merge_grid *g, part *out) {
    int *order = malloc((size_t)n * sizeof *order);
    if (!order) {
        log_error("merge: out of memory");
        return false;
    }
    bool ok = true;
    for (int cy = 0; ok && cy + 1 < g->ny; cy++)
        for (int cx = 0; ok && cx + 1 < g->nx; cx++) {
            int held = 0;
            for (int i = 0; i < n; i++) {
                const part_meta *m = &parts[i].meta;
                if (m->x0 > g->xs[cx] || m->x1 < g->xs[cx + 1] || m->y0 > g->ys[cy] ||
                    m->y1 < g->ys[cy + 1] || m->sample_begin == m->sample_end)
                    continue;
                int j = held++;
                for (; j > 0 && parts[order[j - 1]].meta.sample_begin > m->sample_begin; j--)
                    order[j] = order[j - 1];
                order[j] = i;
            }
            for (int64_t y = g->ys[cy]; ok && y < g->ys[cy + 1]; y++)
                for (int64_t x = g->xs[cx]; ok && x < g->xs[cx + 1]; x++)
                    ok = merge_pixel(parts, order, held, (int)x, (int)y, out);
        }
    if (!ok)
        log_error("merge: internal error: the parts' chunk blocks do not continue one another");
    free(order);
    return ok;
}

/* What the merge makes: the whole render, or (whole false) the smallest box of pixels and samples
 * that holds every part. */
static part_meta merge_box(const part *parts, int n, bool whole) {
    part_meta m = parts[0].meta;
    m.nonfinite = 0;
    for (int i = 0; i < n; i++) {
        const part_meta *q = &parts[i].meta;
        m.nonfinite += q->nonfinite;
        if (i == 0) continue;
        m.x0 = q->x0 < m.x0 ? q->x0 : m.x0, m.x1 = q->x1 > m.x1 ? q->x1 : m.x1;
        m.y0 = q->y0 < m.y0 ? q->y0 : m.y0, m.y1 = q->y1 > m.y1 ? q->y1 : m.y1;
        if (q->sample_begin < m.sample_begin) m.sample_begin = q->sample_begin;
        if (q->sample_end > m.sample_end) m.sample_end = q->sample_end;
    }
    if (whole) m.x0 = 0, m.x1 = m.width, m.y0 = 0, m.y1 = m.height;
    if (whole) m.sample_begin = 0, m.sample_end = m.spp;
    return m;
}

/* part_merge into the whole render, or (whole false) the box of merge_box, which the parts must
 * fill. */
static bool merge_parts(const part *parts, const char *const *names, int n, bool whole, part *out) {
    *out = (part){0};
    if (n < 1) {
        log_error("merge: no parts");
        return false;
    }
    if (!merge_check(parts, names, n)) return false;
    part_meta m = merge_box(parts, n, whole);
    merge_grid g;
    bool ok = grid_init(&g, parts, n, &m);
    if (!ok) log_error("merge: out of memory");
    ok = ok && merge_covers(parts, n, &g);
    uint32_t end = m.sample_end;
    ok = ok && part_init(out, &m);
    if (ok) {
        out->meta.sample_end = end;
        chunk_stack_of(chunk_at(&m, m.sample_begin), chunk_at(&m, end), &out->stack);
        size_t pixels = region_pixels(&m);
        for (int k = 0; ok && k < out->stack.count; k++)
            ok = (out->block[k] = big_malloc(pixels * 3 * sizeof(float))) != NULL;
        if (!ok) log_error("merge: out of memory for a %dx%d image", m.x1 - m.x0, m.y1 - m.y0);
        uint32_t aov = 0; /* the feature images of the parts of chunk 0 (merge_check: alike) */
        for (int i = 0; i < n; i++)
            if (parts[i].meta.sample_begin == 0) aov = parts[i].aov.mask;
        if (ok && m.sample_begin == 0 && aov) ok = aov_alloc(&out->aov, aov, pixels);
    }
    ok = ok && merge_sums(parts, n, &g, out);
    grid_free(&g);
    if (!ok) part_free(out);
    return ok;
}

bool part_merge(const part *parts, const char *const *names, int n, part *out) {
    return merge_parts(parts, names, n, true, out);
}

bool part_merge_box(const part *parts, const char *const *names, int n, part *out) {
    return merge_parts(parts, names, n, false, out);
}

bool part_merge_files(const char *const *paths, int n, bool whole, part *out) {
    *out = (part){0};
    part *parts = calloc(n > 0 ? (size_t)n : 1, sizeof *parts);
    if (!parts) {
        log_error("merge: out of memory for %d parts", n);
        return false;
    }
    bool ok = true;
    for (int i = 0; ok && i < n; i++) ok = part_read(paths[i], &parts[i]);
    ok = ok && merge_parts(parts, paths, n, whole, out);
    for (int i = 0; i < n; i++) part_free(&parts[i]);
    free(parts);
    return ok;
}
