/* vk_accel.c: the ray query walk's acceleration structure (vk_accel.h). Every primitive is an
 * AABB, spheres and triangles alike, so that the shared tests of shaders/common/ray.h decide
 * every hit (the device's own triangle test would round differently from the watertight one),
 * and each box is padded past any rounding of the device's box test, so that the device reports
 * every primitive the shared test can hit. */
#include "render/vk/vk_accel.h"

#include <math.h>
#include <string.h>

#include "render/vk/vk_internal.h"
#include "util/log.h"

/* Padding of a box, as a share of the largest coordinate a ray or the box can have: 2^-16 is
 * 128 float ulps, far past the few roundings of a slab test (position errors of a few ulps of
 * the ray origin and the box, which a padding widens every slab by at least as much). */
#define BOX_PAD_SHARE (1.0 / 65536.0)

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

static double max_abs3(double x, double y, double z) {
    return fmax(fabs(x), fmax(fabs(y), fabs(z)));
}

/* The exact box of primitive k (spheres first, then triangles), in double. */
static void primitive_box(const packed_scene *p, uint32_t k, double lo[3], double hi[3]) {
    if (k < p->frame.sphere_count) {
        const tz_vec4 *c = &p->spheres[k].center_radius;
        double centre[3] = {c->x, c->y, c->z};
        for (int a = 0; a < 3; a++) lo[a] = centre[a] - c->w, hi[a] = centre[a] + c->w;
        return;
    }
    const struct gpu_triangle *t = &p->triangles[k - p->frame.sphere_count];
    const tz_vec4 *v[3] = {&t->v0, &t->v1, &t->v2};
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (int c = 0; c < 3; c++) {
        double x[3] = {v[c]->x, v[c]->y, v[c]->z};
        for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], x[a]), hi[a] = fmax(hi[a], x[a]);
    }
}

/* x as a float no greater (down) or no less than it. */
static float round_out(double x, bool down) {
    float f = (float)x;
    if (down && (double)f > x) return nextafterf(f, -INFINITY);
    if (!down && (double)f < x) return nextafterf(f, INFINITY);
    return f;
}

/* Fills `boxes` with every primitive's box, padded by BOX_PAD_SHARE of the largest coordinate
 * a ray may start from (the camera's, or any point of any primitive) plus the box's own. */
static void fill_boxes(const packed_scene *p, uint32_t count, VkAabbPositionsKHR *boxes) {
    const tz_vec4 *eye = &p->frame.origin;
    double reach = max_abs3(eye->x, eye->y, eye->z) + fabs((double)p->frame.near_distance);
    for (uint32_t k = 0; k < count; k++) {
        double lo[3], hi[3];
        primitive_box(p, k, lo, hi);
        reach = fmax(reach, fmax(max_abs3(lo[0], lo[1], lo[2]), max_abs3(hi[0], hi[1], hi[2])));
    }
    for (uint32_t k = 0; k < count; k++) {
        double lo[3], hi[3];
        primitive_box(p, k, lo, hi);
        double own = fmax(max_abs3(lo[0], lo[1], lo[2]), max_abs3(hi[0], hi[1], hi[2]));
        double pad = BOX_PAD_SHARE * fmax(reach + own, 1.0);
        boxes[k] =
            (VkAabbPositionsKHR){round_out(lo[0] - pad, true),  round_out(lo[1] - pad, true),
                                 round_out(lo[2] - pad, true),  round_out(hi[0] + pad, false),
                                 round_out(hi[1] + pad, false), round_out(hi[2] + pad, false)};
    }
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

bool vk_accel_build(vk_context *ctx, const packed_scene *p, vk_accel *out) {
    *out = (vk_accel){0};
    accel_functions f;
    if (!load_functions(ctx, &f)) return false;
    uint32_t count = p->frame.sphere_count + p->frame.triangle_count;
    const VkBufferUsageFlags input =
        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
        VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;
    if (!vk_buffer_create(ctx, (count ? count : 1u) * sizeof(VkAabbPositionsKHR), input,
                          VK_MEMORY_UPLOAD, &out->boxes) ||
        !vk_buffer_create(ctx, sizeof(VkAccelerationStructureInstanceKHR), input, VK_MEMORY_UPLOAD,
                          &out->instance))
        return false;
    fill_boxes(p, count, out->boxes.mapped);

    VkAccelerationStructureGeometryKHR boxes = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_AABBS_KHR,
        .geometry.aabbs = {.sType =
                               VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_AABBS_DATA_KHR,
                           .data.deviceAddress = buffer_address(&f, ctx, &out->boxes),
                           .stride = sizeof(VkAabbPositionsKHR)},
        /* The shader decides every candidate either way; opaque spares any-hit bookkeeping. */
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
    VkAccelerationStructureBuildGeometryInfoKHR bottom =
        build_info(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, &boxes);
    VkAccelerationStructureBuildSizesInfoKHR bottom_sizes, top_sizes;
    if (!create_structure(ctx, &f, &bottom, count, &bottom_sizes, &out->bottom_storage,
                          &out->bottom))
        return false;
    VkAccelerationStructureDeviceAddressInfoKHR bottom_address = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR,
        .accelerationStructure = out->bottom};
    /* The identity transform: the device's ray stays the shader's, bit for bit. */
    VkAccelerationStructureInstanceKHR instance = {
        .transform.matrix = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}},
        .mask = 0xffu,
        .accelerationStructureReference = f.get_address(ctx->device, &bottom_address),
    };
    memcpy(out->instance.mapped, &instance, sizeof instance);
    VkAccelerationStructureGeometryKHR instances = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR,
        .geometry.instances =
            {.sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR,
             .data.deviceAddress = buffer_address(&f, ctx, &out->instance)},
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
    VkAccelerationStructureBuildGeometryInfoKHR top =
        build_info(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, &instances);
    if (!create_structure(ctx, &f, &top, 1u, &top_sizes, &out->top_storage, &out->top))
        return false;

    /* One scratch buffer for both builds, in turn (a barrier between), aligned as asked. */
    VkDeviceSize align = scratch_alignment(ctx);
    VkDeviceSize scratch = bottom_sizes.buildScratchSize > top_sizes.buildScratchSize
                               ? bottom_sizes.buildScratchSize
                               : top_sizes.buildScratchSize;
    if (!vk_buffer_create(
            ctx, scratch + align,
            VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
            VK_MEMORY_DEVICE, &out->scratch))
        return false;
    VkDeviceAddress scratch_at =
        (buffer_address(&f, ctx, &out->scratch) + align - 1u) / align * align;
    bottom.scratchData.deviceAddress = scratch_at;
    top.scratchData.deviceAddress = scratch_at;
    VkAccelerationStructureBuildRangeInfoKHR bottom_range = {.primitiveCount = count};
    VkAccelerationStructureBuildRangeInfoKHR top_range = {.primitiveCount = 1u};
    const VkAccelerationStructureBuildRangeInfoKHR *bottom_ranges = &bottom_range;
    const VkAccelerationStructureBuildRangeInfoKHR *top_ranges = &top_range;

    VkCommandBuffer cmd = VK_NULL_HANDLE;
    VkFence fence = VK_NULL_HANDLE;
    VkFenceCreateInfo fence_info = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (!VK_CHECK(vkCreateFence(ctx->device, &fence_info, NULL, &fence))) return false;
    bool ok = vk_commands_begin(ctx, &cmd);
    if (ok) {
        const VkPipelineStageFlags build = VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
        f.build(cmd, 1, &bottom, &bottom_ranges);
        vk_commands_barrier(cmd, build, VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR, build,
                            VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                                VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR);
        f.build(cmd, 1, &top, &top_ranges);
        vk_commands_barrier(cmd, build, VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                            VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
        ok = vk_commands_submit_wait(ctx, cmd, fence);
    }
    if (cmd) vkFreeCommandBuffers(ctx->device, ctx->command_pool, 1, &cmd);
    vkDestroyFence(ctx->device, fence, NULL);
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
        a->top || a->bottom ? (PFN_vkDestroyAccelerationStructureKHR)vk_loader_proc(
                                  ctx->instance, "vkDestroyAccelerationStructureKHR")
                            : NULL;
    if (destroy && a->top) destroy(ctx->device, a->top, NULL);
    if (destroy && a->bottom) destroy(ctx->device, a->bottom, NULL);
    vk_buffer *buffers[] = {&a->scratch, &a->instance, &a->boxes, &a->top_storage,
                            &a->bottom_storage};
    for (size_t k = 0; k < sizeof buffers / sizeof buffers[0]; k++)
        vk_buffer_destroy(ctx, buffers[k]);
    *a = (vk_accel){0};
}
