/* test_part.c: src/render/part*.c and chunk_tree.h on synthetic films: the chunk tree's total is
 * the fixed binary tree over chunks; parts split by regions, by chunk-aligned sample ranges and
 * both, written as EXR, read back and merged, give the whole render's film bit for bit; and every
 * refusal (other render, overlap, gaps, a part ending mid-chunk, a foreign or bad file). The
 * scene digest of the metadata: test_digest.c. */
#define _GNU_SOURCE /* memmem */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "common/film_sum.h"
#include "image/exr.h"
#include "render/part.h"
#include "tmp_dir.h"
#include "util/log.h"

enum { W = 13, H = 11, SPP = 170 }; /* 11 chunks, the last of 10 samples */

static uint32_t hash(uint32_t v) {
    v = v * 747796405u + 2891336453u;
    v = ((v >> ((v >> 28u) + 4u)) ^ v) * 277803737u;
    return (v >> 22u) ^ v;
}

/* Sample s of pixel (x, y), channel c: values over many magnitudes, so that the order of the
 * additions shows in the sums; now and then NaN or infinite, to be dropped. */
static float sample(int x, int y, uint32_t s, int c) {
    uint32_t h = hash(hash(hash((uint32_t)(y * W + x)) ^ s) ^ (uint32_t)c);
    if (c == 0 && h % 97 == 0) return h % 2 ? NAN : INFINITY;
    return ldexpf((float)(h >> 8) * 0x1p-24f, (int)(h % 24) - 8);
}

static bool pixel_sample_finite(int x, int y, uint32_t s) {
    return isfinite(sample(x, y, s, 0)) && isfinite(sample(x, y, s, 1)) &&
           isfinite(sample(x, y, s, 2));
}

/* Chunk k of pixel (x, y): its compensated sum and finite count. */
static uint32_t chunk_value(int x, int y, uint32_t k, float out[3]) {
    vec3 sum = v3(0.0f, 0.0f, 0.0f), comp = sum;
    uint32_t count = 0, end = (k + 1) * TZ_CHUNK_SAMPLES < SPP ? (k + 1) * TZ_CHUNK_SAMPLES : SPP;
    for (uint32_t s = k * TZ_CHUNK_SAMPLES; s < end; s++) {
        if (!pixel_sample_finite(x, y, s)) continue;
        film_sum_add(&sum, &comp, v3(sample(x, y, s, 0), sample(x, y, s, 1), sample(x, y, s, 2)));
        count++;
    }
    vec3 value = film_sum_value(sum, comp);
    out[0] = value.x, out[1] = value.y, out[2] = value.z;
    return count;
}

static part_meta base_meta(void) {
    part_meta m = {.seed = 7, .spp = SPP, .chunk = TZ_CHUNK_SAMPLES, .width = W, .height = H};
    snprintf(m.digest, sizeof m.digest, "%s", "d1g3st");
    snprintf(m.mode, sizeof m.mode, "%s", "report");
    snprintf(m.version, sizeof m.version, "%s", TRAZADOR_VERSION);
    return m;
}

/* Renders region x0,x1,y0,y1 over samples begin to end - 1 as the renderer will: chunk by chunk.
 */
static bool render_part(int x0, int x1, int y0, int y1, uint32_t begin, uint32_t end, part *p) {
    part_meta m = base_meta();
    m.x0 = x0, m.x1 = x1, m.y0 = y0, m.y1 = y1, m.sample_begin = begin;
    if (!part_init(p, &m)) return false;
    size_t n = (size_t)(x1 - x0) * (size_t)(y1 - y0);
    float *rgb = malloc(n * 3 * sizeof *rgb);
    uint32_t *count = malloc(n * sizeof *count);
    bool ok = rgb && count;
    while (ok && p->meta.sample_end < end) {
        uint32_t k = p->meta.sample_end / TZ_CHUNK_SAMPLES;
        for (int y = y0; y < y1; y++)
            for (int x = x0; x < x1; x++) {
                size_t i = (size_t)(y - y0) * (size_t)(x1 - x0) + (size_t)(x - x0);
                count[i] = chunk_value(x, y, k, &rgb[3 * i]);
                uint32_t end_k =
                    (k + 1) * TZ_CHUNK_SAMPLES < SPP ? (k + 1) * TZ_CHUNK_SAMPLES : SPP;
                p->meta.nonfinite += end_k - k * TZ_CHUNK_SAMPLES - count[i];
            }
        ok = part_push_chunk(p, rgb, count);
    }
    free(rgb);
    free(count);
    return ok;
}

/* The binary tree over chunks first to end - 1 as DESIGN.md states it: a node's value is its left
 * half plus its right half, a node with no right half is its left half. */
static void tree_sum(int x, int y, uint32_t first, uint32_t size, uint32_t chunks, float out[3]) {
    if (size == 1) {
        chunk_value(x, y, first, out);
        return;
    }
    tree_sum(x, y, first, size / 2, chunks, out);
    if (first + size / 2 >= chunks) return;
    float right[3];
    tree_sum(x, y, first + size / 2, size / 2, chunks, right);
    for (int c = 0; c < 3; c++) out[c] = out[c] + right[c];
}

static film whole_film;

/* The whole render: its film equals the tree of DESIGN.md, pixel for pixel, and differs from
 * chunks added in order (so the splits below would catch a wrong order). */
static void test_whole_render(void) {
    part whole;
    EXPECT(render_part(0, W, 0, H, 0, SPP, &whole));
    EXPECT(whole.stack.count == 3); /* 11 chunks: blocks 0-8, 8-10 and 10-11 */
    EXPECT(part_film(&whole, &whole_film));
    uint32_t chunks = (SPP + TZ_CHUNK_SAMPLES - 1) / TZ_CHUNK_SAMPLES;
    int off_tree = 0, off_sequence = 0, dropped = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            float tree[3], seq[3] = {0}, v[3];
            tree_sum(x, y, 0, 16, chunks, tree);
            uint32_t count = 0;
            for (uint32_t k = 0; k < chunks; k++) {
                count += chunk_value(x, y, k, v);
                for (int c = 0; c < 3; c++) seq[c] += v[c];
            }
            const float *a = &whole_film.accum[4 * (y * W + x)];
            if (memcmp(a, tree, sizeof tree) || a[3] != (float)count) off_tree++;
            if (memcmp(a, seq, sizeof seq)) off_sequence++;
            dropped += SPP - (int)count;
        }
    CHECK(off_tree == 0, "%d pixels differ from the chunk tree", off_tree);
    CHECK(off_sequence > 0, "no pixel depends on the order of the chunks: a weak test");
    CHECK(dropped > 0 && whole_film.nonfinite == (uint64_t)dropped, "nonfinite %llu of %d",
          (unsigned long long)whole_film.nonfinite, dropped);
    part_free(&whole);
}

typedef struct piece {
    int x0, x1, y0, y1;
    uint32_t begin, end;
} piece;

/* Renders the pieces, writes each, and merges the files in the order given. */
static bool merge_pieces(const piece *pieces, int n, part *merged) {
    char(*names)[64] = calloc((size_t)n, sizeof *names);
    const char **paths = calloc((size_t)n, sizeof *paths);
    bool ok = names && paths;
    for (int i = 0; ok && i < n; i++) {
        char name[32];
        snprintf(name, sizeof name, "piece%d.exr", i);
        snprintf(names[i], sizeof names[i], "%s", tmp_path(name));
        paths[i] = names[i];
        part p;
        const piece *q = &pieces[i];
        ok = render_part(q->x0, q->x1, q->y0, q->y1, q->begin, q->end, &p) &&
             part_write(names[i], &p);
        part_free(&p);
    }
    ok = ok && part_merge_files(paths, n, true, merged);
    for (int i = 0; names && i < n; i++) unlink(names[i]);
    free(names);
    free(paths);
    return ok;
}

/* The merged film equals the whole render's, bit for bit. */
static void check_split(const char *what, const piece *pieces, int n) {
    part merged;
    bool ok = merge_pieces(pieces, n, &merged);
    CHECK(ok, "%s: merge failed", what);
    film f = {0};
    ok = ok && part_film(&merged, &f);
    CHECK(ok && !memcmp(f.accum, whole_film.accum, sizeof(float) * 4 * W * H) &&
              f.nonfinite == whole_film.nonfinite,
          "%s: merged film differs from the whole render", what);
    film_free(&f);
    part_free(&merged);
}

static void test_splits(void) {
    piece regions[] = {{0, 5, 0, 11, 0, SPP},
                       {5, 13, 0, 4, 0, SPP},
                       {5, 9, 4, 11, 0, SPP},
                       {9, 13, 4, 11, 0, SPP}};
    check_split("regions", regions, 4);
    piece ranges[] = {{0, W, 0, H, 80, SPP}, {0, W, 0, H, 0, 16}, {0, W, 0, H, 16, 80}};
    check_split("sample ranges", ranges, 3);
    piece odd[] = {
        {0, W, 0, H, 48, 112}, {0, W, 0, H, 0, 48}, {0, W, 0, H, 112, 144}, {0, W, 0, H, 144, SPP}};
    check_split("sample ranges across tree blocks", odd, 4);
    /* Regions cut one way for the first samples and another way for the rest, with an empty
     * range thrown in. */
    piece mixed[] = {{0, W, 0, 6, 0, 32},  {0, W, 6, H, 0, 32},   {0, 7, 0, H, 32, SPP},
                     {7, W, 0, H, 32, 96}, {7, W, 0, H, 96, SPP}, {0, 3, 0, 3, 32, 32}};
    check_split("regions and sample ranges", mixed, 6);
    piece single[11];
    for (int k = 0; k < 11; k++) {
        uint32_t c = (uint32_t)(k * 7 % 11); /* every chunk alone, shuffled */
        single[k] = (piece){0,
                            W,
                            0,
                            H,
                            c * TZ_CHUNK_SAMPLES,
                            (c + 1) * TZ_CHUNK_SAMPLES < SPP ? (c + 1) * TZ_CHUNK_SAMPLES : SPP};
    }
    check_split("single chunks", single, 11);
}

/* A merged part written and read back is the same part; an open chunk round-trips. */
static void test_part_files(void) {
    part p, q;
    EXPECT(render_part(2, 9, 3, 8, 32, 96, &p));
    p.meta.sample_end = 100; /* a checkpoint 4 samples into chunk 6 */
    p.open = malloc(sizeof(float) * 6 * 7 * 5);
    for (int i = 0; i < 6 * 7 * 5; i++) p.open[i] = sample(i, 0, 1, 1);
    const char *path = tmp_path("open.exr");
    EXPECT(part_write(path, &p) && part_read(path, &q));
    EXPECT(q.meta.sample_begin == 32 && q.meta.sample_end == 100 && q.meta.x0 == 2 &&
           q.meta.x1 == 9 && q.meta.y0 == 3 && q.meta.y1 == 8 && q.meta.seed == 7 &&
           q.meta.nonfinite == p.meta.nonfinite && !strcmp(q.meta.digest, "d1g3st"));
    EXPECT(q.stack.count == p.stack.count && q.open &&
           !memcmp(q.open, p.open, sizeof(float) * 6 * 7 * 5) &&
           !memcmp(q.count, p.count, sizeof(uint32_t) * 7 * 5));
    for (int k = 0; k < p.stack.count && k < q.stack.count; k++)
        EXPECT(!memcmp(q.block[k], p.block[k], sizeof(float) * 3 * 7 * 5));
    /* A part of report mode written before its rename says "seed": read as "report". */
    part old;
    snprintf(p.meta.mode, sizeof p.meta.mode, "%s", "seed");
    EXPECT(part_write(path, &p) && part_read(path, &old));
    EXPECT(!strcmp(old.meta.mode, "report") && !strcmp(q.meta.mode, "report"));
    part_free(&old);
    snprintf(p.meta.mode, sizeof p.meta.mode, "%s", "report");
    EXPECT(part_write(path, &p));
    /* The file is a viewable image of the region's mean inside the whole image. */
    exr_file f;
    EXPECT(exr_file_read(path, &f));
    EXPECT(f.display_width == W && f.display_height == H && f.x0 == 2 && f.y0 == 3 &&
           exr_file_channel(&f, "R") && exr_file_channel(&f, "sum.2-4.G") &&
           exr_file_channel(&f, "sum.4-6.B") && exr_file_channel(&f, "open.comp.R") &&
           !strcmp(exr_file_attr(&f, "trazador.samples"), "32:100"));
    exr_file_free(&f);
    /* It cannot be merged: it ends inside a chunk. */
    log_hold_errors();
    part merged;
    const char *name = "open.exr";
    EXPECT(!part_merge(&q, &name, 1, &merged));
    EXPECT(strstr(log_release_errors(), "open.exr ends inside a chunk"));
    part_free(&p);
    part_free(&q);
    unlink(path);
}

/* Merges two pieces after changing the second's metadata with edit; returns the errors. */
static const char *refusal(const piece *pieces, int n, void (*edit)(part_meta *)) {
    part *parts = calloc((size_t)n, sizeof *parts);
    static const char *names[] = {"a.exr", "b.exr", "c.exr", "d.exr"};
    for (int i = 0; i < n; i++)
        render_part(pieces[i].x0, pieces[i].x1, pieces[i].y0, pieces[i].y1, pieces[i].begin,
                    pieces[i].end, &parts[i]);
    if (edit) edit(&parts[n - 1].meta);
    part merged;
    log_hold_errors();
    bool ok = part_merge(parts, names, n, &merged);
    const char *held = log_release_errors();
    EXPECT(!ok);
    for (int i = 0; i < n; i++) part_free(&parts[i]);
    free(parts);
    return held;
}

static void other_seed(part_meta *m) { m->seed = 8; }
static void other_digest(part_meta *m) { m->digest[0] = 'X'; }
static void other_mode(part_meta *m) { snprintf(m->mode, sizeof m->mode, "path"); }
static void other_version(part_meta *m) { snprintf(m->version, sizeof m->version, "0.0.9"); }
/* As a real render of another seed: the digest covers the seed, and the seed is named. */
static void other_seed_digest(part_meta *m) {
    m->seed = 8;
    m->digest[0] = 'X';
}
static void other_spp_digest(part_meta *m) {
    m->spp = 180;
    m->digest[0] = 'X';
}

static void test_refusals(void) {
    piece two[] = {{0, W, 0, H, 0, 64}, {0, W, 0, H, 64, SPP}};
    const char *why = refusal(two, 2, other_seed);
    CHECK(strstr(why, "a.exr and b.exr") && strstr(why, "seed 7 against 8"), "%s", why);
    why = refusal(two, 2, other_digest);
    CHECK(strstr(why, "a.exr and b.exr") && strstr(why, "scene digest d1g3st against X1g3st"), "%s",
          why);
    why = refusal(two, 2, other_mode);
    CHECK(strstr(why, "mode report against path"), "%s", why);
    why = refusal(two, 2, other_seed_digest);
    CHECK(strstr(why, "seed 7 against 8"), "%s", why);
    why = refusal(two, 2, other_spp_digest);
    CHECK(strstr(why, "170 against 180 samples per pixel"), "%s", why);
    why = refusal(two, 2, other_version);
    CHECK(strstr(why, "version " TRAZADOR_VERSION " against 0.0.9"), "%s", why);
    piece overlap[] = {{0, W, 0, H, 0, 64}, {0, 4, 2, 5, 48, SPP}, {0, W, 0, H, 64, SPP}};
    why = refusal(overlap, 3, NULL);
    CHECK(strstr(why, "a.exr and b.exr both hold samples 48:64 of region 0,4,2,5"), "%s", why);
    piece gaps[] = {{0, W, 0, H, 0, 32}, {0, 8, 0, H, 32, SPP}, {8, W, 5, H, 48, SPP}};
    why = refusal(gaps, 3, NULL);
    CHECK(strstr(why, "region 8,13,0,11 samples 32:48") &&
              strstr(why, "region 8,13,0,5 samples 48:170"),
          "%s", why);
    piece no_end[] = {{0, W, 0, H, 0, 128}};
    why = refusal(no_end, 1, NULL);
    CHECK(strstr(why, "region 0,13,0,11 samples 128:170"), "%s", why);
}

/* A merge of files stops at the first that is not a part. */
static void test_merge_files(void) {
    const char *paths[] = {tmp_path("missing.exr")};
    part merged;
    log_hold_errors();
    EXPECT(!part_merge_files(paths, 1, true, &merged));
    EXPECT(strstr(log_release_errors(), "missing.exr: No such file"));
}

/* Files that are not parts, or not consistent ones, or damaged, are refused with the file named.
 */
static void test_bad_files(void) {
    image img;
    EXPECT(image_init(&img, 4, 3));
    const char *path = tmp_path("plain.exr");
    EXPECT(exr_write_image(path, &img, true));
    image_free(&img);
    part p;
    log_hold_errors();
    EXPECT(!part_read(path, &p));
    const char *held = log_release_errors();
    CHECK(strstr(held, "plain.exr: not a trazador part: no 'trazador.version'"), "%s", held);
    /* A part with a damaged attribute, and one whose count passes its samples. */
    part q;
    EXPECT(render_part(0, 3, 0, 2, 16, 48, &q));
    q.count[1] = 33;
    EXPECT(part_write(path, &q));
    log_hold_errors();
    EXPECT(!part_read(path, &p));
    held = log_release_errors();
    CHECK(strstr(held, "pixel (1, 0) counts 33 samples of 32"), "%s", held);
    part_free(&q);
    /* A part that does not say its back end (written before trazador.backend): refused so. */
    EXPECT(render_part(0, 3, 0, 2, 16, 48, &q));
    EXPECT(part_write(path, &q));
    part_free(&q);
    size_t old_len = 0;
    unsigned char *old = tmp_file_read(path, &old_len);
    unsigned char *name = old ? memmem(old, old_len, "trazador.backend", 16) : NULL;
    EXPECT(name != NULL);
    if (name) name[15] = 'X'; /* another attribute of the same size */
    if (old) tmp_file_write(path, old, old_len);
    free(old);
    log_hold_errors();
    EXPECT(!part_read(path, &p));
    held = log_release_errors();
    CHECK(strstr(held, "that does not say its back end (CPU or Vulkan, which differ by rounding)"),
          "%s", held);
    /* An attribute edited in place, and bytes flipped anywhere: refused, or read unchanged. */
    EXPECT(render_part(0, 5, 0, 4, 32, 96, &q));
    EXPECT(part_write(path, &q));
    size_t len = 0;
    unsigned char *bytes = tmp_file_read(path, &len);
    unsigned char *at = bytes ? memmem(bytes, len, "d1g3st", 6) : NULL;
    EXPECT(at != NULL);
    if (at) at[5] = 'u';
    tmp_file_write(path, bytes, len);
    log_hold_errors();
    EXPECT(!part_read(path, &p));
    held = log_release_errors();
    CHECK(strstr(held, "plain.exr: damaged trazador part: its content does not match its checksum"),
          "%s", held);
    if (at) at[5] = 't';
    int changed = 0;
    uint32_t rng = 1;
    for (int k = 0; bytes && k < 300; k++) {
        rng = hash(rng);
        size_t where = rng % len;
        unsigned char was = bytes[where];
        bytes[where] ^= (unsigned char)(1u << (rng >> 29));
        tmp_file_write(path, bytes, len);
        bytes[where] = was;
        log_hold_errors();
        bool ok = part_read(path, &p);
        log_release_errors();
        if (!ok) continue;
        if (p.stack.count != q.stack.count || memcmp(p.count, q.count, 20 * sizeof *p.count) ||
            memcmp(&p.meta, &q.meta, sizeof p.meta))
            changed++;
        for (int b = 0; b < p.stack.count && b < q.stack.count; b++)
            if (memcmp(p.block[b], q.block[b], 20 * 3 * sizeof(float))) changed++;
        part_free(&p);
    }
    CHECK(changed == 0, "%d damaged files read with other content", changed);
    free(bytes);
    part_free(&q);
    part_meta m = base_meta();
    m.x0 = 0, m.x1 = W, m.y0 = 0, m.y1 = H, m.sample_begin = 8;
    log_hold_errors();
    EXPECT(!part_init(&q, &m));
    held = log_release_errors();
    CHECK(strstr(held, "does not begin at a chunk"), "%s", held);
    m.sample_begin = 0, m.spp = SCENE_MAX_SAMPLES + 1;
    log_hold_errors();
    EXPECT(!part_init(&q, &m));
    held = log_release_errors();
    CHECK(strstr(held, "samples per pixel outside 1..1048576"), "%s", held);
    unlink(path);
}

/* 1,048,576 samples of 0.9 through the chunk tree keep the mean (a plain float sum gives 0.891).
 */
static void test_long_sum(void) {
    part_meta m = base_meta();
    m.width = m.height = 1, m.x0 = 0, m.x1 = 1, m.y0 = 0, m.y1 = 1, m.spp = 1u << 20;
    part p;
    EXPECT(part_init(&p, &m));
    vec3 sum = v3(0.0f, 0.0f, 0.0f), comp = sum;
    for (uint32_t s = 0; s < TZ_CHUNK_SAMPLES; s++) film_sum_add(&sum, &comp, v3(0.9f, 0.9f, 0.9f));
    vec3 value = film_sum_value(sum, comp);
    float chunk[3] = {value.x, value.y, value.z};
    uint32_t count = TZ_CHUNK_SAMPLES;
    bool pushed = true;
    while (pushed && p.meta.sample_end < m.spp) pushed = part_push_chunk(&p, chunk, &count);
    EXPECT(pushed);
    film f;
    EXPECT(part_film(&p, &f));
    double mean = f.accum[0] / f.accum[3];
    CHECK(fabs(mean - 0.9) < 2e-7 && f.accum[3] == (float)(1u << 20), "mean %.9g", mean);
    film_free(&f);
    part_free(&p);
}

int main(void) {
    if (!tmp_dir_make("test_part")) return 1;
    CHECK_CASE(test_whole_render);
    CHECK_CASE(test_splits);
    CHECK_CASE(test_part_files);
    CHECK_CASE(test_refusals);
    CHECK_CASE(test_merge_files);
    CHECK_CASE(test_bad_files);
    CHECK_CASE(test_long_sum);
    film_free(&whole_film);
    rmdir(tmpdir);
    return check_summary("test_part");
}
