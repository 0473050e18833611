/* vk_accel_boxes.h: what the ray query walk's bottom-level structures hold (vk_accel.c): the
 * scene's own primitives in one, each instanced model's faces in one of their own, and every
 * primitive's AABB padded past the rounding of the device's box tests and transforms. */
#ifndef TRAZADOR_VK_ACCEL_BOXES_H
#define TRAZADOR_VK_ACCEL_BOXES_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "render/scene_pack.h"

/* Primitives [first, first + count) of the packed scene: one bottom-level structure. */
typedef struct accel_range {
    uint32_t first, count;
} accel_range;

/* The ranges of p's bottom-level structures into *ranges (malloc'ed; range 0 the scene's own
 * primitives, range 1 + m the faces of the model whose first face is the m-th smallest among
 * the instances') and their count; 0 (logged) out of memory. */
uint32_t accel_ranges(const packed_scene *p, accel_range **ranges);
/* The range (1 + m) of instance i's model among the `count` ranges. */
uint32_t accel_range_of(const packed_scene *p, const accel_range *ranges, uint32_t count,
                        uint32_t i);
/* Fills boxes[k] for every primitive k of p (sphere_count + triangle_count of them), each in its
 * own space (a model's faces in the model's), padded as the file's comment says; false (logged)
 * out of memory. */
bool accel_fill_boxes(const packed_scene *p, const accel_range *ranges, uint32_t count,
                      VkAabbPositionsKHR *boxes);

#endif
