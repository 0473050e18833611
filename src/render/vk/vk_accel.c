/* vk_accel.c: the ray query walk's acceleration structure (vk_accel.h). Every primitive is an
 * AABB, spheres and triangles alike, so that the shared tests of shaders/common/ray.h decide
 * every hit (the device's own triangle test would round differently from the watertight one),
 * and each box is padded past any rounding of the device's box test, so that the device reports
 * every primitive the shared test can hit. */
#include "render/vk/vk_accel.h"

#include <stdlib.h>
#include <string.h>

#include "render/vk/vk_accel_boxes.h"
#include "render/vk/vk_internal.h"
#include "util/log.h"

/* The ray tracing functions, which the loader only hands out by name (device extensions). */
typedef struct accel_functions {
    PFN_vkGetBufferDeviceAddress get_buffer_address;
    PFN_vkCreateAccelerationStructureKHR create;
    PFN_vkDestroyAccelerationStructureKHR destroy;
    PFN_vkGetAccelerationStructureBuildSizesKHR build_sizes;
    PFN_vkCmdBuildAccelerationStructuresKHR build;
    PFN_vkGetAccelerationStructureDeviceAddressKHR get_address;
} accel_functions;

static bool load_functions(vk_context *ctx, accel_functions *f) {
    f->get_buffer_address =
        (PFN_vkGetBufferDeviceAddress)vk_loader_proc(ctx->instance, "vkGetBufferDeviceAddress");
    f->create = (PFN_vkCreateAccelerationStructureKHR)vk_loader_proc(
        ctx->instance, "vkCreateAccelerationStructureKHR");
    f->destroy = (PFN_vkDestroyAccelerationStructureKHR)vk_loader_proc(
        ctx->instance, "vkDestroyAccelerationStructureKHR");
    f->build_sizes = (PFN_vkGetAccelerationStructureBuildSizesKHR)vk_loader_proc(
        ctx->instance, "vkGetAccelerationStructureBuildSizesKHR");
    f->build = (PFN_vkCmdBuildAccelerationStructuresKHR)vk_loader_proc(
        ctx->instance, "vkCmdBuildAccelerationStructuresKHR");
    f->get_address = (PFN_vkGetAccelerationStructureDeviceAddressKHR)vk_loader_proc(
        ctx->instance, "vkGetAccelerationStructureDeviceAddressKHR");
    bool ok = f->get_buffer_address && f->create && f->destroy && f->build_sizes && f->build &&
              f->get_address;
    if (!ok) log_error("the device offers ray queries but the loader lacks their functions");
    return ok;
}

static VkDeviceAddress buffer_address(const accel_functions *f, vk_context *ctx,
                                      const vk_buffer *b) {
    VkBufferDeviceAddressInfo info = {.sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO,
                                      .buffer = b->buffer};
    return f->get_buffer_address(ctx->device, &info);
}

/* The scratch alignment the device asks for (minAccelerationStructureScratchOffsetAlignment). */
static VkDeviceSize scratch_alignment(const vk_context *ctx) {
    VkPhysicalDeviceAccelerationStructurePropertiesKHR accel = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
    VkPhysicalDeviceProperties2 props = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
                                         .pNext = &accel};
    vkGetPhysicalDeviceProperties2(ctx->physical, &props);
    return accel.minAccelerationStructureScratchOffsetAlignment
               ? accel.minAccelerationStructureScratchOffsetAlignment
               : 1u;
}

/* Creates structure *out of `type` with storage for `info`'s build (its sizes in *sizes). */
static bool create_structure(vk_context *ctx, const accel_functions *f,
                             VkAccelerationStructureBuildGeometryInfoKHR *info, uint32_t count,
                             VkAccelerationStructureBuildSizesInfoKHR *sizes, vk_buffer *storage,
                             VkAccelerationStructureKHR *out) {
    *sizes = (VkAccelerationStructureBuildSizesInfoKHR){
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    f->build_sizes(ctx->device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, info, &count,
                   sizes);
    if (!vk_buffer_create(ctx, sizes->accelerationStructureSize,
                          VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR |
                              VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                          VK_MEMORY_DEVICE, storage))
        return false;
    VkAccelerationStructureCreateInfoKHR create = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR,
        .buffer = storage->buffer,
        .size = sizes->accelerationStructureSize,
        .type = info->type,
    };
    if (!VK_CHECK(f->create(ctx->device, &create, NULL, out))) return false;
    info->dstAccelerationStructure = *out;
    return true;
}

/* The build of one structure of `type` over one geometry, tuned for trace speed. */
static VkAccelerationStructureBuildGeometryInfoKHR build_info(
    VkAccelerationStructureTypeKHR type, const VkAccelerationStructureGeometryKHR *geometry) {
    return (VkAccelerationStructureBuildGeometryInfoKHR){
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
        .type = type,
        .flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR,
        .mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR,
        .geometryCount = 1,
        .pGeometries = geometry,
    };
}

/* The instances' custom index is 24 bits: 0 is the scene's own primitives. */
#define MAX_ACCEL_INSTANCES ((1u << 24) - 1u)

/* The AABB geometry of primitives r of the boxes at `boxes`. */
static VkAccelerationStructureGeometryKHR box_geometry(VkDeviceAddress boxes, accel_range r) {
    return (VkAccelerationStructureGeometryKHR){
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_AABBS_KHR,
        .geometry.aabbs = {.sType =
                               VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_AABBS_DATA_KHR,
                           .data.deviceAddress = boxes + r.first * sizeof(VkAabbPositionsKHR),
                           .stride = sizeof(VkAabbPositionsKHR)},
        /* The shader decides every candidate either way; opaque spares any-hit bookkeeping. */
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
}

/* The top level's instance of bottom structure `address`: identity for the scene's own
 * primitives (the device's ray stays the shader's), else instance i's rows. */
static VkAccelerationStructureInstanceKHR top_instance(const packed_scene *p, int i,
                                                       VkDeviceAddress address) {
    VkAccelerationStructureInstanceKHR in = {
        .transform.matrix = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}},
        .instanceCustomIndex = (uint32_t)(i + 1),
        .mask = 0xffu,
        .accelerationStructureReference = address,
    };
    for (int r = 0; i >= 0 && r < 3; r++) {
        const tz_vec4 *row = &p->instances[i].to_world[r];
        float m[4] = {row->x, row->y, row->z, row->w};
        memcpy(in.transform.matrix[r], m, sizeof m);
    }
    return in;
}

bool vk_accel_build(vk_context *ctx, const packed_scene *p, vk_accel *out) {
    *out = (vk_accel){0};
    accel_functions f;
    if (!load_functions(ctx, &f)) return false;
    uint32_t count = p->frame.sphere_count + p->frame.triangle_count;
    uint32_t instances = p->frame.instance_count;
    if (instances > MAX_ACCEL_INSTANCES - 1u) {
        log_error("the ray query walk takes at most %u instances, the scene has %u",
                  MAX_ACCEL_INSTANCES - 1u, instances);
        return false;
    }
    accel_range *ranges = NULL;
    uint32_t bottoms = accel_ranges(p, &ranges);
    if (!bottoms) return false;
    out->bottoms = calloc(bottoms, sizeof *out->bottoms);
    out->bottom_storage = calloc(bottoms, sizeof *out->bottom_storage);
    VkAccelerationStructureGeometryKHR *geometries = calloc(bottoms, sizeof *geometries);
    VkAccelerationStructureBuildGeometryInfoKHR *builds = calloc(bottoms, sizeof *builds);
    VkAccelerationStructureBuildRangeInfoKHR *build_ranges = calloc(bottoms, sizeof *build_ranges);
    VkDeviceAddress *addresses = calloc(bottoms, sizeof *addresses);
    bool ok =
        out->bottoms && out->bottom_storage && geometries && builds && build_ranges && addresses;
    if (!ok) log_error("out of memory for %u acceleration structures", bottoms);
    out->bottom_count = ok ? bottoms : 0u;
    const VkBufferUsageFlags input =
        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
        VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    ok = ok &&
         vk_buffer_create(ctx, (count ? count : 1u) * sizeof(VkAabbPositionsKHR), input,
                          VK_MEMORY_UPLOAD, &out->boxes) &&
         vk_buffer_create(ctx, (instances + 1u) * sizeof(VkAccelerationStructureInstanceKHR), input,
                          VK_MEMORY_UPLOAD, &out->instances) &&
         accel_fill_boxes(p, ranges, bottoms, out->boxes.mapped);

    /* The bottom level: one structure a range, the scratch the largest build's. */
    VkDeviceSize scratch = 0;
    VkDeviceAddress boxes_at = ok ? buffer_address(&f, ctx, &out->boxes) : 0;
    for (uint32_t b = 0; ok && b < bottoms; b++) {
        geometries[b] = box_geometry(boxes_at, ranges[b]);
        builds[b] = build_info(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, &geometries[b]);
        build_ranges[b] =
            (VkAccelerationStructureBuildRangeInfoKHR){.primitiveCount = ranges[b].count};
        VkAccelerationStructureBuildSizesInfoKHR sizes;
        ok = create_structure(ctx, &f, &builds[b], ranges[b].count, &sizes, &out->bottom_storage[b],
                              &out->bottoms[b]);
        if (sizes.buildScratchSize > scratch) scratch = sizes.buildScratchSize;
        VkAccelerationStructureDeviceAddressInfoKHR at = {
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR,
            .accelerationStructure = out->bottoms[b]};
        if (ok) addresses[b] = f.get_address(ctx->device, &at);
    }
    /* The top level: the scene's own primitives, then every instance. */
    uint32_t tops = 0;
    VkAccelerationStructureInstanceKHR *top_list = out->instances.mapped;
    if (ok && ranges[0].count > 0) top_list[tops++] = top_instance(p, -1, addresses[0]);
    for (uint32_t i = 0; ok && i < instances; i++)
        top_list[tops++] =
            top_instance(p, (int)i, addresses[accel_range_of(p, ranges, bottoms, i)]);
    VkAccelerationStructureGeometryKHR top_geometry = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR,
        .geometry.instances =
            {.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR,
             .data.deviceAddress = ok ? buffer_address(&f, ctx, &out->instances) : 0},
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
    VkAccelerationStructureBuildGeometryInfoKHR top =
        build_info(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, &top_geometry);
    VkAccelerationStructureBuildSizesInfoKHR top_sizes;
    ok = ok && create_structure(ctx, &f, &top, tops, &top_sizes, &out->top_storage, &out->top);
    if (ok && top_sizes.buildScratchSize > scratch) scratch = top_sizes.buildScratchSize;

    /* One scratch buffer for every build, in turn (a barrier between), aligned as asked. */
    VkDeviceSize align = scratch_alignment(ctx);
    ok = ok && vk_buffer_create(
                   ctx, scratch + align,
                   VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                   VK_MEMORY_DEVICE, &out->scratch);
    VkDeviceAddress scratch_at =
        ok ? (buffer_address(&f, ctx, &out->scratch) + align - 1u) / align * align : 0;
    VkAccelerationStructureBuildRangeInfoKHR top_range = {.primitiveCount = tops};
    const VkAccelerationStructureBuildRangeInfoKHR *top_ranges = &top_range;
    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkFenceCreateInfo fence_info = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    ok = ok && VK_CHECK(vkCreateFence(ctx->device, &fence_info, NULL, &fence)) &&
         vk_commands_begin(ctx, &cmd);
    if (ok) {
        const VkPipelineStageFlags build = VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
        const VkAccessFlags written = VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
        for (uint32_t b = 0; b < bottoms; b++) {
            const VkAccelerationStructureBuildRangeInfoKHR *one = &build_ranges[b];
            builds[b].scratchData.deviceAddress = scratch_at;
            f.build(cmd, 1, &builds[b], &one);
            vk_commands_barrier(cmd, build, written, build,
                                VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR | written);
        }
        top.scratchData.deviceAddress = scratch_at;
        f.build(cmd, 1, &top, &top_ranges);
        vk_commands_barrier(cmd, build, written, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
        ok = vk_commands_submit_wait(ctx, cmd, fence);
    }
    if (cmd) vkFreeCommandBuffers(ctx->device, ctx->command_pool, 1, &cmd);
    if (fence) vkDestroyFence(ctx->device, fence, NULL);
    free(ranges), free(geometries), free(builds), free(build_ranges), free(addresses);
    return ok;
}

void vk_accel_bind(vk_context *ctx, vk_kernel *k, uint32_t binding, const vk_accel *a) {
    VkWriteDescriptorSetAccelerationStructureKHR structure = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR,
        .accelerationStructureCount = 1,
        .pAccelerationStructures = &a->top,
    };
    VkWriteDescriptorSet write = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .pNext = &structure,
        .dstSet = k->set,
        .dstBinding = binding,
        .descriptorCount = 1,
        .descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &write, 0, NULL);
}

void vk_accel_destroy(vk_context *ctx, vk_accel *a) {
    PFN_vkDestroyAccelerationStructureKHR destroy =
        a->top || a->bottom_count ? (PFN_vkDestroyAccelerationStructureKHR)vk_loader_proc(
                                        ctx->instance, "vkDestroyAccelerationStructureKHR")
                                  : NULL;
    if (destroy && a->top) destroy(ctx->device, a->top, NULL);
    for (uint32_t b = 0; b < a->bottom_count; b++) {
        if (destroy && a->bottoms[b]) destroy(ctx->device, a->bottoms[b], NULL);
        vk_buffer_destroy(ctx, &a->bottom_storage[b]);
    }
    vk_buffer *buffers[] = {&a->scratch, &a->instances, &a->boxes, &a->top_storage};
    for (size_t k = 0; k < sizeof buffers / sizeof buffers[0]; k++)
        vk_buffer_destroy(ctx, buffers[k]);
    free(a->bottoms);
    free(a->bottom_storage);
    *a = (vk_accel){0};
}
