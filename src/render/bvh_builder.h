/* bvh_builder.h: what the files of the BVH build share (not an API): the build's state (items,
 * the binary tree's slots, the task list), boxes and their operations, and how a node's centroids
 * map to bins, which the SAH (bvh_sah.c) and the partition (bvh_tree.c) must agree on. bvh.c fills
 * the items and calls bvh_tree.c for the binary tree, then bvh_flatten.c for the flat array. */
#ifndef TRAZADOR_BVH_BUILDER_H
#define TRAZADOR_BVH_BUILDER_H

#include <math.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

#include "render/bvh.h"
#include "util/threads.h" /* the build uses THREADS_MAX threads at most */

#ifdef __SSE2__
#include <emmintrin.h>
#endif

/* 32 bins and a node visit costing two sphere tests, against 16 and four: trees that both back
 * ends render faster (docs/PERF.md, BVH build). */
#define BIN_COUNT 32
#define TRAVERSAL_COST 2.0f /* relative to one sphere test */
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
 * slots, so slots depend only on the sphere ranges and subtrees can be built apart. Its box
 * without the fourth lanes: 32 bytes a slot, 2n slots of fresh memory. */
typedef struct binary_node {
    float lo[3], hi[3];
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
    /* Inputs from here on are triangles, which share no leaf with spheres, and from
     * first_instance on instances (bvh_input), which share none with either. */
    uint32_t first_triangle, first_instance;
    binary_node *nodes;
    uint32_t max_depth;
    int threads;
    uint32_t task_items; /* subtrees over at most this many spheres become tasks */
    task *tasks;
    uint32_t task_count, task_capacity;
    atomic_uint next_task;
    bool failed; /* out of memory growing the task list */
} builder;

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

static inline box box_empty(void) {
    return (box){{INFINITY, INFINITY, INFINITY, 0.0f}, {-INFINITY, -INFINITY, -INFINITY, 0.0f}};
}

/* b's lanes take o's where o's are below (lo) or above (hi): what SSE's min and max do. */
static inline void box_grow(box *b, const box *o) {
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

static inline void box_grow_point(box *b, const float p[4]) {
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

static inline float box_area(const box *b) {
    float x = b->hi[0] - b->lo[0], y = b->hi[1] - b->lo[1], z = b->hi[2] - b->lo[2];
    return x < 0.0f ? 0.0f : x * y + y * z + z * x;
}

/* The box of an item (a sphere's fourth lanes 0 and twice the radius). */
static inline box item_box(const item *it) {
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

/* The bin of a centroid coordinate c on an axis whose centroids start at lo, scale bins a unit:
 * the binning and the partition both use it, so the two always agree. */
static inline int bin_of(float c, float lo, float scale) {
    int bin = (int)((c - lo) * scale);
    return bin < 0 ? 0 : bin >= BIN_COUNT ? BIN_COUNT - 1 : bin;
}

/* How the centroids of a node whose centroid box is cbox map to bins. */
static inline binning binning_of(const box *cbox) {
    binning g = {0};
    for (int a = 0; a < 3; a++) {
        float extent = cbox->hi[a] - cbox->lo[a];
        g.lo[a] = cbox->lo[a];
        g.binned[a] = extent > 0.0f;
        g.scale[a] = g.binned[a] ? BIN_COUNT / extent : 0.0f;
    }
    return g;
}

/* The cheapest SAH split of items [begin, end) binned by g, on all of b's threads when shared. */
split bvh_sah_split(const builder *b, uint32_t begin, uint32_t end, const binning *g, bool shared);
/* Builds t's subtree into its slots, or when top all but its tasks; returns its inner nodes. */
uint32_t bvh_build_node(builder *b, const task *t, bool top, uint32_t *depth);
/* Builds b's tasks on b->threads threads; returns the deepest leaf's depth. */
uint32_t bvh_build_tasks(builder *b);
/* Writes b's tree into out, depth first; returns the node count. */
uint32_t bvh_flatten_all(builder *b, struct gpu_bvh_node *out);
/* Turns the leaves' positions into primitive ids (instances' from instance_id); false on
 * out-of-memory. */
bool bvh_renumber_leaves(const builder *b, uint32_t count, uint32_t instance_id,
                         struct gpu_bvh_node *nodes, uint32_t node_count);

#endif
