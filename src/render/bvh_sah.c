/* bvh_sah.c: where the surface area heuristic splits a node: its items binned on three axes
 * (on all threads for the nodes above the tasks: each bins a slice, the bins are merged), then
 * the cheapest split between bins, with the children's boxes. */
#include <stdlib.h>

#include "render/bvh_builder.h"
#include "util/threads.h"

/* Below this many spheres per thread, sharing one node's binning costs more than it saves. */
#define MIN_SHARED_ITEMS 16384

/* The bins of one node on the three axes. Bit k of used[a] says bin k of axis a holds a sphere;
 * only then are its box and count set, so small nodes clear and sweep no empty bins. */
typedef struct bins {
    box bounds[3][BIN_COUNT];
    uint32_t counts[3][BIN_COUNT];
    uint32_t used[3];
} bins;
_Static_assert(BIN_COUNT <= 32, "bins.used has a bit per bin");

/* bin_of on the three axes at once. */
static void bins_of(const float c[4], const binning *g, int bin[4]) {
#ifdef __SSE2__
    __m128i v = _mm_cvttps_epi32(
        _mm_mul_ps(_mm_sub_ps(_mm_loadu_ps(c), _mm_loadu_ps(g->lo)), _mm_loadu_ps(g->scale)));
    v = _mm_andnot_si128(_mm_cmplt_epi32(v, _mm_setzero_si128()), v);
    __m128i last = _mm_set1_epi32(BIN_COUNT - 1), over = _mm_cmpgt_epi32(v, last);
    v = _mm_or_si128(_mm_and_si128(over, last), _mm_andnot_si128(over, v));
    _mm_storeu_si128((__m128i *)bin, v);
#else
    for (int a = 0; a < 4; a++) bin[a] = bin_of(c[a], g->lo[a], g->scale[a]);
#endif
}

/* Bins items [begin, end) into *out. Only the masks of used bins are cleared up front: a bin's
 * box and count are set by its first item, since deep in the tree most bins stay empty. */
static void bin_items(const item *items, uint32_t begin, uint32_t end, const binning *g,
                      bins *out) {
    out->used[0] = out->used[1] = out->used[2] = 0;
    for (uint32_t k = begin; k < end; k++) {
        const item *it = &items[k];
        int bins[4];
        bins_of(it->centroid, g, bins);
        box ib = item_box(it);
        for (int a = 0; a < 3; a++) {
            if (!g->binned[a]) continue;
            int bin = bins[a];
            uint32_t bit = 1u << bin;
            if (out->used[a] & bit) {
                out->counts[a][bin]++;
                box_grow(&out->bounds[a][bin], &ib);
            } else {
                out->used[a] |= bit;
                out->counts[a][bin] = 1;
                out->bounds[a][bin] = ib;
            }
        }
    }
}

/* Adds the bins of o to b. */
static void bins_merge(bins *b, const bins *o) {
    for (int a = 0; a < 3; a++) {
        for (uint32_t rest = o->used[a]; rest; rest &= rest - 1) {
            int k = __builtin_ctz(rest);
            if (b->used[a] & 1u << k) {
                box_grow(&b->bounds[a][k], &o->bounds[a][k]);
                b->counts[a][k] += o->counts[a][k];
            } else {
                b->bounds[a][k] = o->bounds[a][k];
                b->counts[a][k] = o->counts[a][k];
            }
        }
        b->used[a] |= o->used[a];
    }
}

/* The cheapest SAH split between non-empty bins (splits at empty ones cost what the split
 * before them does), with the children's boxes; cost INFINITY when there is none. */
static split sah_sweep(const bins *bn, const binning *g) {
    split s = {.cost = INFINITY};
    for (int a = 0; a < 3; a++) {
        if (!g->binned[a]) continue;
        int used[BIN_COUNT], m = 0;
        for (uint32_t rest = bn->used[a]; rest; rest &= rest - 1) used[m++] = __builtin_ctz(rest);
        float right_area[BIN_COUNT];
        uint32_t right_count[BIN_COUNT];
        box acc = box_empty();
        uint32_t n = 0;
        for (int u = m - 1; u > 0; u--) {
            box_grow(&acc, &bn->bounds[a][used[u]]);
            n += bn->counts[a][used[u]];
            right_area[u] = box_area(&acc);
            right_count[u] = n;
        }
        acc = box_empty();
        n = 0;
        for (int u = 0; u < m - 1; u++) {
            box_grow(&acc, &bn->bounds[a][used[u]]);
            n += bn->counts[a][used[u]];
            float cost = box_area(&acc) * (float)n + right_area[u + 1] * (float)right_count[u + 1];
            if (cost < s.cost) {
                s.cost = cost;
                s.axis = a;
                s.bin = used[u] + 1;
            }
        }
    }
    if (s.cost < INFINITY) {
        s.left = box_empty(), s.right = box_empty();
        for (uint32_t rest = bn->used[s.axis]; rest; rest &= rest - 1) {
            int k = __builtin_ctz(rest);
            box_grow(k < s.bin ? &s.left : &s.right, &bn->bounds[s.axis][k]);
        }
    }
    return s;
}

typedef struct bin_share {
    const item *items;
    uint32_t begin, end;
    const binning *g;
    bins out;
} bin_share;

static void *bin_share_run(void *arg) {
    bin_share *s = arg;
    bin_items(s->items, s->begin, s->end, s->g, &s->out);
    return NULL;
}

/* Bins items [begin, end) on up to b->threads threads into *out. */
static void bin_shared(const builder *b, uint32_t begin, uint32_t end, const binning *g,
                       bins *out) {
    uint32_t n = end - begin;
    int parts = b->threads;
    if (n / MIN_SHARED_ITEMS < (uint32_t)parts) parts = (int)(n / MIN_SHARED_ITEMS);
    if (parts < 2) {
        bin_items(b->items, begin, end, g, out);
        return;
    }
    bin_share *shares = malloc((size_t)parts * sizeof *shares);
    if (!shares) { /* no memory: bin on this thread */
        bin_items(b->items, begin, end, g, out);
        return;
    }
    for (int t = 0; t < parts; t++) {
        shares[t] = (bin_share){.items = b->items,
                                .begin = begin + (uint32_t)((uint64_t)n * t / parts),
                                .end = begin + (uint32_t)((uint64_t)n * (t + 1) / parts),
                                .g = g};
    }
    threads_run(bin_share_run, shares, sizeof *shares, parts);
    *out = shares[0].out;
    for (int t = 1; t < parts; t++) bins_merge(out, &shares[t].out);
    free(shares);
}

split bvh_sah_split(const builder *b, uint32_t begin, uint32_t end, const binning *g, bool shared) {
    bins bn;
    if (shared)
        bin_shared(b, begin, end, g, &bn);
    else
        bin_items(b->items, begin, end, g, &bn);
    return sah_sweep(&bn, g);
}
