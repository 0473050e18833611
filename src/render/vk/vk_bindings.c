/* vk_bindings.c: the table of trace.comp's bindings and what it drives (see vk_bindings.h). */
#include "render/vk/vk_bindings.h"

#include <string.h>

#include "render/vk/vk_strategy.h"

/* The bytes of one binding's buffer: `count` elements of `stride` bytes, an input's copied from
 * `data`, an output's (data NULL) written by the shader. A count of 0 makes one zeroed
 * element: the binding stays valid, and the shader reads none of it. */
typedef struct vk_bytes {
    const void *data;
    size_t count, stride;
} vk_bytes;

typedef struct vk_binding_row {
    VkDescriptorType kind;
    vk_bytes (*source)(const vk_binding_sources *s); /* NULL: no buffer (the acceleration
                                                        structure) */
    VkFormat format; /* a texel buffer's view; VK_FORMAT_UNDEFINED for other kinds */
} vk_binding_row;

static vk_bytes frame(const vk_binding_sources *s) {
    return (vk_bytes){&s->scene->frame, 1u, sizeof s->scene->frame};
}
static vk_bytes spheres(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->spheres, s->scene->frame.sphere_count, sizeof *s->scene->spheres};
}
static vk_bytes lights(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->lights, s->scene->frame.light_count, sizeof *s->scene->lights};
}
static vk_bytes nodes(const vk_binding_sources *s) {
    return (vk_bytes){s->nodes, s->node_count, sizeof *s->nodes};
}
static vk_bytes wide_nodes(const vk_binding_sources *s) {
    return (vk_bytes){s->wide_nodes, s->wide_node_count, sizeof *s->wide_nodes};
}
static vk_bytes emitters(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->emitters, s->scene->frame.emitter_count,
                      sizeof *s->scene->emitters};
}
static vk_bytes triangles(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->triangles, s->scene->frame.triangle_count,
                      sizeof *s->scene->triangles};
}
static vk_bytes materials(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->materials, s->scene->material_count, sizeof *s->scene->materials};
}
static vk_bytes normals(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->normals, s->scene->normals_count, sizeof *s->scene->normals};
}
static vk_bytes textures(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->texture_words, s->scene->texture_word_count,
                      sizeof *s->scene->texture_words};
}
static vk_bytes environment(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->environment, s->scene->environment_texels,
                      sizeof *s->scene->environment};
}
static vk_bytes instances(const vk_binding_sources *s) {
    return (vk_bytes){s->scene->instances, s->scene->frame.instance_count,
                      sizeof *s->scene->instances};
}
/* The part's sums and their compensation: a pixel each, rows padded to whole bands so that every
 * band binding stays inside the buffer. */
static vk_bytes pixels(const vk_binding_sources *s) {
    return (vk_bytes){NULL, (size_t)s->rows * s->width, ACCUM_PIXEL_BYTES};
}
static vk_bytes stacks(const vk_binding_sources *s) {
    return (vk_bytes){NULL, (size_t)s->rows * s->width * s->depth, STACK_BLOCK_BYTES};
}
static vk_bytes counters(const vk_binding_sources *s) {
    (void)s;
    return (vk_bytes){NULL, TZ_COUNTER_WORDS, sizeof(uint32_t)};
}

/* Scene data are uniform texel buffers (shared_layout.h says why), RGBA32F over the structs'
 * very bytes; the BVH nodes as uints, since child references are not floats (a GPU may flush
 * their denormal bits). The dynamic bindings are bound a band at a time. */
static const vk_binding_row table[VK_BINDINGS] = {
    [TZ_BINDING_FRAME] = {VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER, frame, VK_FORMAT_UNDEFINED},
    [TZ_BINDING_SPHERES] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, spheres,
                            VK_FORMAT_R32G32B32A32_SFLOAT},
    [TZ_BINDING_LIGHTS] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, lights,
                           VK_FORMAT_R32G32B32A32_SFLOAT},
    [TZ_BINDING_ACCUM] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC, pixels, VK_FORMAT_UNDEFINED},
    [TZ_BINDING_COUNTERS] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, counters, VK_FORMAT_UNDEFINED},
    [TZ_BINDING_NODES] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, nodes,
                          VK_FORMAT_R32G32B32A32_UINT},
    [TZ_BINDING_ACCUM_COMP] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC, pixels,
                               VK_FORMAT_UNDEFINED},
    [TZ_BINDING_EMITTERS] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, emitters,
                             VK_FORMAT_R32G32B32A32_SFLOAT},
    [TZ_BINDING_STACK] = {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC, stacks, VK_FORMAT_UNDEFINED},
    [TZ_BINDING_TRIANGLES] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, triangles,
                              VK_FORMAT_R32G32B32A32_SFLOAT},
    [TZ_BINDING_MATERIALS] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, materials,
                              VK_FORMAT_R32G32B32A32_SFLOAT},
    [TZ_BINDING_NORMALS] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, normals,
                            VK_FORMAT_R32G32B32A32_SFLOAT},
    [TZ_BINDING_WIDE_NODES] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, wide_nodes,
                               VK_FORMAT_R32G32B32A32_UINT},
    [TZ_BINDING_TEXTURES] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, textures, VK_FORMAT_R32_UINT},
    [TZ_BINDING_ENVIRONMENT] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, environment,
                                VK_FORMAT_R32G32B32A32_SFLOAT},
    [TZ_BINDING_INSTANCES] = {VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, instances,
                              VK_FORMAT_R32G32B32A32_UINT},
    [TZ_BINDING_ACCEL] = {VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, NULL, VK_FORMAT_UNDEFINED},
};
_Static_assert(VK_BINDINGS <= VK_KERNEL_MAX_BINDINGS, "raise VK_KERNEL_MAX_BINDINGS");

/* Whether the host writes a binding of this kind (an input: the kinds a shader only reads) or
 * the shader (the storage buffers). */
static bool is_input(VkDescriptorType kind) {
    return kind == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER ||
           kind == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER;
}

/* The buffer usage a binding of this kind needs: inputs are copied into (uploads); the shader's
 * outputs are copied from (read back) and into (a resumed part), and filled (zeroed). */
static VkBufferUsageFlags usage_of(VkDescriptorType kind) {
    if (kind == VK_DESCRIPTOR_TYPE_UNIFORM_BUFFER)
        return VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (kind == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER)
        return VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    return VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
           VK_BUFFER_USAGE_TRANSFER_DST_BIT;
}

/* Bytes of a source's buffer: at least one element. */
static size_t bytes_of(vk_bytes b) { return (b.count ? b.count : 1u) * b.stride; }

/* Writes a source's bytes at `to`: its elements, or the one zeroed element of an empty one. */
static void write_bytes(void *to, vk_bytes b) {
    if (b.count)
        memcpy(to, b.data, b.count * b.stride);
    else
        memset(to, 0, b.stride);
}

bool vk_bindings_create(vk_context *ctx, const vk_binding_sources *s, vk_buffer *buffers,
                        vk_buffer *upload) {
    bool mapped = true;
    size_t staged = 0;
    for (int k = 0; k < VK_BINDINGS; k++) {
        if (!table[k].source) continue;
        vk_bytes b = table[k].source(s);
        if (!vk_buffer_create(ctx, bytes_of(b), usage_of(table[k].kind), VK_MEMORY_DEVICE,
                              &buffers[k]) ||
            (table[k].format != VK_FORMAT_UNDEFINED &&
             !vk_buffer_create_view(ctx, &buffers[k], table[k].format)))
            return false;
        if (is_input(table[k].kind)) mapped &= buffers[k].mapped != NULL, staged += bytes_of(b);
    }
    if (!mapped &&
        !vk_buffer_create(ctx, staged, VK_BUFFER_USAGE_TRANSFER_SRC_BIT, VK_MEMORY_UPLOAD, upload))
        return false;
    size_t offset = 0;
    for (int k = 0; k < VK_BINDINGS; k++) {
        if (!table[k].source || !is_input(table[k].kind)) continue;
        vk_bytes b = table[k].source(s);
        write_bytes(mapped ? buffers[k].mapped : (char *)upload->mapped + offset, b);
        offset += bytes_of(b);
    }
    return true;
}

void vk_bindings_record_upload(VkCommandBuffer cmd, const vk_buffer *upload,
                               const vk_buffer *buffers) {
    if (!upload->buffer) return;
    VkDeviceSize offset = 0;
    for (int k = 0; k < VK_BINDINGS; k++) {
        if (!table[k].source || !is_input(table[k].kind)) continue;
        VkBufferCopy copy = {offset, 0, buffers[k].size};
        vkCmdCopyBuffer(cmd, upload->buffer, buffers[k].buffer, 1, &copy);
        offset += buffers[k].size;
    }
}

void vk_bindings_types(uint32_t count, VkDescriptorType *types) {
    for (uint32_t k = 0; k < count; k++) types[k] = table[k].kind;
}

void vk_bindings_bind(vk_context *ctx, vk_kernel *k, const vk_buffer *buffers, uint32_t rows) {
    const vk_buffer *bound[VK_BINDINGS];
    VkDeviceSize ranges[VK_BINDINGS];
    for (int n = 0; n < VK_BINDINGS; n++) {
        bound[n] = &buffers[n];
        ranges[n] = table[n].kind == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC
                        ? buffers[n].size / rows * TZ_BAND_ROWS
                        : VK_WHOLE_SIZE;
    }
    vk_kernel_bind(ctx, k, bound, ranges);
}

uint32_t vk_bindings_dynamic_offsets(const vk_buffer *buffers, uint32_t rows, uint32_t band_y0,
                                     uint32_t *offsets) {
    uint32_t count = 0;
    for (int k = 0; k < VK_BINDINGS; k++)
        if (table[k].kind == VK_DESCRIPTOR_TYPE_STORAGE_BUFFER_DYNAMIC)
            /* 32-bit, as Vulkan's dynamic offsets: check_limits keeps the buffers under 4 GiB. */
            offsets[count++] = band_y0 * (uint32_t)(buffers[k].size / rows);
    return count;
}

void vk_bindings_destroy(vk_context *ctx, vk_buffer *buffers) {
    for (int k = VK_BINDINGS - 1; k >= 0; k--) vk_buffer_destroy(ctx, &buffers[k]);
}
