/* part.c: render parts: their chunk-tree sums, their EXR files (image/exr.h) and their exact
 * merge, which refuses what would not give the single render's sums. */
#include "render/part.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/exr.h"
#include "image/image.h"
#include "util/log.h"

/* Most missing pieces a refused merge lists. */
#define MISSING_LISTED 16

static size_t region_pixels(const part_meta *m) {
    return (size_t)(m->x1 - m->x0) * (size_t)(m->y1 - m->y0);
}

/* Chunks in a render of spp samples. */
static uint32_t chunk_count(uint32_t spp) {
    return spp / CHUNK_SAMPLES + (spp % CHUNK_SAMPLES != 0);
}

/* Whether sample s ends a chunk (or the render). */
static bool chunk_aligned(const part_meta *m, uint32_t s) {
    return s % CHUNK_SAMPLES == 0 || s == m->spp;
}

/* The chunk that sample s begins (s aligned), or the chunk count at the end. */
static uint32_t chunk_at(const part_meta *m, uint32_t s) {
    return s == m->spp ? chunk_count(m->spp) : s / CHUNK_SAMPLES;
}

/* Whether m describes a part; false (logged, `where` first) if not. */
static bool meta_valid(const part_meta *m, const char *where) {
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
    else if (m->sample_begin % CHUNK_SAMPLES != 0 && m->sample_begin != m->spp)
        why = "sample range does not begin at a chunk (a multiple of 16 samples)";
    else if (m->chunk != CHUNK_SAMPLES)
        why = "chunk size is not this trazador's 16 samples";
    else if (!m->digest[0] || !m->mode[0] || !m->version[0])
        why = "scene digest, mode or version missing";
    if (why)
        log_error("%s: %s (region %d,%d,%d,%d of %dx%d, samples %" PRIu32 ":%" PRIu32 " of %" PRIu32
                  ", chunk %" PRIu32 ")",
                  where, why, m->x0, m->x1, m->y0, m->y1, m->width, m->height, m->sample_begin,
                  m->sample_end, m->spp, m->chunk);
    return !why;
}

bool part_init(part *p, const part_meta *meta) {
    *p = (part){.meta = *meta};
    p->meta.sample_end = p->meta.sample_begin;
    if (!meta_valid(&p->meta, "part")) return false;
    p->stack = chunk_stack_at(chunk_at(&p->meta, p->meta.sample_begin));
    p->count = calloc(region_pixels(&p->meta), sizeof *p->count);
    if (!p->count) {
        log_error("out of memory for a part of %zu pixels", region_pixels(&p->meta));
        return false;
    }
    return true;
}

bool part_copy(const part *src, part *dst) {
    *dst = (part){.meta = src->meta, .stack = src->stack};
    size_t n = region_pixels(&src->meta);
    bool ok = (dst->count = malloc(n * sizeof *dst->count)) != NULL;
    if (ok) memcpy(dst->count, src->count, n * sizeof *dst->count);
    for (int k = 0; ok && k < src->stack.count; k++)
        if ((ok = (dst->block[k] = malloc(n * 3 * sizeof(float))) != NULL))
            memcpy(dst->block[k], src->block[k], n * 3 * sizeof(float));
    if (ok && src->open && (ok = (dst->open = malloc(n * 6 * sizeof(float))) != NULL))
        memcpy(dst->open, src->open, n * 6 * sizeof(float));
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
    float *plane = malloc(n * 3 * sizeof *plane);
    if (!plane) {
        log_error("out of memory for a part of %zu pixels", n);
        return false;
    }
    int merges = chunk_stack_push(&p->stack, (chunk_block){0, p->stack.end});
    if (merges < 0) { /* past 2^32 chunks: meta_valid's sample limit rules it out */
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
    uint32_t next = m->sample_end + CHUNK_SAMPLES;
    m->sample_end = next < m->spp && next > m->sample_end ? next : m->spp;
    return true;
}

/* The chunk-tree total of region pixel i; never fails. */
static void pixel_total(const part *p, size_t i, float out[3]) {
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
        pixel_total(p, i, &out->accum[4 * i]);
        out->accum[4 * i + 3] = (float)p->count[i];
    }
    out->nonfinite = p->meta.nonfinite;
    return true;
}

bool part_film(const part *p, film *out) { return film_of(p, out, true); }

bool part_film_so_far(const part *p, film *out) { return film_of(p, out, false); }

/* The file's channels: R G B mean, count, each block's RGB, the open chunk's sums. */
typedef struct part_channels {
    int count;
    exr_channel ch[4 + 3 * CHUNK_STACK_MAX + 6];
} part_channels;

static void add_channel(part_channels *pc, exr_sample_type type, const char *prefix, char rgb) {
    exr_channel *ch = &pc->ch[pc->count++];
    *ch = (exr_channel){.type = type};
    if (!rgb)
        snprintf(ch->name, sizeof ch->name, "%s", prefix);
    else if (!prefix[0])
        snprintf(ch->name, sizeof ch->name, "%c", rgb);
    else
        snprintf(ch->name, sizeof ch->name, "%s.%c", prefix, rgb);
}

/* Names every channel p's file has, in the order part_write fills them (data pointers NULL). */
static void name_channels(const part *p, part_channels *pc) {
    static const char rgb[3] = {'R', 'G', 'B'};
    pc->count = 0;
    for (int c = 0; c < 3; c++) add_channel(pc, EXR_SAMPLE_FLOAT, "", rgb[c]);
    add_channel(pc, EXR_SAMPLE_UINT, "count", 0);
    for (int k = 0; k < p->stack.count; k++) {
        char prefix[64];
        snprintf(prefix, sizeof prefix, "sum.%" PRIu64 "-%" PRIu64,
                 chunk_block_first(p->stack.block[k]), chunk_block_end(p->stack.block[k]));
        for (int c = 0; c < 3; c++) add_channel(pc, EXR_SAMPLE_FLOAT, prefix, rgb[c]);
    }
    if (chunk_aligned(&p->meta, p->meta.sample_end)) return;
    for (int c = 0; c < 3; c++) add_channel(pc, EXR_SAMPLE_FLOAT, "open.sum", rgb[c]);
    for (int c = 0; c < 3; c++) add_channel(pc, EXR_SAMPLE_FLOAT, "open.comp", rgb[c]);
}

/* The file's string attributes. */
typedef struct part_attrs {
    exr_attr a[9];
} part_attrs;

/* The last, trazador.checksum, covers the others, the windows and every channel. */
static const char *const attr_names[9] = {
    "trazador.version", "trazador.digest", "trazador.mode",      "trazador.seed",    "trazador.spp",
    "trazador.samples", "trazador.chunk",  "trazador.nonfinite", "trazador.checksum"};

static void fill_attrs(const part_meta *m, part_attrs *pa) {
    for (int k = 0; k < 9; k++) snprintf(pa->a[k].name, sizeof pa->a[k].name, "%s", attr_names[k]);
    snprintf(pa->a[0].value, sizeof pa->a[0].value, "%s", m->version);
    snprintf(pa->a[1].value, sizeof pa->a[1].value, "%s", m->digest);
    snprintf(pa->a[2].value, sizeof pa->a[2].value, "%s", m->mode);
    snprintf(pa->a[3].value, sizeof pa->a[3].value, "%" PRIu32, m->seed);
    snprintf(pa->a[4].value, sizeof pa->a[4].value, "%" PRIu32, m->spp);
    snprintf(pa->a[5].value, sizeof pa->a[5].value, "%" PRIu32 ":%" PRIu32, m->sample_begin,
             m->sample_end);
    snprintf(pa->a[6].value, sizeof pa->a[6].value, "%" PRIu32, m->chunk);
    snprintf(pa->a[7].value, sizeof pa->a[7].value, "%" PRIu64, m->nonfinite);
}

/* FNV-1a over 8-byte words in four interleaved lanes (fast, and any flipped bit changes it),
 * continued from h. */
static void hash_bytes(uint64_t h[4], const void *data, size_t len) {
    const uint64_t prime = 0x100000001b3u;
    const unsigned char *b = data;
    size_t words = len / 8;
    for (size_t i = 0; i < words; i++) {
        uint64_t w;
        memcpy(&w, b + 8 * i, 8);
        h[i % 4] = (h[i % 4] ^ w) * prime;
    }
    for (size_t i = 8 * words; i < len; i++) h[0] = (h[0] ^ b[i]) * prime;
    h[1] = (h[1] ^ len) * prime;
}

/* The checksum of a part file's content: windows, the other trazador attributes (values as in
 * attrs), and the channels pc names, by name, from f; 16 hex digits into out. */
static void part_checksum(const exr_file *f, const char *const *attrs, const part_channels *pc,
                          char out[17]) {
    uint64_t h[4] = {0xcbf29ce484222325u, 1, 2, 3};
    int windows[6] = {f->display_width, f->display_height, f->x0, f->y0, f->width, f->height};
    hash_bytes(h, windows, sizeof windows);
    for (int k = 0; k < 8; k++) hash_bytes(h, attrs[k], strlen(attrs[k]) + 1);
    size_t n = (size_t)f->width * (size_t)f->height;
    for (int c = 0; c < pc->count; c++) {
        const exr_channel *ch = exr_file_channel(f, pc->ch[c].name);
        hash_bytes(h, pc->ch[c].name, strlen(pc->ch[c].name) + 1);
        if (ch) hash_bytes(h, ch->data, n * (ch->type == EXR_SAMPLE_HALF ? 2 : 4));
    }
    uint64_t sum = h[0] ^ (h[1] * 3) ^ (h[2] * 5) ^ (h[3] * 7);
    snprintf(out, 17, "%016" PRIx64, sum);
}

bool part_write(const char *path, const part *p) {
    const part_meta *m = &p->meta;
    size_t n = region_pixels(m);
    part_channels pc;
    name_channels(p, &pc);
    float *mean = malloc(n * 3 * sizeof *mean);
    float *open[6] = {NULL};
    bool has_open = p->open && !chunk_aligned(m, m->sample_end), ok = mean != NULL;
    for (int c = 0; ok && has_open && c < 6; c++)
        ok = (open[c] = malloc(n * sizeof(float))) != NULL;
    if (!ok) log_error("%s: out of memory for a part of %zu pixels", path, n);
    for (size_t i = 0; ok && i < n; i++) {
        float total[3];
        pixel_total(p, i, total);
        for (int c = 0; c < 3; c++) {
            if (has_open) total[c] += p->open[6 * i + c] - p->open[6 * i + 3 + c];
            mean[c * n + i] = p->count[i] ? total[c] / (float)p->count[i] : 0.0f;
            if (has_open) {
                open[c][i] = p->open[6 * i + c];
                open[3 + c][i] = p->open[6 * i + 3 + c];
            }
        }
    }
    /* Block planes are interleaved RGB; the file's channels are planar. */
    float *planes = ok ? malloc((size_t)p->stack.count * 3 * n * sizeof *planes) : NULL;
    if (ok && p->stack.count && !planes) {
        log_error("%s: out of memory for a part of %zu pixels", path, n);
        ok = false;
    }
    for (int k = 0; ok && k < p->stack.count; k++)
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++)
                planes[(size_t)(3 * k + c) * n + i] = p->block[k][3 * i + c];
    int ch = 0;
    for (int c = 0; c < 3; c++) pc.ch[ch++].data = mean + (size_t)c * n;
    pc.ch[ch++].data = p->count;
    for (int k = 0; k < 3 * p->stack.count; k++) pc.ch[ch++].data = planes + (size_t)k * n;
    for (int c = 0; has_open && c < 6; c++) pc.ch[ch++].data = open[c];
    part_attrs pa;
    fill_attrs(m, &pa);
    exr_file f = {.display_width = m->width,
                  .display_height = m->height,
                  .x0 = m->x0,
                  .y0 = m->y0,
                  .width = m->x1 - m->x0,
                  .height = m->y1 - m->y0,
                  .channel_count = pc.count,
                  .channels = pc.ch,
                  .attr_count = 9,
                  .attrs = pa.a,
                  /* ZIP shrinks the float sums of a render by a third only, for 3.6 to 6 times the
                   * write (1024 x 1024 pixels, two blocks: 0.9 s at zlib's default level, 0.54 s
                   * at its fastest, 0.15 s as is). */
                  .uncompressed = true};
    const char *values[8];
    for (int k = 0; k < 8; k++) values[k] = pa.a[k].value;
    if (ok) part_checksum(&f, values, &pc, pa.a[8].value);
    ok = ok && exr_file_write(path, &f);
    free(mean);
    free(planes);
    for (int c = 0; c < 6; c++) free(open[c]);
    return ok;
}

/* Parses a decimal without sign or spaces into *out, at most max; false if it is not one. */
static bool parse_u64(const char *s, uint64_t max, uint64_t *out) {
    uint64_t v = 0;
    if (!*s) return false;
    for (; *s; s++) {
        if (*s < '0' || *s > '9' || v > (max - (uint64_t)(*s - '0')) / 10) return false;
        v = v * 10 + (uint64_t)(*s - '0');
    }
    *out = v;
    return true;
}

/* Fills m from the file's attributes and windows; false (logged) on a missing or bad one. */
static bool read_meta(const char *path, const exr_file *f, part_meta *m) {
    const char *value[9];
    for (int k = 0; k < 9; k++)
        if (!(value[k] = exr_file_attr(f, attr_names[k]))) {
            log_error("%s: not a trazador part: no '%s' attribute", path, attr_names[k]);
            return false;
        }
    *m = (part_meta){.width = f->display_width,
                     .height = f->display_height,
                     .x0 = f->x0,
                     .x1 = f->x0 + f->width,
                     .y0 = f->y0,
                     .y1 = f->y0 + f->height};
    snprintf(m->version, sizeof m->version, "%s", value[0]);
    snprintf(m->digest, sizeof m->digest, "%s", value[1]);
    snprintf(m->mode, sizeof m->mode, "%s", value[2]);
    uint64_t seed, spp, begin, end, chunk;
    char begin_text[16] = "", end_text[16] = "";
    const char *colon = strchr(value[5], ':');
    if (colon && (size_t)(colon - value[5]) < sizeof begin_text &&
        strlen(colon + 1) < sizeof end_text) {
        memcpy(begin_text, value[5], (size_t)(colon - value[5]));
        snprintf(end_text, sizeof end_text, "%s", colon + 1);
    }
    if (!parse_u64(value[3], UINT32_MAX, &seed) || !parse_u64(value[4], UINT32_MAX, &spp) ||
        !parse_u64(begin_text, UINT32_MAX, &begin) || !parse_u64(end_text, UINT32_MAX, &end) ||
        !parse_u64(value[6], UINT32_MAX, &chunk) ||
        !parse_u64(value[7], UINT64_MAX, &m->nonfinite)) {
        log_error(
            "%s: bad trazador attribute: seed '%s', spp '%s', samples '%s' (A:B), chunk "
            "'%s', nonfinite '%s'",
            path, value[3], value[4], value[5], value[6], value[7]);
        return false;
    }
    m->seed = (uint32_t)seed;
    m->spp = (uint32_t)spp;
    m->sample_begin = (uint32_t)begin;
    m->sample_end = (uint32_t)end;
    m->chunk = (uint32_t)chunk;
    return meta_valid(m, path);
}

/* The channel called name of the given type; NULL (logged) if the file lacks it. */
static const exr_channel *need_channel(const char *path, const exr_file *f, const char *name,
                                       exr_sample_type type) {
    const exr_channel *ch = exr_file_channel(f, name);
    if (!ch || ch->type != type)
        log_error("%s: not a consistent trazador part: channel '%s' is missing or of another type",
                  path, name);
    return ch && ch->type == type ? ch : NULL;
}

bool part_read(const char *path, part *out) {
    *out = (part){0};
    exr_file f;
    if (!exr_file_read(path, &f)) return false;
    part_meta m;
    bool ok = read_meta(path, &f, &m);
    uint32_t samples = ok ? m.sample_end - m.sample_begin : 0;
    bool open = ok && !chunk_aligned(&m, m.sample_end);
    ok = ok && part_init(out, &m);
    if (ok) {
        out->meta = m;
        ok = chunk_stack_of(out->stack.first,
                            open ? m.sample_end / CHUNK_SAMPLES : chunk_at(&m, m.sample_end),
                            &out->stack);
    }
    part_channels pc;
    if (ok) name_channels(out, &pc);
    size_t n = region_pixels(&m);
    const exr_channel *count = ok ? need_channel(path, &f, "count", EXR_SAMPLE_UINT) : NULL;
    ok = ok && count;
    if (ok) memcpy(out->count, count->data, n * sizeof *out->count);
    for (size_t i = 0; ok && i < n; i++)
        if (out->count[i] > samples) {
            log_error("%s: not a consistent trazador part: pixel (%d, %d) counts %" PRIu32
                      " samples of %" PRIu32,
                      path, m.x0 + (int)(i % (size_t)(m.x1 - m.x0)),
                      m.y0 + (int)(i / (size_t)(m.x1 - m.x0)), out->count[i], samples);
            ok = false;
        }
    for (int k = 0; ok && k < out->stack.count; k++) {
        ok = (out->block[k] = malloc(n * 3 * sizeof(float))) != NULL;
        if (!ok) log_error("%s: out of memory for a part of %zu pixels", path, n);
        for (int c = 0; ok && c < 3; c++) {
            const exr_channel *ch =
                need_channel(path, &f, pc.ch[4 + 3 * k + c].name, EXR_SAMPLE_FLOAT);
            ok = ch != NULL;
            for (size_t i = 0; ok && i < n; i++)
                out->block[k][3 * i + c] = ((const float *)ch->data)[i];
        }
    }
    if (ok && open && !(out->open = malloc(n * 6 * sizeof(float)))) {
        log_error("%s: out of memory for a part of %zu pixels", path, n);
        ok = false;
    }
    for (int c = 0; ok && open && c < 6; c++) {
        const exr_channel *ch =
            need_channel(path, &f, pc.ch[4 + 3 * out->stack.count + c].name, EXR_SAMPLE_FLOAT);
        ok = ch != NULL;
        for (size_t i = 0; ok && i < n; i++) out->open[6 * i + c] = ((const float *)ch->data)[i];
    }
    for (int c = 0; ok && c < 3; c++)
        ok = need_channel(path, &f, pc.ch[c].name, EXR_SAMPLE_FLOAT) != NULL;
    if (ok) {
        const char *values[8];
        char sum[17];
        for (int k = 0; k < 8; k++) values[k] = exr_file_attr(&f, attr_names[k]);
        part_checksum(&f, values, &pc, sum);
        if (strcmp(sum, exr_file_attr(&f, attr_names[8]))) {
            log_error("%s: damaged trazador part: its content does not match its checksum", path);
            ok = false;
        }
    }
    exr_file_free(&f);
    if (!ok) part_free(out);
    return ok;
}

/* What differs between two parts' renders ("" if nothing) into why. */
static void meta_difference(const part_meta *a, const part_meta *b, char *why, size_t size) {
    why[0] = '\0';
    if (strcmp(a->digest, b->digest))
        snprintf(why, size, "scene digest %s against %s", a->digest, b->digest);
    else if (a->seed != b->seed)
        snprintf(why, size, "seed %" PRIu32 " against %" PRIu32, a->seed, b->seed);
    else if (strcmp(a->mode, b->mode))
        snprintf(why, size, "mode %s against %s", a->mode, b->mode);
    else if (strcmp(a->version, b->version))
        snprintf(why, size, "trazador version %s against %s", a->version, b->version);
    else if (a->spp != b->spp)
        snprintf(why, size, "%" PRIu32 " against %" PRIu32 " samples per pixel", a->spp, b->spp);
    else if (a->width != b->width || a->height != b->height)
        snprintf(why, size, "image %dx%d against %dx%d", a->width, a->height, b->width, b->height);
    else if (a->chunk != b->chunk)
        snprintf(why, size, "chunk size %" PRIu32 " against %" PRIu32, a->chunk, b->chunk);
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

static bool grid_init(merge_grid *g, const part *parts, int n) {
    *g = (merge_grid){0};
    size_t len = 2 * (size_t)n + 2;
    g->xs = malloc(len * sizeof *g->xs);
    g->ys = malloc(len * sizeof *g->ys);
    g->ss = malloc(len * sizeof *g->ss);
    if (!g->xs || !g->ys || !g->ss) return false;
    const part_meta *m0 = &parts[0].meta;
    g->xs[0] = 0, g->xs[1] = m0->width, g->ys[0] = 0, g->ys[1] = m0->height;
    g->ss[0] = 0, g->ss[1] = m0->spp;
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
    char why[2 * PART_TEXT_MAX + 64];
    for (int i = 1; i < n; i++) {
        meta_difference(&parts[0].meta, &parts[i].meta, why, sizeof why);
        if (why[0]) {
            log_error("merge: %s and %s are parts of different renders: %s", names[0], names[i],
                      why);
            return false;
        }
    }
    for (int i = 0; i < n; i++)
        if (!chunk_aligned(&parts[i].meta, parts[i].meta.sample_end)) {
            log_error("merge: %s ends inside a chunk, at sample %" PRIu32
                      " (parts merge in whole chunks of %u samples): resume it to finish",
                      names[i], parts[i].meta.sample_end, CHUNK_SAMPLES);
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
    chunk_stack s = chunk_stack_at(0);
    float value[CHUNK_STACK_MAX][3];
    uint32_t count = 0;
    for (int h = 0; h < held; h++) {
        const part *q = &parts[order[h]];
        size_t i =
            (size_t)(y - q->meta.y0) * (size_t)(q->meta.x1 - q->meta.x0) + (size_t)(x - q->meta.x0);
        for (int k = 0; k < q->stack.count; k++) {
            int top = s.count, merges = chunk_stack_push(&s, q->stack.block[k]);
            if (merges < 0) return false;
            chunk_values_push(value, top, merges, &q->block[k][3 * i]);
        }
        count += q->count[i];
    }
    if (s.count != out->stack.count) return false;
    size_t o = (size_t)y * (size_t)out->meta.width + (size_t)x;
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

bool part_merge(const part *parts, const char *const *names, int n, part *out) {
    *out = (part){0};
    if (n < 1) {
        log_error("merge: no parts");
        return false;
    }
    if (!merge_check(parts, names, n)) return false;
    merge_grid g;
    bool ok = grid_init(&g, parts, n);
    if (!ok) log_error("merge: out of memory");
    ok = ok && merge_covers(parts, n, &g);
    part_meta m = parts[0].meta;
    m.x0 = 0, m.x1 = m.width, m.y0 = 0, m.y1 = m.height, m.sample_begin = 0, m.nonfinite = 0;
    for (int i = 0; i < n; i++) m.nonfinite += parts[i].meta.nonfinite;
    ok = ok && part_init(out, &m);
    if (ok) {
        out->meta.sample_end = m.spp;
        chunk_stack_of(0, chunk_count(m.spp), &out->stack);
        size_t pixels = region_pixels(&m);
        for (int k = 0; ok && k < out->stack.count; k++)
            ok = (out->block[k] = malloc(pixels * 3 * sizeof(float))) != NULL;
        if (!ok) log_error("merge: out of memory for a %dx%d image", m.width, m.height);
    }
    ok = ok && merge_sums(parts, n, &g, out);
    grid_free(&g);
    if (!ok) part_free(out);
    return ok;
}

bool part_merge_files(const char *const *paths, int n, part *out) {
    *out = (part){0};
    part *parts = calloc(n > 0 ? (size_t)n : 1, sizeof *parts);
    if (!parts) {
        log_error("merge: out of memory for %d parts", n);
        return false;
    }
    bool ok = true;
    for (int i = 0; ok && i < n; i++) ok = part_read(paths[i], &parts[i]);
    ok = ok && part_merge(parts, paths, n, out);
    for (int i = 0; i < n; i++) part_free(&parts[i]);
    free(parts);
    return ok;
}
