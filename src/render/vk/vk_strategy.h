/* vk_strategy.h: how the Vulkan back end renders a scene on a device: the accumulation's
 * bytes a pixel, the walk (compute, cooperative, ray query), the intersection
 * strategy (unrolled spheres, a BVH walk bounded on lavapipe, every sphere, the device's
 * acceleration structure) and the refusals of what the device could not render right. */
#ifndef TRAZADOR_VK_STRATEGY_H
#define TRAZADOR_VK_STRATEGY_H

#include <stdbool.h>
#include <stdint.h>

#include "render/render.h"
#include "render/vk/vk_context.h"

/* Bytes a pixel takes in each accumulation buffer (sums, compensation): a vec4. */
#define ACCUM_PIXEL_BYTES (4u * sizeof(float))
/* Bytes a block of a pixel's stack takes: RGB. */
#define STACK_BLOCK_BYTES (3u * sizeof(float))

/* How the shader intersects a scene: every sphere in unrolled tests, a walk of the BVH (bounded on
 * lavapipe), or a loop over every sphere; and the loop passes one sample may cost. */
typedef struct vk_strategy {
    uint32_t unrolled_spheres; /* TZ_SPEC_UNROLLED_SPHERES: 0 when not unrolled */
    bool use_bvh;
    bool cooperative; /* the subgroup walks the BVH together: the trace_coop module */
    bool ray_query;   /* rays walk the device's acceleration structure: the trace_rq module */
    bool wide_bvh;    /* the walk per invocation reads the wide BVH (TZ_SPEC_WIDE_BVH) */
    uint32_t walk;    /* loop passes of a ray's walk (TZ_SPEC_WALK_BUDGET: vk_strategy_walk_loop), 0
                         unlimited */
    uint64_t sample_iterations;
} vk_strategy;

/* Whether a context for opts should enable ray queries (vk_context_desc.ray_query): where the
 * walk asked for may be the ray query walk; never fails. */
bool vk_strategy_wants_ray_query(const render_opts *opts);
/* The walk of a render on this device into *walk: the one opts->walk names, else the one
 * TRAZADOR_VK_WALK names (compute, invocation, cooperative, rayquery; one it cannot do falls
 * back to auto's with a notice), else auto's (the measured faster one for the device type), with
 * a few words on why in *why. False (logged) when the walk asked for is one the device cannot
 * do. */
bool vk_strategy_walk(const vk_context *ctx, const render_opts *opts, render_walk *walk,
                      const char **why);
/* The strategy for the scene on this device with `walk` (vk_strategy_walk's); never fails. */
vk_strategy vk_strategy_choose(const vk_context *ctx, const scene *s, const render_opts *opts,
                               render_walk walk);
/* TZ_SPEC_WALK_BUDGET: the passes each walk loop may take (0 unlimited); never fails. */
uint32_t vk_strategy_walk_loop(const vk_strategy *st);
/* False, with the reason in `reason` (RENDER_REASON_SIZE bytes) and nothing logged, when the
 * device could not render a width x height region with `depth` chunk-tree blocks a pixel right:
 * buffers past its limits, or on lavapipe loop work that could reach its silent loop limit. */
bool vk_strategy_check(const vk_context *ctx, const scene *s, const render_opts *opts,
                       const vk_strategy *st, int width, int height, uint32_t depth, char *reason);

#endif
