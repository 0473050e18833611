/* bvh.c: binned-SAH BVH build over spheres and triangles: a binary tree, then its inner nodes
 * written into the flat array of shared_layout.h, each holding its two children's boxes.
 *
 * The tree is a function of the input alone, whatever the thread count: the nodes over many
 * spheres are split one at a time with their binning shared among the threads, and the subtrees
 * below them are built as independent tasks. Every step (bin sums, partition, median selection)
 * does exactly what a one-thread build does, so the trees and the sphere order are identical. */
#include "render/bvh.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "util/log.h"

#ifdef __SSE2__
#include <emmintrin.h>
#endif

/* 32 bins and a node visit costing two sphere tests, against 16 and four: random spheres (the
 * bench's camera, one thread) render 8-10% faster on the CPU at 1,000 to 1,000,000 spheres and
 * 4-5% faster on lavapipe, sphereflakes 2% faster. */
#define BIN_COUNT 32
#define TRAVERSAL_COST 2.0f /* relative to one sphere test */
/* Threads the build uses at most. */
#define MAX_THREADS 64
/* Below this many spheres per thread, sharing one node's binning costs more than it saves. */
#define MIN_SHARED_ITEMS 16384
/* Tasks per thread: enough that uneven SAH splits still even out across the threads. */
#define TASKS_PER_THREAD 16

/* Boxes hold a fourth lane, always finite, so that growing one compiles to vector min and max. */
typedef struct box {
    float lo[4], hi[4];
} box;

/* Position k of the permutation being built: the sphere's centre (its centroid) and padded
 * radius, 16 bytes that every pass reads (its input index moves beside it in builder.order, which
 * only the partition touches); its box is the centre minus and plus the radius, computed where
 * needed by the very operations that would have stored it. */
typedef struct item {
    float centroid[4]; /* the fourth lane is a sphere's radius, 0 for a triangle */
    float half[4];     /* the box's half extents (a sphere's radius four times) */
} item;

/* A node of the binary tree. A subtree over n spheres takes at most 2n - 1 slots: a node's
 * first child is the next slot and its second child follows the first child's 2 * left_count
 * slots, so slots depend only on the sphere ranges and subtrees can be built apart. */
typedef struct binary_node {
    box bounds;
    uint32_t index; /* inner: the second child's slot; leaf: the first sphere */
    uint32_t count; /* spheres of a leaf, 0 for an inner node */
} binary_node;

/* A subtree to build: its slot, sphere range, depth, box and centroid box; once built, how many
 * inner nodes it has and where the first of them goes in the flat array. */
typedef struct task {
    uint32_t slot, begin, end, depth;
    box bounds, cbox;
    uint32_t inner, flat_at;
} task;

typedef struct builder {
    item *items;
    uint32_t *order; /* order[k]: the input primitive at position k */
    uint32_t
        first_triangle; /* inputs from here on are triangles, which share no leaf with spheres */
    binary_node *nodes;
    uint32_t max_depth;
    int threads;
    uint32_t task_items; /* subtrees over at most this many spheres become tasks */
    task *tasks;
    uint32_t task_count, task_capacity;
    atomic_uint next_task;
    bool failed; /* out of memory growing the task list */
} builder;

/* The bins of one node on the three axes. Bit k of used[a] says bin k of axis a holds a sphere;
 * only then are its box and count set, so small nodes clear and sweep no empty bins. */
typedef struct bins {
    box bounds[3][BIN_COUNT];
    uint32_t counts[3][BIN_COUNT];
    uint32_t used[3];
} bins;
_Static_assert(BIN_COUNT <= 32, "bins.used has a bit per bin");

/* How one node's centroids map to bins (the fourth lanes are 0: their bin is 0, never used). */
typedef struct binning {
    float lo[4], scale[4];
    bool binned[3]; /* the axis has centroid extent */
} binning;

/* The best split of a node. */
typedef struct split {
    float cost; /* INFINITY: none */
    int axis, bin;
    box left, right; /* the children's boxes */
} split;

static box box_empty(void) {
    return (box){{INFINITY, INFINITY, INFINITY, 0.0f}, {-INFINITY, -INFINITY, -INFINITY, 0.0f}};
}

/* b's lanes take o's where o's are below (lo) or above (hi): what SSE's min and max do. */
static void box_grow(box *b, const box *o) {
#ifdef __SSE2__
    _mm_storeu_ps(b->lo, _mm_min_ps(_mm_loadu_ps(o->lo), _mm_loadu_ps(b->lo)));
    _mm_storeu_ps(b->hi, _mm_max_ps(_mm_loadu_ps(o->hi), _mm_loadu_ps(b->hi)));
#else
    for (int a = 0; a < 4; a++) {
        b->lo[a] = o->lo[a] < b->lo[a] ? o->lo[a] : b->lo[a];
        b->hi[a] = o->hi[a] > b->hi[a] ? o->hi[a] : b->hi[a];
    }
#endif
}

static void box_grow_point(box *b, const float p[4]) {
#ifdef __SSE2__
    __m128 v = _mm_loadu_ps(p);
    _mm_storeu_ps(b->lo, _mm_min_ps(v, _mm_loadu_ps(b->lo)));
    _mm_storeu_ps(b->hi, _mm_max_ps(v, _mm_loadu_ps(b->hi)));
#else
    for (int a = 0; a < 4; a++) {
        b->lo[a] = p[a] < b->lo[a] ? p[a] : b->lo[a];
        b->hi[a] = p[a] > b->hi[a] ? p[a] : b->hi[a];
    }
#endif
}

static float box_area(const box *b) {
    float x = b->hi[0] - b->lo[0], y = b->hi[1] - b->lo[1], z = b->hi[2] - b->lo[2];
    return x < 0.0f ? 0.0f : x * y + y * z + z * x;
}

static float float_of(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Levels a median-split subtree of n spheres needs below its root. */
static uint32_t median_levels(uint32_t n) {
    uint32_t levels = 0;
    for (uint32_t leaves = (n + TZ_BVH_LEAF_MAX - 1) / TZ_BVH_LEAF_MAX; leaves > 1;
         leaves = (leaves + 1) / 2)
        levels++;
    return levels;
}

static void swap_items(const builder *b, uint32_t i, uint32_t j) {
    item t = b->items[i];
    b->items[i] = b->items[j];
    b->items[j] = t;
    uint32_t o = b->order[i];
    b->order[i] = b->order[j];
    b->order[j] = o;
}

/* The box of an item (a sphere's fourth lanes 0 and twice the radius). */
static box item_box(const item *it) {
    box b;
#ifdef __SSE2__
    __m128 c = _mm_loadu_ps(it->centroid), r = _mm_loadu_ps(it->half);
    _mm_storeu_ps(b.lo, _mm_sub_ps(c, r));
    _mm_storeu_ps(b.hi, _mm_add_ps(c, r));
#else
    for (int a = 0; a < 4; a++) {
        b.lo[a] = it->centroid[a] - it->half[a];
        b.hi[a] = it->centroid[a] + it->half[a];
    }
#endif
    return b;
}

/* Whether positions [begin, end) hold primitives of one kind: a leaf holds spheres or triangles,
 * so that a walk tests it with one test. */
static bool one_kind(const builder *b, uint32_t begin, uint32_t end) {
    bool first = b->order[begin] >= b->first_triangle;
    for (uint32_t k = begin + 1; k < end; k++)
        if ((b->order[k] >= b->first_triangle) != first) return false;
    return true;
}

/* The box and centroid box of items [begin, end). */
static void range_boxes(const item *items, uint32_t begin, uint32_t end, box *bounds, box *cbox) {
    *bounds = box_empty(), *cbox = box_empty();
    for (uint32_t k = begin; k < end; k++) {
        box ib = item_box(&items[k]);
        box_grow(bounds, &ib);
        box_grow_point(cbox, items[k].centroid);
    }
}

/* Reorders positions [begin, end) so that the one at mid has the median centroid on axis, none
 * before it greater and none after it smaller (Wirth's selection). */
static void select_median(const builder *b, uint32_t begin, uint32_t end, uint32_t mid, int axis) {
    const item *items = b->items;
    long lo = begin, hi = (long)end - 1, m = mid;
    while (lo < hi) {
        float pivot = items[m].centroid[axis];
        long i = lo, j = hi;
        while (i <= j) {
            while (items[i].centroid[axis] < pivot) i++;
            while (items[j].centroid[axis] > pivot) j--;
            if (i <= j) swap_items(b, (uint32_t)i++, (uint32_t)j--);
        }
        if (m <= j)
            hi = j;
        else if (m >= i)
            lo = i;
        else
            break;
    }
}

/* The bin of a centroid coordinate c on an axis whose centroids start at lo, scale bins a unit:
 * the binning and the partition both use it, so the two always agree. */
static int bin_of(float c, float lo, float scale) {
    int bin = (int)((c - lo) * scale);
    return bin < 0 ? 0 : bin >= BIN_COUNT ? BIN_COUNT - 1 : bin;
}

static binning binning_of(const box *cbox) {
    binning g = {0};
    for (int a = 0; a < 3; a++) {
        float extent = cbox->hi[a] - cbox->lo[a];
        g.lo[a] = cbox->lo[a];
        g.binned[a] = extent > 0.0f;
        g.scale[a] = g.binned[a] ? BIN_COUNT / extent : 0.0f;
    }
    return g;
}

/* Bins items [begin, end) into *out. Only the counts are cleared up front: a bin's box is set
 * by its first item, since deep in the tree most bins stay empty. */
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
    pthread_t threads[MAX_THREADS];
    int started = 0;
    if (shares) {
        for (int t = 0; t < parts; t++) {
            shares[t] = (bin_share){.items = b->items,
                                    .begin = begin + (uint32_t)((uint64_t)n * t / parts),
                                    .end = begin + (uint32_t)((uint64_t)n * (t + 1) / parts),
                                    .g = g};
        }
        while (started < parts - 1 &&
               pthread_create(&threads[started], NULL, bin_share_run, &shares[started + 1]) == 0)
            started++;
    }
    if (!shares || started < parts - 1) { /* no memory or no threads: bin on this one */
        for (int t = 0; t < started; t++) pthread_join(threads[t], NULL);
        free(shares);
        bin_items(b->items, begin, end, g, out);
        return;
    }
    bin_share_run(&shares[0]);
    *out = shares[0].out;
    for (int t = 0; t < started; t++) {
        pthread_join(threads[t], NULL);
        bins_merge(out, &shares[t + 1].out);
    }
    free(shares);
}

static bool push_task(builder *b, const task *t) {
    if (b->task_count == b->task_capacity) {
        uint32_t capacity = b->task_capacity ? 2 * b->task_capacity : 64;
        task *grown = realloc(b->tasks, capacity * sizeof *grown);
        if (!grown) return false;
        b->tasks = grown;
        b->task_capacity = capacity;
    }
    b->tasks[b->task_count++] = *t;
    return true;
}

/* Builds the subtree of t into its slots and raises *depth to its deepest leaf; returns its
 * count of inner nodes. top: the subtrees over at most b->task_items spheres are left in b's task
 * list instead (and not counted). */
static uint32_t build_node(builder *b, const task *t, bool top, uint32_t *depth) {
    if (top && t->end - t->begin <= b->task_items) {
        if (!push_task(b, t)) b->failed = true;
        return 0;
    }
    item *items = b->items;
    uint32_t id = t->slot, begin = t->begin, end = t->end, n = end - begin;
    if (t->depth > *depth) *depth = t->depth;
    b->nodes[id] = (binary_node){.bounds = t->bounds};

    /* Near the depth limit only median splits, which halve the count, are sure to fit. */
    bool must_median = t->depth + 1 + median_levels(n) >= b->max_depth;
    bool leaf_ok = n <= TZ_BVH_LEAF_MAX && one_kind(b, begin, end);
    /* A split's cost is the traversal and more: as few spheres as that are a leaf whatever the
     * split would cost, so they are not binned. */
    bool leaf_sure = leaf_ok && (float)n <= TRAVERSAL_COST;
    split s = {.cost = INFINITY};
    binning g = binning_of(&t->cbox);
    if (n > 1 && !must_median && !leaf_sure) {
        bins bn;
        if (top)
            bin_shared(b, begin, end, &g, &bn);
        else
            bin_items(items, begin, end, &g, &bn);
        s = sah_sweep(&bn, &g);
    }
    float parent_area = box_area(&t->bounds);
    if (leaf_ok &&
        (n <= 1 || !(s.cost < INFINITY) ||
         TRAVERSAL_COST + s.cost / (parent_area > 0.0f ? parent_area : 1.0f) >= (float)n)) {
        b->nodes[id].index = begin;
        b->nodes[id].count = n;
        return 0;
    }
    task left = {.slot = id + 1, .begin = begin, .depth = t->depth + 1};
    task right = {.end = end, .depth = t->depth + 1};
    uint32_t mid = begin;
    if (s.cost < INFINITY) {
        /* Partition by bin, gathering each side's centroid box on the way: an item is final
         * once it is passed on the left or swapped to the right. */
        int axis = s.axis;
        float lo = g.lo[axis], scale = g.scale[axis];
        box lc = box_empty(), rc = box_empty();
        uint32_t i = begin, j = end;
        while (i < j) {
            if (bin_of(items[i].centroid[axis], lo, scale) < s.bin) {
                box_grow_point(&lc, items[i].centroid);
                i++;
            } else {
                swap_items(b, i, --j);
                box_grow_point(&rc, items[j].centroid);
            }
        }
        mid = i;
        left.bounds = s.left, left.cbox = lc;
        right.bounds = s.right, right.cbox = rc;
    }
    if (mid == begin || mid == end) { /* no SAH split: the object median on the widest axis */
        int axis = 0;
        for (int a = 1; a < 3; a++)
            if (t->cbox.hi[a] - t->cbox.lo[a] > t->cbox.hi[axis] - t->cbox.lo[axis]) axis = a;
        mid = begin + n / 2;
        select_median(b, begin, end, mid, axis);
        range_boxes(items, begin, mid, &left.bounds, &left.cbox);
        range_boxes(items, mid, end, &right.bounds, &right.cbox);
    }
    left.end = mid;
    right.slot = id + 2 * (mid - begin), right.begin = mid;
    uint32_t inner = 1 + build_node(b, &left, top, depth);
    inner += build_node(b, &right, top, depth);
    b->nodes[id].index = right.slot;
    return inner;
}

typedef struct worker {
    builder *b;
    uint32_t depth;
} worker;

/* Builds tasks from the shared list until none is left. */
static void *worker_run(void *arg) {
    worker *w = arg;
    builder *b = w->b;
    for (;;) {
        uint32_t k = atomic_fetch_add(&b->next_task, 1);
        if (k >= b->task_count) return NULL;
        b->tasks[k].inner = build_node(b, &b->tasks[k], false, &w->depth);
    }
}

static int task_larger(const void *x, const void *y) {
    const task *a = x, *b = y;
    uint32_t na = a->end - a->begin, nb = b->end - b->begin;
    return na != nb ? (na < nb) - (na > nb) : (a->slot > b->slot) - (a->slot < b->slot);
}

/* Builds every task of b on b->threads threads, the largest first so that the last ones to
 * finish are small; returns the deepest leaf's depth. */
static uint32_t build_tasks(builder *b) {
    if (b->task_count > 1) qsort(b->tasks, b->task_count, sizeof *b->tasks, task_larger);
    atomic_init(&b->next_task, 0);
    worker workers[MAX_THREADS];
    pthread_t threads[MAX_THREADS];
    int started = 0;
    for (int t = 0; t < b->threads; t++) workers[t] = (worker){.b = b};
    while (started < b->threads - 1 &&
           pthread_create(&threads[started], NULL, worker_run, &workers[started + 1]) == 0)
        started++;
    worker_run(&workers[0]);
    uint32_t depth = workers[0].depth;
    for (int t = 0; t < started; t++) {
        pthread_join(threads[t], NULL);
        if (workers[t + 1].depth > depth) depth = workers[t + 1].depth;
    }
    return depth;
}

static int task_slot_order(const void *x, const void *y) {
    const task *a = x, *b = y;
    return (a->slot > b->slot) - (a->slot < b->slot);
}

/* The task whose subtree starts at slot; NULL if none (b's tasks sorted by slot). */
static task *task_at(const builder *b, uint32_t slot) {
    task key = {.slot = slot};
    if (b->task_count == 0) return NULL; /* and b->tasks may be NULL, which bsearch refuses */
    return bsearch(&key, b->tasks, b->task_count, sizeof *b->tasks, task_slot_order);
}

/* Writes binary node k and the inner nodes below it, depth first, into out from *count on (a
 * leaf root becomes a node whose second child is empty); returns its index in out. With tasks
 * (b non-NULL), a task's subtree is not written: its place is kept (task.flat_at) and counted. */
static uint32_t flatten(const builder *tasks, const binary_node *tree, uint32_t k,
                        struct gpu_bvh_node *out, uint32_t *count) {
    uint32_t id = (*count)++;
    /* A box at +infinity, which no ray enters. */
    static const binary_node empty = {
        {{INFINITY, INFINITY, INFINITY, 0.0f}, {INFINITY, INFINITY, INFINITY, 0.0f}}, 0, 0};
    const binary_node *kids[2] = {&tree[k], &empty};
    uint32_t at[2] = {k, 0};
    if (tree[k].count == 0) {
        at[0] = k + 1, at[1] = tree[k].index;
        kids[0] = &tree[at[0]], kids[1] = &tree[at[1]];
    }
    tz_vec4 *lo[2] = {&out[id].left_lo, &out[id].right_lo};
    tz_vec4 *hi[2] = {&out[id].left_hi, &out[id].right_hi};
    for (int c = 0; c < 2; c++) {
        const binary_node *kid = kids[c];
        task *t = kid != &empty && kid->count == 0 && tasks ? task_at(tasks, at[c]) : NULL;
        if (t) {
            t->flat_at = *count;
            *count += t->inner;
        }
        uint32_t ref = kid == &empty    ? 0u
                       : kid->count > 0 ? kid->count << TZ_BVH_COUNT_SHIFT | kid->index
                       : t              ? t->flat_at
                                        : flatten(tasks, tree, at[c], out, count);
        const box *bx = &kid->bounds;
        *lo[c] = (tz_vec4){bx->lo[0], bx->lo[1], bx->lo[2], float_of(ref)};
        *hi[c] = (tz_vec4){bx->hi[0], bx->hi[1], bx->hi[2], 0.0f};
    }
    return id;
}

typedef struct flattener {
    const builder *b;
    struct gpu_bvh_node *out;
    atomic_uint *next;
} flattener;

/* Writes the subtrees of tasks from the shared list until none is left. */
static void *flattener_run(void *arg) {
    const flattener *f = arg;
    const builder *b = f->b;
    for (;;) {
        uint32_t k = atomic_fetch_add(f->next, 1);
        if (k >= b->task_count) return NULL;
        uint32_t at = b->tasks[k].flat_at;
        if (b->tasks[k].inner > 0) flatten(NULL, b->nodes, b->tasks[k].slot, f->out, &at);
    }
}

/* Writes the tree of b into out, depth first, its tasks' subtrees on b->threads threads; returns
 * the node count. */
static uint32_t flatten_all(builder *b, struct gpu_bvh_node *out) {
    uint32_t count = 0;
    if (b->task_count == 1 && b->tasks[0].slot == 0) { /* one task: the whole tree */
        flatten(NULL, b->nodes, 0, out, &count);
        return count;
    }
    if (b->task_count > 1) qsort(b->tasks, b->task_count, sizeof *b->tasks, task_slot_order);
    flatten(b, b->nodes, 0, out, &count);
    atomic_uint next;
    atomic_init(&next, 0);
    flattener f = {.b = b, .out = out, .next = &next};
    pthread_t threads[MAX_THREADS];
    int started = 0;
    while (started < b->threads - 1 &&
           pthread_create(&threads[started], NULL, flattener_run, &f) == 0)
        started++;
    flattener_run(&f);
    for (int t = 0; t < started; t++) pthread_join(threads[t], NULL);
    return count;
}

static int thread_count(int requested) {
    long n = requested > 0 ? requested : sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > MAX_THREADS ? MAX_THREADS : (int)n;
}

/* The item of a sphere: its centre and its radius, padded by a few float ulps of the largest
 * coordinate, so that a hit the sphere test accepts never lies outside its box through
 * rounding. */
static item sphere_item(const struct gpu_sphere *sp) {
    const tz_vec4 *c = &sp->center_radius;
    float m = fabsf(c->x) > fabsf(c->y) ? fabsf(c->x) : fabsf(c->y);
    m = m > fabsf(c->z) ? m : fabsf(c->z);
    float r = c->w + (m + c->w) * 4e-6f;
    return (item){{c->x, c->y, c->z, r}, {r, r, r, r}};
}

/* The item of a triangle: the middle of its corners' box and its half extents, padded as a
 * sphere's. */
static item triangle_item(const struct gpu_triangle *t) {
    const tz_vec4 *v[3] = {&t->v0, &t->v1, &t->v2};
    float lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        float x0 = (&v[0]->x)[a], x1 = (&v[1]->x)[a], x2 = (&v[2]->x)[a];
        lo[a] = fminf(x0, fminf(x1, x2));
        hi[a] = fmaxf(x0, fmaxf(x1, x2));
    }
    item it = {{0}, {0}};
    float m = 0.0f, h = 0.0f;
    for (int a = 0; a < 3; a++) {
        it.centroid[a] = 0.5f * lo[a] + 0.5f * hi[a];
        it.half[a] = 0.5f * hi[a] - 0.5f * lo[a];
        m = fmaxf(m, fmaxf(fabsf(lo[a]), fabsf(hi[a])));
        h = fmaxf(h, it.half[a]);
    }
    for (int a = 0; a < 3; a++) it.half[a] += (m + h) * 4e-6f;
    return it;
}

/* Leaf references hold positions until here; a walk wants primitive ids, spheres numbered in
 * their order, then triangles: each leaf's range (of one kind) maps to consecutive ids. */
static bool renumber_leaves(const builder *b, uint32_t count, struct gpu_bvh_node *nodes,
                            uint32_t node_count) {
    uint32_t *id = malloc((count ? count : 1) * sizeof *id);
    if (!id) return false;
    uint32_t spheres = 0, triangles = 0;
    for (uint32_t k = 0; k < count; k++)
        id[k] = b->order[k] < b->first_triangle ? spheres++ : b->first_triangle + triangles++;
    for (uint32_t k = 0; k < node_count; k++) {
        tz_vec4 *lo[2] = {&nodes[k].left_lo, &nodes[k].right_lo};
        for (int c = 0; c < 2; c++) {
            uint32_t ref;
            memcpy(&ref, &lo[c]->w, sizeof ref);
            if (ref >> TZ_BVH_COUNT_SHIFT == 0) continue;
            ref = (ref & ~TZ_BVH_INDEX_MASK) | id[ref & TZ_BVH_INDEX_MASK];
            lo[c]->w = float_of(ref);
        }
    }
    free(id);
    return true;
}

bool bvh_build_primitives(const bvh_input *in, uint32_t max_depth, int threads, bvh *out) {
    *out = (bvh){0};
    uint32_t count = in->sphere_count + in->triangle_count;
    builder b = {.max_depth = max_depth,
                 .threads = thread_count(threads),
                 .first_triangle = in->sphere_count};
    size_t n = count ? count : 1;
    b.items = malloc(n * sizeof *b.items);
    b.nodes = malloc(2 * n * sizeof *b.nodes);
    b.order = malloc(n * sizeof *b.order);
    struct gpu_bvh_node *flat = malloc(n * sizeof *flat); /* the inner nodes: fewer than n */
    if (!b.items || !b.nodes || !b.order || !flat) {
        log_error("out of memory building a BVH over %u primitives", count);
        free(b.items), free(b.nodes), free(b.order), free(flat);
        return false;
    }
    task root = {.end = count, .bounds = box_empty(), .cbox = box_empty()};
    for (uint32_t k = 0; k < count; k++) {
        item *it = &b.items[k];
        *it = k < in->sphere_count ? sphere_item(&in->spheres[k])
                                   : triangle_item(&in->triangles[k - in->sphere_count]);
        b.order[k] = k;
        box ib = item_box(it);
        box_grow(&root.bounds, &ib);
        box_grow_point(&root.cbox, it->centroid);
    }
    uint32_t flat_count = 0, depth = 0;
    if (count > 0) { /* no primitives, no nodes: nothing to traverse */
        b.task_items = b.threads > 1 ? count / ((uint32_t)b.threads * TASKS_PER_THREAD) : count;
        build_node(&b, &root, true, &depth);
        uint32_t task_depth = b.failed ? 0 : build_tasks(&b);
        if (task_depth > depth) depth = task_depth;
        if (!b.failed) flat_count = flatten_all(&b, flat);
        if (b.failed || (in->triangle_count > 0 && !renumber_leaves(&b, count, flat, flat_count))) {
            log_error("out of memory building a BVH over %u primitives", count);
            free(b.items), free(b.nodes), free(b.order), free(flat), free(b.tasks);
            return false;
        }
    }
    free(b.items);
    free(b.nodes);
    free(b.tasks);
    *out = (bvh){.nodes = flat, .node_count = flat_count, .depth = depth, .order = b.order};
    return true;
}

bool bvh_build_threads(const struct gpu_sphere *spheres, uint32_t count, uint32_t max_depth,
                       int threads, bvh *out) {
    bvh_input in = {.spheres = spheres, .sphere_count = count};
    return bvh_build_primitives(&in, max_depth, threads, out);
}

bool bvh_build(const struct gpu_sphere *spheres, uint32_t count, uint32_t max_depth, bvh *out) {
    return bvh_build_threads(spheres, count, max_depth, 0, out);
}

void bvh_free(bvh *b) {
    free(b->nodes);
    free(b->order);
    *b = (bvh){0};
}
