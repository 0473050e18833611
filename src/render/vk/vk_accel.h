/* vk_accel.h: the acceleration structure of the ray query walk: the scene's primitives as one
 * geometry of padded AABBs in a bottom-level structure, one instance of it at the top. */
#ifndef TRAZADOR_VK_ACCEL_H
#define TRAZADOR_VK_ACCEL_H

#include "render/scene_pack.h"
#include "render/vk/vk_context.h"

typedef struct vk_accel {
    VkAccelerationStructureKHR bottom, top;
    vk_buffer bottom_storage, top_storage; /* where the structures live */
    vk_buffer boxes, instance, scratch;    /* the build's inputs and scratch */
} vk_accel;

/* Builds the structures over p's primitives (AABB k is primitive id k) and waits for the build;
 * false (logged) on failure, with whatever was made left for vk_accel_destroy. */
bool vk_accel_build(vk_context *ctx, const packed_scene *p, vk_accel *out);
/* Points the kernel's acceleration-structure binding `binding` at the top-level structure;
 * never fails (misuse surfaces through validation). */
void vk_accel_bind(vk_context *ctx, vk_kernel *k, uint32_t binding, const vk_accel *a);
/* Destroys the structures and frees their buffers; safe on a zeroed vk_accel. */
void vk_accel_destroy(vk_context *ctx, vk_accel *a);

#endif
