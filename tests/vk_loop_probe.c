/* vk_loop_probe.c: runs tests/loop_probe.comp, which counts the loop iterations each
 * invocation really completes. */
#include "vk_loop_probe.h"

#include "loop_probe_spv.h"

bool vk_loop_probe_run(vk_context *ctx, const uint32_t n[2], uint32_t least[2], uint32_t most[2]) {
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
    const VkDeviceSize bytes = VK_LOOP_PROBE_INVOCATIONS * 2u * sizeof(uint32_t);
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
    vkCmdDispatch(cmd, VK_LOOP_PROBE_INVOCATIONS / 64u, 1, 1);
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
        for (uint32_t k = 0; k < VK_LOOP_PROBE_INVOCATIONS; k++) {
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
