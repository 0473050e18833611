/* vk_render_state.c: the device buffers of a Vulkan render and the part's state in and out of
 * them (see vk_render_state.h). */
#include "render/vk/vk_render_state.h"

#include <stdlib.h>
#include <string.h>

#include "render/bvh_wide.h"
#include "render/vk/vk_strategy.h"
#include "util/big_memory.h"
#include "util/clock.h"
#include "util/log.h"

/* vk_render_create_buffers with the wide nodes made (none: one zeroed node), and the binary ones
 * when `binary`. */
static bool create_buffers(vk_render *r, const packed_scene *p, int width, int height,
                           uint32_t depth, bool stoppable, bool binary,
                           const struct gpu_wide_node *wide, uint32_t wide_count) {
    vk_context *ctx = &r->ctx;
    r->rows = ((uint32_t)height + TZ_BAND_ROWS - 1u) / TZ_BAND_ROWS * TZ_BAND_ROWS;
    vk_binding_sources sources = {.scene = p,
                                  .nodes = binary ? p->nodes : NULL,
                                  .node_count = binary ? p->frame.node_count : 0u,
                                  .wide_nodes = wide,
                                  .wide_node_count = wide_count,
                                  .width = (uint32_t)width,
                                  .rows = r->rows,
                                  .depth = depth};
    if (!vk_bindings_create(ctx, &sources, r->buffers, &r->upload)) return false;
    VkDeviceSize pixels = (VkDeviceSize)width * (VkDeviceSize)height;
    VkDeviceSize state_bytes = 16u + pixels * (ACCUM_PIXEL_BYTES + depth * STACK_BLOCK_BYTES);
    if ((!r->buffers[TZ_BINDING_ACCUM].mapped || !r->buffers[TZ_BINDING_STACK].mapped ||
         !r->buffers[TZ_BINDING_COUNTERS].mapped) &&
        !vk_buffer_create(ctx, state_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_READBACK,
                          &r->readback))
        return false;
    return !stoppable || vk_buffer_create(ctx, state_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                          VK_MEMORY_READBACK, &r->snapshot);
}

bool vk_render_create_buffers(vk_render *r, const packed_scene *p, const vk_strategy *st, int width,
                              int height, uint32_t depth, bool stoppable) {
    struct gpu_wide_node *wide;
    uint32_t wide_count;
    double start = clock_seconds();
    if (!bvh_widen(p->nodes, st->wide_bvh ? p->frame.node_count : 0u, &wide, &wide_count))
        return false;
    if (wide_count)
        log_debug("vulkan: %u wide BVH nodes from %u binary ones in %.1f ms", wide_count,
                  p->frame.node_count, 1e3 * (clock_seconds() - start));
    /* The cooperative walk reads the binary nodes; so does the walk per invocation without the
     * wide ones. */
    bool binary = st->cooperative || !st->wide_bvh;
    bool made = create_buffers(r, p, width, height, depth, stoppable, binary, wide, wide_count);
    free(wide);
    return made;
}

bool vk_render_load_part(vk_render *r, const part *p, uint32_t depth) {
    size_t n = (size_t)(p->meta.x1 - p->meta.x0) * (size_t)(p->meta.y1 - p->meta.y0);
    size_t accum_bytes = n * ACCUM_PIXEL_BYTES;
    char *accum = r->buffers[TZ_BINDING_ACCUM].mapped, *stack = r->buffers[TZ_BINDING_STACK].mapped;
    if (!accum || !stack) {
        if (!vk_buffer_create(&r->ctx, accum_bytes + n * depth * STACK_BLOCK_BYTES,
                              VK_BUFFER_USAGE_TRANSFER_SRC_BIT, VK_MEMORY_UPLOAD, &r->state))
            return false;
        accum = r->state.mapped;
        stack = accum + accum_bytes;
    }
    for (size_t i = 0; i < n; i++) {
        float px[4] = {0.0f, 0.0f, 0.0f, (float)p->count[i]};
        memcpy(accum + i * ACCUM_PIXEL_BYTES, px, sizeof px);
        for (int k = 0; k < p->stack.count; k++)
            memcpy(stack + (i * depth + (size_t)k) * STACK_BLOCK_BYTES, &p->block[k][3 * i],
                   STACK_BLOCK_BYTES);
        if (p->adaptive) { /* the last two blocks (gpu_pass.noise_threshold) */
            float state[6] = {p->adaptive[4 * i],
                              p->adaptive[4 * i + 1],
                              p->adaptive[4 * i + 2],
                              p->adaptive[4 * i + 3],
                              0.0f,
                              0.0f};
            memcpy(stack + (i * depth + depth - 2u) * STACK_BLOCK_BYTES, state, sizeof state);
        }
    }
    return true;
}

void vk_render_record_setup(vk_render *r, bool resumed, size_t pixels) {
    vk_bindings_record_upload(r->cmd, &r->upload, r->buffers);
    if (!resumed) {
        vkCmdFillBuffer(r->cmd, r->buffers[TZ_BINDING_ACCUM].buffer, 0, VK_WHOLE_SIZE, 0u);
        vkCmdFillBuffer(r->cmd, r->buffers[TZ_BINDING_STACK].buffer, 0, VK_WHOLE_SIZE, 0u);
    } else if (r->state.buffer) {
        VkDeviceSize accum_bytes = (VkDeviceSize)pixels * ACCUM_PIXEL_BYTES;
        VkBufferCopy sums = {0, 0, accum_bytes};
        VkBufferCopy stacks = {accum_bytes, 0, r->state.size - accum_bytes};
        vkCmdCopyBuffer(r->cmd, r->state.buffer, r->buffers[TZ_BINDING_ACCUM].buffer, 1, &sums);
        vkCmdCopyBuffer(r->cmd, r->state.buffer, r->buffers[TZ_BINDING_STACK].buffer, 1, &stacks);
    }
    vkCmdFillBuffer(r->cmd, r->buffers[TZ_BINDING_ACCUM_COMP].buffer, 0, VK_WHOLE_SIZE, 0u);
}

void vk_render_record_snapshot(vk_render *r, const pass_plan *plan) {
    vk_commands_barrier(r->cmd,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                        VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
    VkDeviceSize pixels = (VkDeviceSize)plan->width * plan->height;
    VkBufferCopy sums = {0, 16, pixels * ACCUM_PIXEL_BYTES};
    VkBufferCopy stacks = {0, 16 + pixels * ACCUM_PIXEL_BYTES,
                           pixels * plan->depth * STACK_BLOCK_BYTES};
    vkCmdCopyBuffer(r->cmd, r->buffers[TZ_BINDING_ACCUM].buffer, r->snapshot.buffer, 1, &sums);
    vkCmdCopyBuffer(r->cmd, r->buffers[TZ_BINDING_STACK].buffer, r->snapshot.buffer, 1, &stacks);
}

void vk_render_record_readback(vk_render *r, const pass_plan *plan, bool final) {
    VkCommandBuffer cmd = r->cmd;
    vk_commands_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                        VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_HOST_READ_BIT);
    if (!r->buffers[TZ_BINDING_COUNTERS].mapped) {
        VkBufferCopy copy = {0, 0, TZ_COUNTER_WORDS * sizeof(uint32_t)};
        vkCmdCopyBuffer(cmd, r->buffers[TZ_BINDING_COUNTERS].buffer, r->readback.buffer, 1, &copy);
    }
    VkDeviceSize pixels = (VkDeviceSize)plan->width * plan->height;
    if (final && !r->buffers[TZ_BINDING_ACCUM].mapped) {
        VkBufferCopy copy = {0, 16, pixels * ACCUM_PIXEL_BYTES};
        vkCmdCopyBuffer(cmd, r->buffers[TZ_BINDING_ACCUM].buffer, r->readback.buffer, 1, &copy);
    }
    if (final && !r->buffers[TZ_BINDING_STACK].mapped) {
        VkBufferCopy copy = {0, 16 + pixels * ACCUM_PIXEL_BYTES,
                             pixels * plan->depth * STACK_BLOCK_BYTES};
        vkCmdCopyBuffer(cmd, r->buffers[TZ_BINDING_STACK].buffer, r->readback.buffer, 1, &copy);
    }
    if (r->readback.buffer || r->snapshot.buffer)
        vk_commands_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                            VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
}

/* Where the sums and stacks are for the host to read: the mapped buffers, or readback after a
 * copy; false (logged) on a Vulkan failure. */
static bool live_state(vk_render *r, const pass_plan *plan, const char **sums,
                       const char **stacks) {
    size_t n = (size_t)plan->width * plan->height;
    if (!r->buffers[TZ_BINDING_ACCUM].mapped || !r->buffers[TZ_BINDING_STACK].mapped) {
        if (!vk_commands_begin(&r->ctx, &r->cmd)) return false;
        vk_render_record_readback(r, plan, true);
        if (!vk_commands_submit_wait(&r->ctx, r->cmd, r->fence)) return false;
    }
    *sums = r->buffers[TZ_BINDING_ACCUM].mapped ? r->buffers[TZ_BINDING_ACCUM].mapped
                                                : (const char *)r->readback.mapped + 16;
    *stacks = r->buffers[TZ_BINDING_STACK].mapped
                  ? (const char *)r->buffers[TZ_BINDING_STACK].mapped
                  : (const char *)r->readback.mapped + 16 + n * ACCUM_PIXEL_BYTES;
    return true;
}

/* Reads sums and stacks (live_state's, or the snapshot's) into p: its counts, the stack `shape`
 * and its blocks, the samples up to chunk `done` and the non-finite samples since the last sync;
 * false (logged) on out of memory. */
static bool sync_part(const pass_plan *plan, const char *sums, const char *stacks,
                      const chunk_stack *shape, uint32_t done, uint64_t *nonfinite, part *p) {
    size_t n = (size_t)plan->width * plan->height;
    for (int k = 0; k < CHUNK_STACK_MAX; k++) {
        if (k >= shape->count) {
            free(p->block[k]);
            p->block[k] = NULL;
        } else if (!p->block[k] && !(p->block[k] = big_malloc(n * STACK_BLOCK_BYTES))) {
            log_error("out of memory for a part of %zu pixels", n);
            return false;
        }
    }
    for (size_t i = 0; i < n; i++) {
        float px[4];
        memcpy(px, sums + i * ACCUM_PIXEL_BYTES, sizeof px);
        p->count[i] = (uint32_t)px[3];
        for (int k = 0; k < shape->count; k++)
            memcpy(&p->block[k][3 * i], stacks + (i * plan->depth + (size_t)k) * STACK_BLOCK_BYTES,
                   STACK_BLOCK_BYTES);
        if (p->adaptive) /* the last two blocks: odd RGB, then the stop chunk */
            memcpy(&p->adaptive[4 * i],
                   stacks + (i * plan->depth + plan->depth - 2u) * STACK_BLOCK_BYTES,
                   4 * sizeof(float));
    }
    p->stack = *shape;
    p->meta.sample_end = part_sample_of(p, done);
    p->meta.nonfinite += *nonfinite;
    *nonfinite = 0;
    return true;
}

bool vk_render_sync_part(vk_render *r, const pass_plan *plan, bool abandoned,
                         const chunk_stack *shape, uint32_t done, uint64_t *nonfinite, part *p) {
    const char *sums, *stacks;
    if (abandoned) {
        size_t n = (size_t)plan->width * plan->height;
        sums = (const char *)r->snapshot.mapped + 16;
        stacks = sums + n * ACCUM_PIXEL_BYTES;
    } else if (!live_state(r, plan, &sums, &stacks)) {
        return false;
    }
    return sync_part(plan, sums, stacks, shape, done, nonfinite, p);
}

void vk_render_destroy(vk_render *r) {
    vk_context *ctx = &r->ctx;
    if (ctx->device) {
        VK_CHECK(vkDeviceWaitIdle(ctx->device)); /* teardown goes on either way */
        if (r->fence) vkDestroyFence(ctx->device, r->fence, NULL);
        if (r->cmd) vkFreeCommandBuffers(ctx->device, ctx->command_pool, 1, &r->cmd);
        vk_kernel_destroy(ctx, &r->kernel);
        vk_accel_destroy(ctx, &r->accel);
        vk_buffer *staging[] = {&r->snapshot, &r->readback, &r->state, &r->upload};
        for (size_t k = 0; k < sizeof staging / sizeof staging[0]; k++)
            vk_buffer_destroy(ctx, staging[k]);
        vk_bindings_destroy(ctx, r->buffers);
    }
}
