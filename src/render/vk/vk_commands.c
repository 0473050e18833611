/* vk_commands.c: one-shot command buffers: begin, submit and wait (validation deciding the
 * outcome), and the global barrier between stages. */
#include "render/vk/vk_context.h"
#include "util/log.h"

bool vk_commands_begin(vk_context *ctx, VkCommandBuffer *cmd) {
    if (!*cmd) {
        VkCommandBufferAllocateInfo info = {
            .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO,
            .commandPool = ctx->command_pool,
            .level = VK_COMMAND_BUFFER_LEVEL_PRIMARY,
            .commandBufferCount = 1,
        };
        if (!VK_CHECK(vkAllocateCommandBuffers(ctx->device, &info, cmd))) {
            *cmd = VK_NULL_HANDLE;
            return false;
        }
    }
    VkCommandBufferBeginInfo begin = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO,
        .flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT,
    };
    return VK_CHECK(vkBeginCommandBuffer(*cmd, &begin));
}

bool vk_commands_submit_wait(vk_context *ctx, VkCommandBuffer cmd, VkFence fence) {
    VkSubmitInfo submit = {
        .sType = VK_STRUCTURE_TYPE_SUBMIT_INFO,
        .commandBufferCount = 1,
        .pCommandBuffers = &cmd,
    };
    if (!VK_CHECK(vkEndCommandBuffer(cmd)) || !VK_CHECK(vkResetFences(ctx->device, 1, &fence)) ||
        !VK_CHECK(vkQueueSubmit(ctx->queue, 1, &submit, fence)) ||
        !VK_CHECK(vkWaitForFences(ctx->device, 1, &fence, VK_TRUE, UINT64_MAX)))
        return false;
    unsigned errors = vk_context_validation_errors(ctx);
    if (errors)
        log_error("stopping after %u Vulkan validation error%s", errors, errors == 1 ? "" : "s");
    return errors == 0;
}

void vk_commands_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage,
                         VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                         VkAccessFlags dst_access) {
    VkMemoryBarrier barrier = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = src_access,
        .dstAccessMask = dst_access,
    };
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 1, &barrier, 0, NULL, 0, NULL);
}
