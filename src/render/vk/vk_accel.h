/* vk_accel.h: the acceleration structure of the ray query walk: the scene's own primitives as
 * one geometry of padded AABBs in a bottom-level structure, each instanced model's faces in one
 * of their own (vk_accel_boxes.h), and at the top one instance of the first (custom index 0) and
 * each of the scene's instances of its model's (custom index 1 + its index). */
#ifndef TRAZADOR_VK_ACCEL_H
#define TRAZADOR_VK_ACCEL_H

#include "render/scene_pack.h"
#include "render/vk/vk_context.h"

typedef struct vk_accel {
    VkAccelerationStructureKHR *bottoms, top;
    vk_buffer *bottom_storage, top_storage; /* where the structures live */
    uint32_t bottom_count;
    vk_buffer boxes, instances, scratch; /* the build's inputs and scratch */
} vk_accel;

/* Builds the structures over p's primitives (AABB k is primitive id k, a model's face k counted
 * from its model's first) and waits for the build;
 * false (logged) on failure, with whatever was made left for vk_accel_destroy. */
bool vk_accel_build(vk_context *ctx, const packed_scene *p, vk_accel *out);
/* Points the kernel's acceleration-structure binding `binding` at the top-level structure;
 * never fails (misuse surfaces through validation). */
void vk_accel_bind(vk_context *ctx, vk_kernel *k, uint32_t binding, const vk_accel *a);
/* Destroys the structures and frees their buffers; safe on a zeroed vk_accel. */
void vk_accel_destroy(vk_context *ctx, vk_accel *a);

#endif
