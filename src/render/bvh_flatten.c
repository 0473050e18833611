/* bvh_flatten.c: the binary tree written into the flat array of shared_layout.h, depth first,
 * each node holding its two children's boxes: the nodes above the tasks first, keeping each
 * task's place, then the tasks' subtrees at their places on all threads; then the leaves'
 * positions turned into primitive ids. */
#include <stdlib.h>
#include <string.h>

#include "render/bvh_builder.h"
#include "util/big_memory.h"

static float float_of(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
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
 * non-NULL, a task's subtree is not written: its place is kept (task.flat_at) and counted. */
static uint32_t flatten(const builder *tasks, const binary_node *tree, uint32_t k,
                        struct gpu_bvh_node *out, uint32_t *count) {
    uint32_t id = (*count)++;
    /* A box at +infinity, which no ray enters. */
    static const binary_node empty = {
        {INFINITY, INFINITY, INFINITY}, {INFINITY, INFINITY, INFINITY}, 0, 0};
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
        *lo[c] = (tz_vec4){kid->lo[0], kid->lo[1], kid->lo[2], float_of(ref)};
        *hi[c] = (tz_vec4){kid->hi[0], kid->hi[1], kid->hi[2], 0.0f};
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
uint32_t bvh_flatten_all(builder *b, struct gpu_bvh_node *out) {
    uint32_t count = 0;
    if (b->task_count == 1 && b->tasks[0].slot == 0) { /* one task: the whole tree */
        flatten(NULL, b->nodes, 0, out, &count);
        return count;
    }
    if (b->task_count > 1) qsort(b->tasks, b->task_count, sizeof *b->tasks, task_slot_order);
    flatten(b, b->nodes, 0, out, &count);
    atomic_uint next;
    atomic_init(&next, 0);
    flattener f[THREADS_MAX]; /* alike: each thread takes tasks from the shared list */
    for (int t = 0; t < b->threads; t++) f[t] = (flattener){.b = b, .out = out, .next = &next};
    threads_run(flattener_run, f, sizeof *f, b->threads);
    return count;
}

/* Leaf references hold positions until here; a walk wants primitive ids, spheres numbered in
 * their order, then triangles, then instances from instance_id: each leaf's range (of one kind)
 * maps to consecutive ids. */
bool bvh_renumber_leaves(const builder *b, uint32_t count, uint32_t instance_id,
                         struct gpu_bvh_node *nodes, uint32_t node_count) {
    uint32_t *id = big_malloc((count ? count : 1) * sizeof *id);
    if (!id) return false;
    uint32_t spheres = 0, triangles = 0, instances = 0;
    for (uint32_t k = 0; k < count; k++)
        id[k] = b->order[k] < b->first_triangle   ? spheres++
                : b->order[k] < b->first_instance ? b->first_triangle + triangles++
                                                  : instance_id + instances++;
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
