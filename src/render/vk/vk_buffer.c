/* vk_buffer.c: buffers with their own memory, placed by how they are used, and their views; and
 * the file-size limit check of drivers that keep device memory in a file. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"
#include "render/vk/vk_context.h"
#include "util/big_memory.h"
#include "util/log.h"

#ifdef __linux__
#include <dirent.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* Room left in the file for the driver's own allocations after a buffer (command buffers,
 * descriptor sets: a page each). */
#define MEMORY_FILE_HEADROOM (1u << 20)

/* Bytes of the largest memfd lavapipe keeps device memory in (Mesa 25's llvmpipe names it
 * "allocation fd"; Mesa 22.3 has none): -1 when the process has none. */
static int64_t memory_file_bytes(void) {
    DIR *dir = opendir("/proc/self/fd");
    if (!dir) return -1;
    int64_t largest = -1;
    for (struct dirent *e; (e = readdir(dir)) != NULL;) {
        char path[300], target[64];
        snprintf(path, sizeof path, "/proc/self/fd/%s", e->d_name);
        ssize_t n = readlink(path, target, sizeof target - 1);
        if (n <= 0) continue;
        target[n] = '\0';
        struct stat st;
        if (strncmp(target, "/memfd:allocation fd", 20) == 0 && stat(path, &st) == 0 &&
            (int64_t)st.st_size > largest)
            largest = (int64_t)st.st_size;
    }
    closedir(dir);
    return largest;
}
#endif

bool vk_memory_file_fits(uint64_t bytes) {
#ifdef __linux__
    /* The limit caps memfds as it caps files; the driver ignores the ftruncate that fails
     * (EFBIG), maps past the file's end anyway and dies with SIGBUS on the first touch. */
    struct rlimit limit;
    if (getrlimit(RLIMIT_FSIZE, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return true;
    int64_t held = memory_file_bytes();
    uint64_t pages = (bytes + 4095u) / 4096u * 4096u;
    if (held < 0 || (uint64_t)held + pages + MEMORY_FILE_HEADROOM <= (uint64_t)limit.rlim_cur)
        return true;
    log_error(
        "lavapipe keeps device memory in a memfd, which the file-size limit (ulimit -f) "
        "caps at %" PRIu64 " bytes: it holds %" PRId64 " and would need %" PRIu64
        " more, past which the driver crashes (SIGBUS); raise the limit" RENDER_USE_CPU,
        (uint64_t)limit.rlim_cur, held, pages + MEMORY_FILE_HEADROOM);
    return false;
#else
    (void)bytes;
    return true;
#endif
}

/* First memory type allowed by type_bits with all of `required`, preferring `preferred` too;
 * -1 when none. */
static int find_memory_type(const vk_context *ctx, uint32_t type_bits,
                            VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) {
    for (int pass = 0; pass < 2; pass++) {
        VkMemoryPropertyFlags want = pass == 0 ? required | preferred : required;
        for (uint32_t k = 0; k < ctx->memory.memoryTypeCount; k++)
            if ((type_bits & (1u << k)) &&
                (ctx->memory.memoryTypes[k].propertyFlags & want) == want)
                return (int)k;
    }
    return -1;
}

/* Whether the device imports the process's memory as a buffer of this usage. */
static bool imports_host_memory(const vk_context *ctx, VkBufferUsageFlags usage) {
    VkPhysicalDeviceExternalBufferInfo info = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_BUFFER_INFO,
        .usage = usage,
        .handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT};
    VkExternalBufferProperties props = {.sType = VK_STRUCTURE_TYPE_EXTERNAL_BUFFER_PROPERTIES};
    vkGetPhysicalDeviceExternalBufferProperties(ctx->physical, &info, &props);
    return (props.externalMemoryProperties.externalMemoryFeatures &
            VK_EXTERNAL_MEMORY_FEATURE_IMPORTABLE_BIT) != 0;
}

/* Binds the process's own memory to out (created for host allocations), on huge pages where it
 * is big enough to hold one: a CPU device reads it in place. */
static bool bind_host_memory(vk_context *ctx, const VkMemoryRequirements *req, vk_buffer *out) {
    VkDeviceSize align = big_alignment(
        (size_t)req->size,
        (size_t)(ctx->host_import > req->alignment ? ctx->host_import : req->alignment));
    VkDeviceSize bytes = (req->size + align - 1) / align * align;
    out->host = aligned_alloc((size_t)align, (size_t)bytes);
    if (!out->host) {
        log_error("out of memory for a buffer of %" PRIu64 " bytes", (uint64_t)bytes);
        return false;
    }
    big_memory_advise(out->host, (size_t)bytes);
    VkMemoryHostPointerPropertiesEXT props = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_HOST_POINTER_PROPERTIES_EXT};
    if (!VK_CHECK(ctx->host_pointer_properties(
            ctx->device, VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT, out->host,
            &props)))
        return false;
    int type =
        find_memory_type(ctx, req->memoryTypeBits & props.memoryTypeBits,
                         VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT,
                         VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
    if (type < 0) {
        log_error("no Vulkan memory type imports a buffer of %" PRIu64 " bytes", (uint64_t)bytes);
        return false;
    }
    VkImportMemoryHostPointerInfoEXT import = {
        .sType = VK_STRUCTURE_TYPE_IMPORT_MEMORY_HOST_POINTER_INFO_EXT,
        .handleType = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT,
        .pHostPointer = out->host};
    VkMemoryAllocateInfo alloc = {.sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
                                  .pNext = &import,
                                  .allocationSize = bytes,
                                  .memoryTypeIndex = (uint32_t)type};
    if (!VK_CHECK(vkAllocateMemory(ctx->device, &alloc, NULL, &out->memory)) ||
        !VK_CHECK(vkBindBufferMemory(ctx->device, out->buffer, out->memory, 0)))
        return false;
    out->mapped = out->host;
    return true;
}

bool vk_buffer_create(vk_context *ctx, VkDeviceSize size, VkBufferUsageFlags usage,
                      vk_memory_use use, vk_buffer *out) {
    *out = (vk_buffer){.size = size};
    /* A CPU device's device memory may sit in shared memory (Mesa 25's lavapipe: a memfd),
     * which gets no huge pages where the kernel keeps them from shared memory (Debian's
     * default), so that filling a big scene's buffers costs set-up time, and which the
     * file-size limit caps: the process's own memory is imported instead (docs/PERF.md). */
    bool import = use == VK_MEMORY_DEVICE && ctx->host_import && !ctx->force_staging &&
                  (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) == 0 &&
                  imports_host_memory(ctx, usage);
    VkExternalMemoryBufferCreateInfo external = {
        .sType = VK_STRUCTURE_TYPE_EXTERNAL_MEMORY_BUFFER_CREATE_INFO,
        .handleTypes = VK_EXTERNAL_MEMORY_HANDLE_TYPE_HOST_ALLOCATION_BIT_EXT};
    VkBufferCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .pNext = import ? &external : NULL,
        .size = size,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    if (!VK_CHECK(vkCreateBuffer(ctx->device, &info, NULL, &out->buffer))) return false;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx->device, out->buffer, &req);
    if (import) {
        if (bind_host_memory(ctx, &req, out)) return true;
        vk_buffer_destroy(ctx, out);
        return false;
    }
    const VkMemoryPropertyFlags host =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    int type =
        use == VK_MEMORY_DEVICE
            ? find_memory_type(ctx, req.memoryTypeBits, 0, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT)
            : find_memory_type(ctx, req.memoryTypeBits, host,
                               use == VK_MEMORY_READBACK ? VK_MEMORY_PROPERTY_HOST_CACHED_BIT : 0);
    if (type < 0) {
        log_error("no Vulkan memory type fits a %s buffer of %" PRIu64 " bytes",
                  use == VK_MEMORY_DEVICE ? "device" : "staging", (uint64_t)size);
        vk_buffer_destroy(ctx, out);
        return false;
    }
    /* Buffers read through device addresses (acceleration structure builds) need memory that
     * has them. */
    VkMemoryAllocateFlagsInfo address = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO,
        .flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT,
    };
    VkMemoryAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .pNext = (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) ? &address : NULL,
        .allocationSize = req.size,
        .memoryTypeIndex = (uint32_t)type,
    };
    if (!vk_memory_file_fits(req.size) ||
        !VK_CHECK(vkAllocateMemory(ctx->device, &alloc, NULL, &out->memory)) ||
        !VK_CHECK(vkBindBufferMemory(ctx->device, out->buffer, out->memory, 0))) {
        vk_buffer_destroy(ctx, out);
        return false;
    }
    /* Device memory is used in place only when reading it back is cheap: host-cached and
     * coherent (lavapipe, integrated GPUs); a discrete GPU's BAR goes through staging. */
    VkMemoryPropertyFlags flags = ctx->memory.memoryTypes[type].propertyFlags;
    bool map = use != VK_MEMORY_DEVICE ||
               (!ctx->force_staging && (flags & (host | VK_MEMORY_PROPERTY_HOST_CACHED_BIT)) ==
                                           (host | VK_MEMORY_PROPERTY_HOST_CACHED_BIT));
    if (map &&
        !VK_CHECK(vkMapMemory(ctx->device, out->memory, 0, VK_WHOLE_SIZE, 0, &out->mapped))) {
        vk_buffer_destroy(ctx, out);
        return false;
    }
    /* lavapipe's memory is the process's own, untouched, and written whole (uploads, the
     * part's sums): mapped at once, on huge pages where they apply (Mesa 22.3's; 25's is shared
     * memory). */
    if (map) big_memory_advise(out->mapped, req.size);
    return true;
}

bool vk_buffer_create_view(vk_context *ctx, vk_buffer *b, VkFormat format) {
    VkBufferViewCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO,
        .buffer = b->buffer,
        .format = format,
        .range = VK_WHOLE_SIZE,
    };
    return VK_CHECK(vkCreateBufferView(ctx->device, &info, NULL, &b->view));
}

void vk_buffer_destroy(vk_context *ctx, vk_buffer *b) {
    if (b->view) vkDestroyBufferView(ctx->device, b->view, NULL);
    if (b->mapped && !b->host) vkUnmapMemory(ctx->device, b->memory);
    if (b->buffer) vkDestroyBuffer(ctx->device, b->buffer, NULL);
    if (b->memory) vkFreeMemory(ctx->device, b->memory, NULL);
    free(b->host); /* after the memory imported from it */
    *b = (vk_buffer){0};
}
