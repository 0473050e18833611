/* bvh.h: the bounding volume hierarchy over spheres and triangles, built on the host with binned
 * SAH and stored as one flat array of struct gpu_bvh_node (shaders/shared_layout.h) that both
 * back ends traverse as is.
 * Four walks read it: trace_bvh in src/render/cpu/integrator.c (one ray, a leaf at once),
 * packet_walk in src/render/cpu/packet_trace.h (a packet's union of nodes), and
 * trace_bvh and trace_bvh_cooperative in shaders/intersect.glsl (one primitive a loop pass, per
 * invocation or for the whole subgroup), the first of these over the same tree collapsed by
 * bvh_wide.h where the device gains by it, whose boxes hold these. They visit primitives in
 * different orders, and the packet tests spheres beyond a lane's own walk; they agree on every hit
 * because of the tie rule, nearer_hit in shaders/common/ray.h: an exact tie goes to the lower
 * index. Primitives are stored in BVH order with and without the tree, so --no-bvh gives the same
 * images too. */
#ifndef TRAZADOR_BVH_H
#define TRAZADOR_BVH_H

#include <stdbool.h>
#include <stdint.h>

#include "shared_layout.h"

typedef struct bvh {
    struct gpu_bvh_node *nodes;
    uint32_t node_count;
    uint32_t depth;  /* levels from the root to the deepest leaf, below the build's max_depth */
    uint32_t *order; /* order[k]: the input primitive stored at position k (leaves are ranges) */
} bvh;

/* The primitives a tree is built over: spheres, then triangles (input ids in that order). Its
 * leaves hold one kind each and refer to primitive ids of the stored order: the spheres in
 * their order of `order`, then the triangles in theirs (ids from sphere_count on). */
typedef struct bvh_input {
    const struct gpu_sphere *spheres;
    uint32_t sphere_count;
    const struct gpu_triangle *triangles;
    uint32_t triangle_count;
    /* Instances (input ids after the triangles), each by its box in world space; their leaves
     * refer to ids from instance_id on, in their order of `order`. */
    const struct bvh_box *instances;
    uint32_t instance_count, instance_id;
} bvh_input;

/* An axis-aligned box. */
typedef struct bvh_box {
    float lo[3], hi[3];
} bvh_box;

/* Builds the tree over the input's primitives on at most threads threads (0: one per online
 * processor), every leaf at depth < max_depth; the same tree for every thread count. False
 * (logged) on out-of-memory. */
bool bvh_build_primitives(const bvh_input *in, uint32_t max_depth, int threads, bvh *out);

/* Builds the tree over count spheres (0 spheres: 0 nodes) with every leaf at depth < max_depth
 * (TZ_BVH_MAX_DEPTH for rendering; at least 22 so that 2^24 spheres fit); false (logged) on
 * out-of-memory. */
bool bvh_build(const struct gpu_sphere *spheres, uint32_t count, uint32_t max_depth, bvh *out);
/* bvh_build on at most threads threads (0: one per online processor); the tree is the same for
 * every thread count. */
bool bvh_build_threads(const struct gpu_sphere *spheres, uint32_t count, uint32_t max_depth,
                       int threads, bvh *out);
/* Frees the tree; safe on a zeroed bvh. */
void bvh_free(bvh *b);

#endif
