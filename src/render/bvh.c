/* bvh.c: the BVH build's entry points: the primitives as items, then the binary tree over them
 * (bvh_tree.c, split by bvh_sah.c), then its inner nodes written into the flat array of
 * shared_layout.h (bvh_flatten.c), each holding its two children's boxes.
 *
 * The tree is a function of the input alone, whatever the thread count: the nodes over many
 * spheres are split one at a time with their binning shared among the threads, and the subtrees
 * below them are built as independent tasks. Every step (bin sums, partition, median selection)
 * does exactly what a one-thread build does, so the trees and the sphere order are identical. */
#include "render/bvh.h"

#include <math.h>
#include <stdlib.h>

#include "render/bvh_builder.h"
#include "util/big_memory.h"
#include "util/log.h"
#include "util/threads.h"

/* Tasks per thread: enough that uneven SAH splits still even out across the threads, few enough
 * that the nodes above them, whose partitions run on one thread, stay few (docs/PERF.md, "Huge
 * pages": 4 built a million faces 15-20% faster than 16). */
#define TASKS_PER_THREAD 4
/* Below this many primitives per thread, the items are made on one. */
#define MIN_ITEMS_PER_THREAD 65536

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

static float smaller(float x, float y) { return y < x ? y : x; }
static float larger(float x, float y) { return y > x ? y : x; }

/* The item of a triangle: the middle of its corners' box and its half extents, padded as a
 * sphere's (the coordinates are finite: selects, not fminf's calls). */
static item triangle_item(const struct gpu_triangle *t) {
    const tz_vec4 *v[3] = {&t->v0, &t->v1, &t->v2};
    float lo[3], hi[3];
    for (int a = 0; a < 3; a++) {
        float x0 = (&v[0]->x)[a], x1 = (&v[1]->x)[a], x2 = (&v[2]->x)[a];
        lo[a] = smaller(x0, smaller(x1, x2));
        hi[a] = larger(x0, larger(x1, x2));
    }
    item it = {{0}, {0}};
    float m = 0.0f, h = 0.0f;
    for (int a = 0; a < 3; a++) {
        it.centroid[a] = 0.5f * lo[a] + 0.5f * hi[a];
        it.half[a] = 0.5f * hi[a] - 0.5f * lo[a];
        m = larger(m, larger(fabsf(lo[a]), fabsf(hi[a])));
        h = larger(h, it.half[a]);
    }
    for (int a = 0; a < 3; a++) it.half[a] += (m + h) * 4e-6f;
    return it;
}

/* The item of an instance's box, padded as a triangle's. */
static item box_item(const bvh_box *bx) {
    item it = {{0}, {0}};
    float m = 0.0f, h = 0.0f;
    for (int a = 0; a < 3; a++) {
        it.centroid[a] = 0.5f * bx->lo[a] + 0.5f * bx->hi[a];
        it.half[a] = 0.5f * bx->hi[a] - 0.5f * bx->lo[a];
        m = larger(m, larger(fabsf(bx->lo[a]), fabsf(bx->hi[a])));
        h = larger(h, it.half[a]);
    }
    for (int a = 0; a < 3; a++) it.half[a] += (m + h) * 4e-6f;
    return it;
}

/* The items of primitives [begin, end) of in, and their box and centroid box. */
typedef struct item_share {
    const bvh_input *in;
    builder *b;
    uint32_t begin, end;
    box bounds, cbox;
} item_share;

static void *item_share_run(void *arg) {
    item_share *s = arg;
    const bvh_input *in = s->in;
    s->bounds = box_empty(), s->cbox = box_empty();
    for (uint32_t k = s->begin; k < s->end; k++) {
        item *it = &s->b->items[k];
        uint32_t instance = in->sphere_count + in->triangle_count;
        *it = k < in->sphere_count ? sphere_item(&in->spheres[k])
              : k < instance       ? triangle_item(&in->triangles[k - in->sphere_count])
                                   : box_item(&in->instances[k - instance]);
        s->b->order[k] = k;
        box ib = item_box(it);
        box_grow(&s->bounds, &ib);
        box_grow_point(&s->cbox, it->centroid);
    }
    return NULL;
}

/* Makes b's count items on its threads into root's boxes: min and max are exact, so the boxes
 * are a one-thread build's. */
static void make_items(const bvh_input *in, builder *b, uint32_t count, task *root) {
    int parts = b->threads;
    if (count / MIN_ITEMS_PER_THREAD < (uint32_t)parts) parts = (int)(count / MIN_ITEMS_PER_THREAD);
    if (parts < 1) parts = 1;
    item_share shares[THREADS_MAX];
    for (int t = 0; t < parts; t++) {
        shares[t] = (item_share){.in = in,
                                 .b = b,
                                 .begin = (uint32_t)((uint64_t)count * t / parts),
                                 .end = (uint32_t)((uint64_t)count * (t + 1) / parts)};
    }
    threads_run(item_share_run, shares, sizeof *shares, parts);
    root->bounds = box_empty(), root->cbox = box_empty();
    for (int t = 0; t < parts; t++) {
        box_grow(&root->bounds, &shares[t].bounds);
        box_grow(&root->cbox, &shares[t].cbox);
    }
}

bool bvh_build_primitives(const bvh_input *in, uint32_t max_depth, int threads, bvh *out) {
    *out = (bvh){0};
    uint32_t count = in->sphere_count + in->triangle_count + in->instance_count;
    builder b = {.max_depth = max_depth,
                 .threads = thread_count(threads, THREADS_MAX),
                 .first_triangle = in->sphere_count,
                 .first_instance = in->sphere_count + in->triangle_count};
    size_t n = count ? count : 1;
    b.items = big_malloc(n * sizeof *b.items);
    b.nodes = big_malloc(2 * n * sizeof *b.nodes);
    b.order = big_malloc(n * sizeof *b.order);
    struct gpu_bvh_node *flat = big_malloc(n * sizeof *flat); /* the inner nodes: fewer than n */
    if (!b.items || !b.nodes || !b.order || !flat) {
        log_error("out of memory building a BVH over %u primitives", count);
        free(b.items), free(b.nodes), free(b.order), free(flat);
        return false;
    }
    task root = {.end = count};
    make_items(in, &b, count, &root);
    uint32_t flat_count = 0, depth = 0;
    if (count > 0) { /* no primitives, no nodes: nothing to traverse */
        b.task_items = b.threads > 1 ? count / ((uint32_t)b.threads * TASKS_PER_THREAD) : count;
        bvh_build_node(&b, &root, true, &depth);
        uint32_t task_depth = b.failed ? 0 : bvh_build_tasks(&b);
        if (task_depth > depth) depth = task_depth;
        if (!b.failed) flat_count = bvh_flatten_all(&b, flat);
        if (b.failed || (in->triangle_count + in->instance_count > 0 &&
                         !bvh_renumber_leaves(&b, count, in->instance_id, flat, flat_count))) {
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
