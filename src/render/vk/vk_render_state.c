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

/* The buffers of the packed scene: frame, spheres, lights, BVH nodes, emitters, triangles, their
 * materials and normals, and the wide BVH nodes. */
#define INPUT_BUFFERS 9

/* vk_render_create_buffers with the wide nodes made (none: one zeroed node), and the binary ones
 * when `binary`. */
static bool create_buffers(vk_render *r, const packed_scene *p, int width, int height,
                           uint32_t depth, bool stoppable, bool binary,
                           const struct gpu_wide_node *wide, uint32_t wide_count) {
    vk_context *ctx = &r->ctx;
    const VkBufferUsageFlags input = VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    const VkBufferUsageFlags storage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                                       VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    size_t sphere_bytes = (p->frame.sphere_count ? p->frame.sphere_count : 1u) * sizeof *p->spheres;
    size_t light_bytes = (p->frame.light_count ? p->frame.light_count : 1u) * sizeof *p->lights;
    /* Without a BVH one zeroed node keeps the binding valid; the shader never reads it. */
    static const struct gpu_bvh_node no_nodes[1];
    uint32_t node_count = binary ? p->frame.node_count : 0u;
    const void *nodes = node_count ? (const void *)p->nodes : (const void *)no_nodes;
    size_t node_bytes = (node_count ? node_count : 1u) * sizeof *p->nodes;
    static const struct gpu_wide_node no_wide_nodes[1];
    const void *wide_nodes = wide_count ? (const void *)wide : (const void *)no_wide_nodes;
    size_t wide_bytes = (wide_count ? wide_count : 1u) * sizeof *wide;
    size_t emitter_bytes =
        (p->frame.emitter_count ? p->frame.emitter_count : 1u) * sizeof *p->emitters;
    size_t triangle_bytes =
        (p->frame.triangle_count ? p->frame.triangle_count : 1u) * sizeof *p->triangles;
    size_t material_bytes = (p->material_count ? p->material_count : 1u) * sizeof *p->materials;
    size_t normals_bytes = (p->normals_count ? p->normals_count : 1u) * sizeof *p->normals;
    /* Rows padded to whole bands: every band binding stays inside the buffer. */
    uint64_t rows = ((uint64_t)height + TZ_BAND_ROWS - 1u) / TZ_BAND_ROWS * TZ_BAND_ROWS;
    VkDeviceSize accum_bytes = rows * (uint64_t)width * ACCUM_PIXEL_BYTES;
    VkDeviceSize stack_bytes = rows * (uint64_t)width * depth * STACK_BLOCK_BYTES;
    const VkBufferUsageFlags texels = VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | input;
    if (!vk_buffer_create(ctx, sizeof p->frame, VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | input,
                          VK_MEMORY_DEVICE, &r->frame) ||
        !vk_buffer_create(ctx, sphere_bytes, texels, VK_MEMORY_DEVICE, &r->spheres) ||
        !vk_buffer_create_view(ctx, &r->spheres, VK_FORMAT_R32G32B32A32_SFLOAT) ||
        !vk_buffer_create(ctx, light_bytes, texels, VK_MEMORY_DEVICE, &r->lights) ||
        !vk_buffer_create_view(ctx, &r->lights, VK_FORMAT_R32G32B32A32_SFLOAT) ||
        !vk_buffer_create(ctx, node_bytes, texels, VK_MEMORY_DEVICE, &r->nodes) ||
        /* As uints: child references are not floats (a GPU may flush their denormal bits). */
        !vk_buffer_create_view(ctx, &r->nodes, VK_FORMAT_R32G32B32A32_UINT) ||
        !vk_buffer_create(ctx, wide_bytes, texels, VK_MEMORY_DEVICE, &r->wide_nodes) ||
        !vk_buffer_create_view(ctx, &r->wide_nodes, VK_FORMAT_R32G32B32A32_UINT) ||
        !vk_buffer_create(ctx, emitter_bytes, texels, VK_MEMORY_DEVICE, &r->emitters) ||
        !vk_buffer_create_view(ctx, &r->emitters, VK_FORMAT_R32G32B32A32_SFLOAT) ||
        !vk_buffer_create(ctx, triangle_bytes, texels, VK_MEMORY_DEVICE, &r->triangles) ||
        !vk_buffer_create_view(ctx, &r->triangles, VK_FORMAT_R32G32B32A32_SFLOAT) ||
        !vk_buffer_create(ctx, material_bytes, texels, VK_MEMORY_DEVICE, &r->materials) ||
        !vk_buffer_create_view(ctx, &r->materials, VK_FORMAT_R32G32B32A32_SFLOAT) ||
        !vk_buffer_create(ctx, normals_bytes, texels, VK_MEMORY_DEVICE, &r->normals) ||
        !vk_buffer_create_view(ctx, &r->normals, VK_FORMAT_R32G32B32A32_SFLOAT) ||
        !vk_buffer_create(ctx, accum_bytes, storage, VK_MEMORY_DEVICE, &r->accum) ||
        !vk_buffer_create(ctx, accum_bytes, storage, VK_MEMORY_DEVICE, &r->accum_comp) ||
        !vk_buffer_create(ctx, stack_bytes, storage, VK_MEMORY_DEVICE, &r->stack) ||
        !vk_buffer_create(ctx, TZ_COUNTER_WORDS * sizeof(uint32_t), storage, VK_MEMORY_DEVICE,
                          &r->counter))
        return false;
    VkDeviceSize pixels = (VkDeviceSize)width * (VkDeviceSize)height;
    VkDeviceSize state_bytes = 16u + pixels * (ACCUM_PIXEL_BYTES + depth * STACK_BLOCK_BYTES);
    if ((!r->accum.mapped || !r->stack.mapped || !r->counter.mapped) &&
        !vk_buffer_create(ctx, state_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT, VK_MEMORY_READBACK,
                          &r->readback))
        return false;
    if (stoppable && !vk_buffer_create(ctx, state_bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                       VK_MEMORY_READBACK, &r->snapshot))
        return false;
    const void *data[INPUT_BUFFERS] = {&p->frame,    p->spheres,  p->lights,
                                       nodes,        p->emitters, p->triangles,
                                       p->materials, p->normals,  wide_nodes};
    vk_buffer *targets[INPUT_BUFFERS] = {&r->frame,     &r->spheres,  &r->lights,
                                         &r->nodes,     &r->emitters, &r->triangles,
                                         &r->materials, &r->normals,  &r->wide_nodes};
    size_t sizes[INPUT_BUFFERS] = {sizeof p->frame, sphere_bytes,  light_bytes,
                                   node_bytes,      emitter_bytes, triangle_bytes,
                                   material_bytes,  normals_bytes, wide_bytes};
    bool mapped = true;
    size_t total = 0;
    for (int k = 0; k < INPUT_BUFFERS; k++) mapped &= targets[k]->mapped != NULL, total += sizes[k];
    if (mapped) {
        for (int k = 0; k < INPUT_BUFFERS; k++) memcpy(targets[k]->mapped, data[k], sizes[k]);
        return true;
    }
    if (!vk_buffer_create(ctx, total, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, VK_MEMORY_UPLOAD,
                          &r->upload))
        return false;
    size_t offset = 0;
    for (int k = 0; k < INPUT_BUFFERS; k++) {
        memcpy((char *)r->upload.mapped + offset, data[k], sizes[k]);
        offset += sizes[k];
    }
    return true;
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
    char *accum = r->accum.mapped, *stack = r->stack.mapped;
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
    }
    return true;
}

void vk_render_record_setup(vk_render *r, bool resumed, size_t pixels) {
    if (r->upload.buffer) {
        vk_buffer *targets[INPUT_BUFFERS] = {&r->frame,     &r->spheres,  &r->lights,
                                             &r->nodes,     &r->emitters, &r->triangles,
                                             &r->materials, &r->normals,  &r->wide_nodes};
        VkDeviceSize offset = 0;
        for (int k = 0; k < INPUT_BUFFERS; k++) {
            VkBufferCopy copy = {offset, 0, targets[k]->size};
            vkCmdCopyBuffer(r->cmd, r->upload.buffer, targets[k]->buffer, 1, &copy);
            offset += targets[k]->size;
        }
    }
    if (!resumed) {
        vkCmdFillBuffer(r->cmd, r->accum.buffer, 0, VK_WHOLE_SIZE, 0u);
        vkCmdFillBuffer(r->cmd, r->stack.buffer, 0, VK_WHOLE_SIZE, 0u);
    } else if (r->state.buffer) {
        VkDeviceSize accum_bytes = (VkDeviceSize)pixels * ACCUM_PIXEL_BYTES;
        VkBufferCopy sums = {0, 0, accum_bytes};
        VkBufferCopy stacks = {accum_bytes, 0, r->state.size - accum_bytes};
        vkCmdCopyBuffer(r->cmd, r->state.buffer, r->accum.buffer, 1, &sums);
        vkCmdCopyBuffer(r->cmd, r->state.buffer, r->stack.buffer, 1, &stacks);
    }
    vkCmdFillBuffer(r->cmd, r->accum_comp.buffer, 0, VK_WHOLE_SIZE, 0u);
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
    vkCmdCopyBuffer(r->cmd, r->accum.buffer, r->snapshot.buffer, 1, &sums);
    vkCmdCopyBuffer(r->cmd, r->stack.buffer, r->snapshot.buffer, 1, &stacks);
}

void vk_render_record_readback(vk_render *r, const pass_plan *plan, bool final) {
    VkCommandBuffer cmd = r->cmd;
    vk_commands_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                        VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                        VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_HOST_READ_BIT);
    if (!r->counter.mapped) {
        VkBufferCopy copy = {0, 0, TZ_COUNTER_WORDS * sizeof(uint32_t)};
        vkCmdCopyBuffer(cmd, r->counter.buffer, r->readback.buffer, 1, &copy);
    }
    VkDeviceSize pixels = (VkDeviceSize)plan->width * plan->height;
    if (final && !r->accum.mapped) {
        VkBufferCopy copy = {0, 16, pixels * ACCUM_PIXEL_BYTES};
        vkCmdCopyBuffer(cmd, r->accum.buffer, r->readback.buffer, 1, &copy);
    }
    if (final && !r->stack.mapped) {
        VkBufferCopy copy = {0, 16 + pixels * ACCUM_PIXEL_BYTES,
                             pixels * plan->depth * STACK_BLOCK_BYTES};
        vkCmdCopyBuffer(cmd, r->stack.buffer, r->readback.buffer, 1, &copy);
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
    if (!r->accum.mapped || !r->stack.mapped) {
        if (!vk_commands_begin(&r->ctx, &r->cmd)) return false;
        vk_render_record_readback(r, plan, true);
        if (!vk_commands_submit_wait(&r->ctx, r->cmd, r->fence)) return false;
    }
    *sums = r->accum.mapped ? r->accum.mapped : (const char *)r->readback.mapped + 16;
    *stacks = r->stack.mapped ? (const char *)r->stack.mapped
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
        vk_buffer *buffers[] = {
            &r->snapshot,   &r->readback,  &r->state,     &r->upload,  &r->counter,   &r->stack,
            &r->accum_comp, &r->accum,     &r->emitters,  &r->nodes,   &r->lights,    &r->spheres,
            &r->frame,      &r->triangles, &r->materials, &r->normals, &r->wide_nodes};
        for (size_t k = 0; k < sizeof buffers / sizeof buffers[0]; k++)
            vk_buffer_destroy(ctx, buffers[k]);
    }
}
