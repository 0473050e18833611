/* vk_bindings.h: trace.comp's descriptor bindings as one table, a row per binding (its kind,
 * where its bytes come from and how many, its texel format), which drives every buffer's
 * creation, upload, descriptor and release: a new input buffer is one row in vk_bindings.c
 * (with its TZ_BINDING_* number in shared_layout.h and its declaration in trace.comp). */
#ifndef TRAZADOR_VK_BINDINGS_H
#define TRAZADOR_VK_BINDINGS_H

#include <stdbool.h>
#include <stdint.h>

#include "render/scene_pack.h"
#include "render/vk/vk_context.h"

/* Rows of the table: every binding of set 0, the ray query module's acceleration structure
 * last (its slot in a buffer array stays empty: vk_accel.c owns the structure). */
#define VK_BINDINGS (TZ_BINDING_ACCEL + 1)

/* What the rows' sources read: the packed scene, the BVH nodes the chosen walks read (NULL and
 * 0: none) and the size of the part's sums and stacks. */
typedef struct vk_binding_sources {
    const packed_scene *scene;
    const struct gpu_bvh_node *nodes;
    uint32_t node_count;
    const struct gpu_wide_node *wide_nodes;
    uint32_t wide_node_count;
    uint32_t width; /* of the region, in pixels */
    uint32_t rows;  /* of the region, padded to whole bands of TZ_BAND_ROWS */
    uint32_t depth; /* chunk-tree blocks a pixel */
} vk_binding_sources;

/* Creates every binding's buffer (and texel view) and writes the inputs into it: straight into
 * mapped memory, or into `upload` (created here) for vk_bindings_record_upload to copy; false
 * (logged) on failure, with what was made left for vk_bindings_destroy. */
bool vk_bindings_create(vk_context *ctx, const vk_binding_sources *s, vk_buffer *buffers,
                        vk_buffer *upload);
/* Records the copies of the staged inputs from `upload` into their buffers; never fails. */
void vk_bindings_record_upload(VkCommandBuffer cmd, const vk_buffer *upload,
                               const vk_buffer *buffers);
/* The descriptor types of the first `count` bindings, for vk_kernel_create; never fails. */
void vk_bindings_types(uint32_t count, VkDescriptorType *types);
/* Points the kernel's buffer bindings at `buffers` (a dynamic binding at one band of rows, the
 * others whole); never fails (misuse surfaces through validation). */
void vk_bindings_bind(vk_context *ctx, vk_kernel *k, const vk_buffer *buffers, uint32_t rows);
/* Writes the dynamic bindings' offsets, in binding order, for a band starting at row `band_y0`
 * and returns how many; never fails. */
uint32_t vk_bindings_dynamic_offsets(const vk_buffer *buffers, uint32_t rows, uint32_t band_y0,
                                     uint32_t *offsets);
/* Frees every binding's buffer; safe on zeroed ones. */
void vk_bindings_destroy(vk_context *ctx, vk_buffer *buffers);

#endif
