/* vk_kernel.c: compute kernels: one pipeline, its layout and one descriptor set of buffers. */
#include "render/vk/vk_context.h"
#include "util/log.h"

bool vk_kernel_create(vk_context *ctx, const vk_kernel_desc *desc, vk_kernel *out) {
    *out = (vk_kernel){0};
    if (desc->binding_count > VK_KERNEL_MAX_BINDINGS) {
        log_error("a kernel has at most %d bindings, got %u", VK_KERNEL_MAX_BINDINGS,
                  desc->binding_count);
        return false;
    }
    VkDescriptorSetLayoutBinding bindings[VK_KERNEL_MAX_BINDINGS];
    VkDescriptorPoolSize sizes[VK_KERNEL_MAX_BINDINGS];
    uint32_t size_count = 0;
    out->binding_count = desc->binding_count;
    for (uint32_t k = 0; k < desc->binding_count; k++) {
        out->types[k] = desc->types[k];
        bindings[k] = (VkDescriptorSetLayoutBinding){
            .binding = k,
            .descriptorType = desc->types[k],
            .descriptorCount = 1,
            .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
        };
        uint32_t s = 0;
        while (s < size_count && sizes[s].type != desc->types[k]) s++;
        if (s == size_count) sizes[size_count++] = (VkDescriptorPoolSize){desc->types[k], 0};
        sizes[s].descriptorCount++;
    }
    VkDescriptorSetLayoutCreateInfo set_info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = desc->binding_count,
        .pBindings = bindings,
    };
    VkPushConstantRange push = {VK_SHADER_STAGE_COMPUTE_BIT, 0, desc->push_size};
    VkShaderModuleCreateInfo module_info = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = desc->code_size,
        .pCode = desc->code,
    };
    VkShaderModule module = VK_NULL_HANDLE;
    if (!VK_CHECK(vkCreateDescriptorSetLayout(ctx->device, &set_info, NULL, &out->set_layout)))
        goto fail;
    VkPipelineLayoutCreateInfo layout_info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 1,
        .pSetLayouts = &out->set_layout,
        .pushConstantRangeCount = desc->push_size ? 1u : 0u,
        .pPushConstantRanges = &push,
    };
    if (!VK_CHECK(vkCreatePipelineLayout(ctx->device, &layout_info, NULL, &out->layout)) ||
        !VK_CHECK(vkCreateShaderModule(ctx->device, &module_info, NULL, &module)))
        goto fail;
    VkComputePipelineCreateInfo pipeline_info = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage =
            {
                .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                .module = module,
                .pName = "main",
                .pSpecializationInfo = desc->spec,
            },
        .layout = out->layout,
    };
    bool built = VK_CHECK(vkCreateComputePipelines(ctx->device, VK_NULL_HANDLE, 1, &pipeline_info,
                                                   NULL, &out->pipeline));
    vkDestroyShaderModule(ctx->device, module, NULL);
    if (!built) goto fail;
    VkDescriptorPoolCreateInfo pool_info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = 1,
        .poolSizeCount = size_count,
        .pPoolSizes = sizes,
    };
    VkDescriptorSetAllocateInfo set_alloc = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorSetCount = 1,
        .pSetLayouts = &out->set_layout,
    };
    if (!VK_CHECK(vkCreateDescriptorPool(ctx->device, &pool_info, NULL, &out->pool))) goto fail;
    set_alloc.descriptorPool = out->pool;
    if (!VK_CHECK(vkAllocateDescriptorSets(ctx->device, &set_alloc, &out->set))) goto fail;
    return true;
fail:
    vk_kernel_destroy(ctx, out);
    return false;
}

void vk_kernel_bind(vk_context *ctx, vk_kernel *k, const vk_buffer *const *buffers,
                    const VkDeviceSize *ranges) {
    VkDescriptorBufferInfo infos[VK_KERNEL_MAX_BINDINGS];
    VkWriteDescriptorSet writes[VK_KERNEL_MAX_BINDINGS];
    uint32_t count = 0;
    for (uint32_t n = 0; n < k->binding_count; n++) {
        /* Acceleration structures are no buffers: vk_accel_bind writes them. */
        if (k->types[n] == VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR) continue;
        bool texel = k->types[n] == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER ||
                     k->types[n] == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
        infos[n] = (VkDescriptorBufferInfo){buffers[n]->buffer, 0, ranges[n]};
        writes[count++] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = k->set,
            .dstBinding = n,
            .descriptorCount = 1,
            .descriptorType = k->types[n],
            .pBufferInfo = texel ? NULL : &infos[n],
            .pTexelBufferView = texel ? &buffers[n]->view : NULL,
        };
    }
    vkUpdateDescriptorSets(ctx->device, count, writes, 0, NULL);
}

void vk_kernel_destroy(vk_context *ctx, vk_kernel *k) {
    if (k->pool) vkDestroyDescriptorPool(ctx->device, k->pool, NULL);
    if (k->pipeline) vkDestroyPipeline(ctx->device, k->pipeline, NULL);
    if (k->layout) vkDestroyPipelineLayout(ctx->device, k->layout, NULL);
    if (k->set_layout) vkDestroyDescriptorSetLayout(ctx->device, k->set_layout, NULL);
    *k = (vk_kernel){0};
}
