/* bvh_wide.h: the BVH's binary nodes collapsed into nodes of up to four children with quantized
 * boxes (struct gpu_wide_node, shaders/shared_layout.h), which the shaders' walk per invocation
 * reads: half the node visits and half the texel fetches a child of the binary nodes. Every
 * decoded box holds its binary box, so the walk finds the binary walks' hits (the tie rule). */
#ifndef TRAZADOR_BVH_WIDE_H
#define TRAZADOR_BVH_WIDE_H

#include <stdbool.h>
#include <stdint.h>

#include "shared_layout.h"

/* Collapses the count binary nodes of a flat BVH (bvh.h) into *out, *out_count wide nodes, root
 * first (NULL and 0 for no nodes); false (logged) on out-of-memory. */
bool bvh_widen(const struct gpu_bvh_node *nodes, uint32_t count, struct gpu_wide_node **out,
               uint32_t *out_count);

#endif
