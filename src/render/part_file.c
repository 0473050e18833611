/* part_file.c: a render part as an EXR file (image/exr.h): the mean, the count and the stack's
 * blocks as channels, the render's description and a checksum as attributes. */
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image/exr.h"
#include "render/part_internal.h"
#include "util/big_memory.h"
#include "util/log.h"

/* The file's channels: R G B mean, count, each block's RGB, the open chunk's sums, the feature
 * images. */
typedef struct part_channels {
    int count;
    exr_channel ch[4 + 3 * CHUNK_STACK_MAX + 6 + 3 * AOV_COUNT + 4];
} part_channels;

/* The channels of a noise threshold's state (part.adaptive), in its order. */
static const char *const adaptive_names[4] = {"adaptive.R", "adaptive.G", "adaptive.B",
                                              "adaptive.stop"};

/* Adds the channels of the feature images of mask. */
static void name_aov_channels(uint32_t mask, part_channels *pc) {
    for (int k = 0; k < AOV_COUNT; k++)
        for (int c = 0; (mask & 1u << k) && c < aov_channels((aov_kind)k); c++) {
            exr_channel *ch = &pc->ch[pc->count++];
            *ch = (exr_channel){.type = EXR_SAMPLE_FLOAT};
            aov_channel_name((aov_kind)k, c, ch->name, sizeof ch->name);
        }
}

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
    if (!chunk_aligned(&p->meta, p->meta.sample_end)) {
        for (int c = 0; c < 3; c++) add_channel(pc, EXR_SAMPLE_FLOAT, "open.sum", rgb[c]);
        for (int c = 0; c < 3; c++) add_channel(pc, EXR_SAMPLE_FLOAT, "open.comp", rgb[c]);
    }
    name_aov_channels(p->aov.mask, pc);
    for (int c = 0; p->meta.adaptive && c < 4; c++)
        add_channel(pc, EXR_SAMPLE_FLOAT, adaptive_names[c], 0);
}

/* The feature images a part file has: those of which it has a first channel. */
static uint32_t aov_mask_of(const exr_file *f) {
    uint32_t mask = 0;
    for (int k = 0; k < AOV_COUNT; k++) {
        char name[EXR_NAME_MAX + 1];
        aov_channel_name((aov_kind)k, 0, name, sizeof name);
        if (exr_file_channel(f, name)) mask |= 1u << k;
    }
    return mask;
}

/* The file's string attributes, the checksum last. */
#define ATTRS 10
#define CHECKSUM (ATTRS - 1)
typedef struct part_attrs {
    exr_attr a[ATTRS];
} part_attrs;

/* The last, trazador.checksum, covers the others, the windows and every channel. */
static const char *const attr_names[ATTRS] = {
    "trazador.version", "trazador.digest",  "trazador.mode",  "trazador.seed",
    "trazador.spp",     "trazador.samples", "trazador.chunk", "trazador.nonfinite",
    "trazador.backend", "trazador.checksum"};

static void fill_attrs(const part_meta *m, part_attrs *pa) {
    for (int k = 0; k < ATTRS; k++)
        snprintf(pa->a[k].name, sizeof pa->a[k].name, "%s", attr_names[k]);
    snprintf(pa->a[0].value, sizeof pa->a[0].value, "%s", m->version);
    snprintf(pa->a[1].value, sizeof pa->a[1].value, "%s", m->digest);
    snprintf(pa->a[2].value, sizeof pa->a[2].value, "%s", m->mode);
    snprintf(pa->a[3].value, sizeof pa->a[3].value, "%" PRIu32, m->seed);
    snprintf(pa->a[4].value, sizeof pa->a[4].value, "%" PRIu32, m->spp);
    snprintf(pa->a[5].value, sizeof pa->a[5].value, "%" PRIu32 ":%" PRIu32, m->sample_begin,
             m->sample_end);
    snprintf(pa->a[6].value, sizeof pa->a[6].value, "%" PRIu32, m->chunk);
    snprintf(pa->a[7].value, sizeof pa->a[7].value, "%" PRIu64, m->nonfinite);
    snprintf(pa->a[8].value, sizeof pa->a[8].value, "%s", m->backend);
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
    for (int k = 0; k < CHECKSUM; k++) hash_bytes(h, attrs[k], strlen(attrs[k]) + 1);
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
    float *mean = big_malloc(n * 3 * sizeof *mean);
    float *open[6] = {NULL};
    bool has_open = p->open && !chunk_aligned(m, m->sample_end), ok = mean != NULL;
    for (int c = 0; ok && has_open && c < 6; c++)
        ok = (open[c] = big_malloc(n * sizeof(float))) != NULL;
    if (!ok) log_error("%s: out of memory for a part of %zu pixels", path, n);
    for (size_t i = 0; ok && i < n; i++) {
        float total[3];
        part_pixel_total(p, i, total);
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
    float *planes = ok ? big_malloc((size_t)p->stack.count * 3 * n * sizeof *planes) : NULL;
    if (ok && p->stack.count && !planes) {
        log_error("%s: out of memory for a part of %zu pixels", path, n);
        ok = false;
    }
    for (int k = 0; ok && k < p->stack.count; k++)
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++)
                planes[(size_t)(3 * k + c) * n + i] = p->block[k][3 * i + c];
    float *aov_planes = NULL; /* the feature images' channels, planar */
    int aov_count =
        pc.count - (4 + 3 * p->stack.count + (has_open ? 6 : 0) + (m->adaptive ? 4 : 0));
    if (ok && aov_count + 4 > 0 &&
        !(aov_planes = big_malloc((size_t)(aov_count + 4) * n * sizeof(float)))) {
        log_error("%s: out of memory for a part of %zu pixels", path, n);
        ok = false;
    }
    for (int k = 0, a = 0; ok && k < AOV_COUNT; k++) {
        int w = aov_channels((aov_kind)k);
        for (int c = 0; p->aov.plane[k] && c < w; c++, a++)
            for (size_t i = 0; i < n; i++)
                aov_planes[(size_t)a * n + i] = p->aov.plane[k][(size_t)w * i + (size_t)c];
    }
    int ch = 0;
    for (int c = 0; c < 3; c++) pc.ch[ch++].data = mean + (size_t)c * n;
    pc.ch[ch++].data = p->count;
    for (int k = 0; k < 3 * p->stack.count; k++) pc.ch[ch++].data = planes + (size_t)k * n;
    for (int c = 0; has_open && c < 6; c++) pc.ch[ch++].data = open[c];
    for (int a = 0; a < aov_count; a++) pc.ch[ch++].data = aov_planes + (size_t)a * n;
    for (int c = 0; ok && m->adaptive && c < 4; c++) {
        float *plane = aov_planes + (size_t)(aov_count + c) * n;
        for (size_t i = 0; i < n; i++) plane[i] = p->adaptive[4 * i + (size_t)c];
        pc.ch[ch++].data = plane;
    }
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
                  .attr_count = ATTRS,
                  .attrs = pa.a,
                  /* ZIP shrinks the float sums of a render by a third only, for several times
                   * the write (docs/PERF.md, "Split renders"). */
                  .uncompressed = true};
    const char *values[CHECKSUM];
    for (int k = 0; k < CHECKSUM; k++) values[k] = pa.a[k].value;
    if (ok) part_checksum(&f, values, &pc, pa.a[CHECKSUM].value);
    ok = ok && exr_file_write(path, &f);
    free(mean);
    free(planes);
    free(aov_planes);
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
    const char *value[ATTRS];
    for (int k = 0; k < ATTRS; k++)
        if (!(value[k] = exr_file_attr(f, attr_names[k]))) {
            /* Parts before the back end was recorded: their samples cannot be told apart. */
            if (k == 8 && value[0])
                log_error(
                    "%s: a part of trazador %s that does not say its back end (CPU or "
                    "Vulkan, which differ by rounding): render it again",
                    path, value[0]);
            else
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
    /* "seed" is what parts of report mode were written with before the mode's rename. */
    snprintf(m->mode, sizeof m->mode, "%s", strcmp(value[2], "seed") ? value[2] : "report");
    snprintf(m->backend, sizeof m->backend, "%s", value[8]);
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
    return part_meta_valid(m, path);
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
    m.adaptive = exr_file_channel(&f, adaptive_names[3]) != NULL;
    ok = ok && part_init(out, &m);
    if (ok) {
        out->meta = m;
        ok = chunk_stack_of(out->stack.first,
                            open ? m.sample_end / TZ_CHUNK_SAMPLES : chunk_at(&m, m.sample_end),
                            &out->stack);
    }
    size_t n = region_pixels(&m);
    uint32_t aov_mask = ok ? aov_mask_of(&f) : 0;
    if (aov_mask && m.sample_begin != 0) {
        log_error(
            "%s: not a consistent trazador part: feature images in a part of samples from %" PRIu32,
            path, m.sample_begin);
        ok = false;
    }
    ok = ok && (!aov_mask || aov_alloc(&out->aov, aov_mask, n));
    part_channels pc;
    if (ok) name_channels(out, &pc);
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
        ok = (out->block[k] = big_malloc(n * 3 * sizeof(float))) != NULL;
        if (!ok) log_error("%s: out of memory for a part of %zu pixels", path, n);
        for (int c = 0; ok && c < 3; c++) {
            const exr_channel *ch =
                need_channel(path, &f, pc.ch[4 + 3 * k + c].name, EXR_SAMPLE_FLOAT);
            ok = ch != NULL;
            for (size_t i = 0; ok && i < n; i++)
                out->block[k][3 * i + c] = ((const float *)ch->data)[i];
        }
    }
    if (ok && open && !(out->open = big_malloc(n * 6 * sizeof(float)))) {
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
    int a = pc.count;
    for (int c = 3; ok && m.adaptive && c >= 0; c--) {
        const exr_channel *ch = need_channel(path, &f, pc.ch[--a].name, EXR_SAMPLE_FLOAT);
        ok = ch != NULL;
        for (size_t i = 0; ok && i < n; i++)
            out->adaptive[4 * i + (size_t)c] = ((const float *)ch->data)[i];
    }
    /* a stop is a chunk the part has passed, so that the renderer may take it as a whole number */
    float last_stop = (float)out->stack.end;
    for (size_t i = 0; ok && m.adaptive && i < n; i++) {
        float stop = out->adaptive[4 * i + 3];
        if (stop == 0.0f || (stop >= 1.0f && stop <= last_stop && stop == floorf(stop))) continue;
        log_error("%s: not a consistent trazador part: pixel (%d, %d) stopped at chunk %g", path,
                  m.x0 + (int)(i % (size_t)(m.x1 - m.x0)), m.y0 + (int)(i / (size_t)(m.x1 - m.x0)),
                  (double)stop);
        ok = false;
    }
    for (int k = AOV_COUNT - 1; ok && k >= 0; k--) {
        int w = aov_channels((aov_kind)k);
        for (int c = w - 1; out->aov.plane[k] && ok && c >= 0; c--) {
            const exr_channel *ch = need_channel(path, &f, pc.ch[--a].name, EXR_SAMPLE_FLOAT);
            ok = ch != NULL;
            for (size_t i = 0; ok && i < n; i++)
                out->aov.plane[k][(size_t)w * i + (size_t)c] = ((const float *)ch->data)[i];
        }
    }
    if (ok) {
        const char *values[CHECKSUM];
        char sum[17];
        for (int k = 0; k < CHECKSUM; k++) values[k] = exr_file_attr(&f, attr_names[k]);
        part_checksum(&f, values, &pc, sum);
        if (strcmp(sum, exr_file_attr(&f, attr_names[CHECKSUM]))) {
            log_error("%s: damaged trazador part: its content does not match its checksum", path);
            ok = false;
        }
    }
    exr_file_free(&f);
    if (!ok) part_free(out);
    return ok;
}
