/* vk_probe.c: the driver's loop budget, measured with shaders/loop_probe.comp, and the bounds of
 * the loop work of one trace.comp sample, as lavapipe counts it. */
#include "render/vk/vk_probe.h"

#include "loop_probe_spv.h"
#include "util/clock.h"
#include "util/log.h"

bool vk_probe_loops(vk_context *ctx, const uint32_t n[2], uint32_t least[2], uint32_t most[2]) {
    vk_buffer result = {0}, readback = {0};
    vk_kernel kernel = {0};
    VkFence fence = VK_NULL_HANDLE;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    bool ok = false;
    const VkDescriptorType types[] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER};
    vk_kernel_desc desc = {
        .code = loop_probe_spv,
        .code_size = sizeof loop_probe_spv,
        .types = types,
        .binding_count = 1,
        .push_size = 16,
    };
    VkFenceCreateInfo fence_info = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    const VkDeviceSize bytes = VK_PROBE_INVOCATIONS * 2u * sizeof(uint32_t);
    if (!vk_buffer_create(ctx, bytes,
                          VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
                              VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                          VK_MEMORY_DEVICE, &result) ||
        (!result.mapped && !vk_buffer_create(ctx, bytes, VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                             VK_MEMORY_READBACK, &readback)) ||
        !vk_kernel_create(ctx, &desc, &kernel) ||
        !VK_CHECK(vkCreateFence(ctx->device, &fence_info, NULL, &fence)) ||
        !vk_commands_begin(ctx, &cmd))
        goto done;
    const vk_buffer *buffers[] = {&result};
    const VkDeviceSize ranges[] = {VK_WHOLE_SIZE};
    vk_kernel_bind(ctx, &kernel, buffers, ranges);
    uint32_t push[4] = {n[0], n[1], 1u, 0u};
    vkCmdFillBuffer(cmd, result.buffer, 0, VK_WHOLE_SIZE, 0xffffffffu);
    vk_commands_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                        VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT);
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, kernel.layout, 0, 1, &kernel.set,
                            0, NULL);
    vkCmdPushConstants(cmd, kernel.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, push);
    vkCmdDispatch(cmd, VK_PROBE_INVOCATIONS / 64u, 1, 1);
    if (result.mapped) {
        vk_commands_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                            VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    } else {
        vk_commands_barrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_ACCESS_SHADER_WRITE_BIT,
                            VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_READ_BIT);
        VkBufferCopy copy = {0, 0, bytes};
        vkCmdCopyBuffer(cmd, result.buffer, readback.buffer, 1, &copy);
        vk_commands_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                            VK_PIPELINE_STAGE_HOST_BIT, VK_ACCESS_HOST_READ_BIT);
    }
    if (!vk_commands_submit_wait(ctx, cmd, fence)) goto done;
    const uint32_t *done = result.mapped ? result.mapped : readback.mapped;
    for (int loop = 0; loop < 2; loop++) {
        least[loop] = UINT32_MAX;
        most[loop] = 0;
        for (uint32_t k = 0; k < VK_PROBE_INVOCATIONS; k++) {
            uint32_t v = done[2 * k + (uint32_t)loop];
            least[loop] = v < least[loop] ? v : least[loop];
            most[loop] = v > most[loop] ? v : most[loop];
        }
    }
    ok = true;
done:
    if (fence) vkDestroyFence(ctx->device, fence, NULL);
    if (cmd) vkFreeCommandBuffers(ctx->device, ctx->command_pool, 1, &cmd);
    vk_kernel_destroy(ctx, &kernel);
    vk_buffer_destroy(ctx, &readback);
    vk_buffer_destroy(ctx, &result);
    return ok;
}

bool vk_probe_loop_limit(vk_context *ctx) {
    ctx->loop_limit = 0u;
    if (!vk_context_is_lavapipe(ctx)) return true;
    /* One loop longer than any budget: where it stops, the budget is what it completed. */
    const uint32_t n[2] = {VK_PROBE_REACH, 0u};
    uint32_t least[2], most[2];
    double t0 = clock_seconds();
    if (!vk_probe_loops(ctx, n, least, most)) return false;
    if (least[0] < VK_PROBE_REACH) ctx->loop_limit = least[0];
    if (ctx->loop_limit)
        log_debug("vulkan: loops stop silently after %u passes (probed in %.1f ms)",
                  ctx->loop_limit, (clock_seconds() - t0) * 1e3);
    else
        log_debug("vulkan: loops run to the end (%u passes probed in %.1f ms)", VK_PROBE_REACH,
                  (clock_seconds() - t0) * 1e3);
    return true;
}

uint64_t vk_probe_safe_iterations(uint32_t limit) {
    /* The margin keeps lavapipe 22.3's 60,000 of 65,535, the guard its tests prove. */
    return limit ? (uint64_t)limit * 60000u / 65535u : UINT64_MAX;
}

uint64_t vk_probe_sample_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                    bool indirect) {
    /* lavapipe spends one unit per pass of any loop, the pass that leaves the loop included. A
     * ray costs a pass per sphere, the sphere loop's exit pass and the pass of the loop that
     * casts it. A path casts at most bounces + 1 rays in follow_specular and one shadow ray per
     * light in direct_light, whose loop adds its exit pass; the indirect bounce is a second
     * path; main()'s sample loop adds a pass per sample. */
    uint64_t per_ray = (uint64_t)sphere_count + 2u;
    uint64_t path = ((uint64_t)bounces + 1u + light_count) * per_ray + 1u;
    return path * (indirect ? 2u : 1u) + 1u;
}

uint64_t vk_probe_path_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                  uint32_t light_samples, uint32_t emitter_count) {
    /* A ray costs as in report mode. The path loop runs a pass a vertex (bounces + 1, and one
     * spare); a diffuse vertex adds its light loop's passes and exit pass, the emitter loop's exit
     * pass, and for each emitter sample a pass of that loop, the binary search's passes
     * (ceil(log2(emitters)) and its exit) and the emitter's shadow ray. */
    uint64_t per_ray = (uint64_t)sphere_count + 2u;
    uint32_t search = 1u;
    while (emitter_count > 1u && (1u << (search - 1u)) < emitter_count && search < 32u) search++;
    uint64_t samples = emitter_count ? (light_samples > 1u ? light_samples : 1u) : 0u;
    uint64_t vertex = ((uint64_t)light_count + samples) * per_ray + 2u + samples * (search + 1u);
    return ((uint64_t)bounces + 2u) + ((uint64_t)bounces + 1u) * per_ray +
           (uint64_t)bounces * vertex + 1u;
}
