/* bvh_tree.c: the binary tree by binned SAH: the nodes over many primitives split one at a
 * time with their binning shared among the threads, the subtrees below them built as tasks that
 * the threads take from a shared list, largest first. */
#include <stdlib.h>

#include "render/bvh_builder.h"

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

/* The kind of input primitive k: 0 a sphere, 1 a triangle, 2 an instance. */
static int kind_of(const builder *b, uint32_t k) {
    return (k >= b->first_triangle) + (k >= b->first_instance);
}

/* Whether positions [begin, end) hold primitives of one kind: a leaf holds spheres, triangles or
 * instances, so that a walk tests it with one test. */
static bool one_kind(const builder *b, uint32_t begin, uint32_t end) {
    int first = kind_of(b, b->order[begin]);
    for (uint32_t k = begin + 1; k < end; k++)
        if (kind_of(b, b->order[k]) != first) return false;
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
uint32_t bvh_build_node(builder *b, const task *t, bool top, uint32_t *depth) {
    if (top && t->end - t->begin <= b->task_items) {
        if (!push_task(b, t)) b->failed = true;
        return 0;
    }
    item *items = b->items;
    uint32_t id = t->slot, begin = t->begin, end = t->end, n = end - begin;
    if (t->depth > *depth) *depth = t->depth;
    const box *bx = &t->bounds;
    b->nodes[id] =
        (binary_node){{bx->lo[0], bx->lo[1], bx->lo[2]}, {bx->hi[0], bx->hi[1], bx->hi[2]}, 0, 0};

    /* Near the depth limit only median splits, which halve the count, are sure to fit. */
    bool must_median = t->depth + 1 + median_levels(n) >= b->max_depth;
    bool leaf_ok = n <= TZ_BVH_LEAF_MAX && one_kind(b, begin, end);
    /* A split's cost is the traversal and more: as few spheres as that are a leaf whatever the
     * split would cost, so they are not binned. */
    bool leaf_sure = leaf_ok && (float)n <= TRAVERSAL_COST;
    split s = {.cost = INFINITY};
    binning g = binning_of(&t->cbox);
    if (n > 1 && !must_median && !leaf_sure) s = bvh_sah_split(b, begin, end, &g, top);
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
    uint32_t inner = 1 + bvh_build_node(b, &left, top, depth);
    inner += bvh_build_node(b, &right, top, depth);
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
        b->tasks[k].inner = bvh_build_node(b, &b->tasks[k], false, &w->depth);
    }
}

static int task_larger(const void *x, const void *y) {
    const task *a = x, *b = y;
    uint32_t na = a->end - a->begin, nb = b->end - b->begin;
    return na != nb ? (na < nb) - (na > nb) : (a->slot > b->slot) - (a->slot < b->slot);
}

/* Builds every task of b on b->threads threads, the largest first so that the last ones to
 * finish are small; returns the deepest leaf's depth. */
uint32_t bvh_build_tasks(builder *b) {
    if (b->task_count > 1) qsort(b->tasks, b->task_count, sizeof *b->tasks, task_larger);
    atomic_init(&b->next_task, 0);
    worker workers[THREADS_MAX];
    for (int t = 0; t < b->threads; t++) workers[t] = (worker){.b = b};
    threads_run(worker_run, workers, sizeof *workers, b->threads);
    uint32_t depth = 0;
    for (int t = 0; t < b->threads; t++)
        if (workers[t].depth > depth) depth = workers[t].depth;
    return depth;
}
