/* vk_context.h: the Vulkan layer the renderer uses: the functions loaded from the loader
 * (vk_loader.c), one context (instance, validation messenger, device, compute queue, command
 * pool: vk_context.c, vk_instance.c, vk_device.c), device listing, buffers (vk_buffer.c), compute
 * kernels (vk_kernel.c), one-shot command buffers (vk_commands.c), and VK_CHECK. */
#ifndef TRAZADOR_VK_CONTEXT_H
#define TRAZADOR_VK_CONTEXT_H

#ifndef VK_NO_PROTOTYPES
#define VK_NO_PROTOTYPES
#endif
#include <stdatomic.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

/* Every Vulkan function trazador calls, loaded through vkGetInstanceProcAddr. */
#define VK_CONTEXT_GLOBAL_FUNCTIONS(X)    \
    X(vkCreateInstance)                   \
    X(vkEnumerateInstanceVersion)         \
    X(vkEnumerateInstanceLayerProperties) \
    X(vkEnumerateInstanceExtensionProperties)
#define VK_CONTEXT_INSTANCE_FUNCTIONS(X)           \
    X(vkDestroyInstance)                           \
    X(vkEnumeratePhysicalDevices)                  \
    X(vkGetPhysicalDeviceProperties)               \
    X(vkGetPhysicalDeviceProperties2)              \
    X(vkGetPhysicalDeviceExternalBufferProperties) \
    X(vkGetPhysicalDeviceFeatures2)                \
    X(vkGetPhysicalDeviceQueueFamilyProperties)    \
    X(vkGetPhysicalDeviceMemoryProperties)         \
    X(vkEnumerateDeviceExtensionProperties)        \
    X(vkCreateDevice)                              \
    X(vkDestroyDevice)                             \
    X(vkGetDeviceQueue)                            \
    X(vkDeviceWaitIdle)                            \
    X(vkQueueSubmit)                               \
    X(vkCreateCommandPool)                         \
    X(vkDestroyCommandPool)                        \
    X(vkAllocateCommandBuffers)                    \
    X(vkFreeCommandBuffers)                        \
    X(vkBeginCommandBuffer)                        \
    X(vkEndCommandBuffer)                          \
    X(vkCreateFence)                               \
    X(vkDestroyFence)                              \
    X(vkWaitForFences)                             \
    X(vkResetFences)                               \
    X(vkCreateBuffer)                              \
    X(vkDestroyBuffer)                             \
    X(vkCreateBufferView)                          \
    X(vkDestroyBufferView)                         \
    X(vkGetBufferMemoryRequirements)               \
    X(vkAllocateMemory)                            \
    X(vkFreeMemory)                                \
    X(vkBindBufferMemory)                          \
    X(vkMapMemory)                                 \
    X(vkUnmapMemory)                               \
    X(vkCreateShaderModule)                        \
    X(vkDestroyShaderModule)                       \
    X(vkCreateDescriptorSetLayout)                 \
    X(vkDestroyDescriptorSetLayout)                \
    X(vkCreatePipelineLayout)                      \
    X(vkDestroyPipelineLayout)                     \
    X(vkCreateComputePipelines)                    \
    X(vkDestroyPipeline)                           \
    X(vkCreateDescriptorPool)                      \
    X(vkDestroyDescriptorPool)                     \
    X(vkAllocateDescriptorSets)                    \
    X(vkUpdateDescriptorSets)                      \
    X(vkCmdBindPipeline)                           \
    X(vkCmdBindDescriptorSets)                     \
    X(vkCmdPushConstants)                          \
    X(vkCmdDispatch)                               \
    X(vkCmdPipelineBarrier)                        \
    X(vkCmdFillBuffer)                             \
    X(vkCmdCopyBuffer)

#define VK_CONTEXT_DECLARE_FUNCTION(name) extern PFN_##name name;
VK_CONTEXT_GLOBAL_FUNCTIONS(VK_CONTEXT_DECLARE_FUNCTION)
VK_CONTEXT_INSTANCE_FUNCTIONS(VK_CONTEXT_DECLARE_FUNCTION)
#undef VK_CONTEXT_DECLARE_FUNCTION

/* Checks a VkResult, always on: logs the failing call, its result name and where; true on
 * VK_SUCCESS (and the other non-negative results). Use as `if (!VK_CHECK(vkX(...))) goto fail;`. */
#define VK_CHECK(call) vk_check_result((call), #call, __FILE__, __LINE__)
bool vk_check_result(VkResult result, const char *call, const char *file, int line);

typedef struct vk_context_desc {
    int device;     /* physical device index; -1 picks the first usable one */
    bool validate;  /* validation layer + messenger; also forced on by TRAZADOR_VALIDATE=1 */
    bool ray_query; /* enable ray queries and acceleration structures where the device has them */
    int threads;    /* lavapipe's worker threads (LP_NUM_THREADS for this context); 0 leaves the
                       driver's choice or the user's own LP_NUM_THREADS */
} vk_context_desc;

typedef struct vk_context {
    VkInstance instance;
    VkDebugUtilsMessengerEXT messenger;
    PFN_vkDestroyDebugUtilsMessengerEXT destroy_messenger;
    VkPhysicalDevice physical;
    VkPhysicalDeviceProperties properties;
    VkPhysicalDeviceMemoryProperties memory;
    VkDriverId driver_id; /* 0 when the device cannot tell (Vulkan 1.1 without the extension) */
    char driver_name[VK_MAX_DRIVER_NAME_SIZE];
    char driver_info[VK_MAX_DRIVER_INFO_SIZE];   /* the version string, e.g. "Mesa 25.0.7" */
    VkPhysicalDeviceSubgroupProperties subgroup; /* size, operations and stages (Vulkan 1.1) */
    bool ray_query; /* ray queries and acceleration structures enabled (vk_context_desc) */
    VkDeviceSize host_import; /* VK_EXT_external_memory_host enabled on a CPU device: the
                                 alignment of imported host memory; 0 when not */
    PFN_vkGetMemoryHostPointerPropertiesEXT host_pointer_properties;
    uint32_t loop_limit; /* loop passes an invocation completes before the driver stops its loops
                            silently (lavapipe 22.3: 65,535); 0 where they run to the end
                            (vk_probe_loop_limit) */
    int device_index;
    VkDevice device;
    uint32_t queue_family;
    VkQueue queue;
    VkCommandPool command_pool;
    bool validate;
    bool force_staging; /* TRAZADOR_VK_STAGING=1: copy through staging buffers even when
                           device memory is mappable, to exercise the discrete-GPU path */
    bool no_import;     /* TRAZADOR_VK_NO_IMPORT=1: the driver's own device memory even where the
                           process's could be imported (host_import), for the path of devices
                           without the extension */
    atomic_uint validation_errors;
    char loader_error[512]; /* the loader's first complaint while the instance was created */
} vk_context;

/* Creates the whole context; false (one logged error, e.g. the no-device message) on failure,
 * with whatever was created already destroyed. */
bool vk_context_init(vk_context *ctx, const vk_context_desc *desc);
/* Destroys everything in reverse order; safe on a zeroed or partly initialized context.
 * Returns false when the validation layer reported any error during the context's life. */
bool vk_context_destroy(vk_context *ctx);
/* Number of validation errors reported so far; never fails. */
unsigned vk_context_validation_errors(vk_context *ctx);
/* True when the device is Mesa's lavapipe (llvmpipe), whose loops had an iteration budget up to
 * Mesa 22.3 (ctx->loop_limit says whether this one has); never fails. */
bool vk_context_is_lavapipe(const vk_context *ctx);

/* True when compute shaders on the device have the subgroup operations the cooperative BVH walk
 * uses (basic, arithmetic) in subgroups of at most 63 lanes; never fails. */
bool vk_context_has_subgroup_walk(const vk_context *ctx);
/* True when the physical device can walk an acceleration structure with ray queries: Vulkan
 * 1.2, VK_KHR_ray_query, VK_KHR_acceleration_structure (and its deferred host operations), and
 * the rayQuery, accelerationStructure and bufferDeviceAddress features; never fails. */
bool vk_device_has_ray_query(VkPhysicalDevice device);
/* True when there are Vulkan devices and every one is a CPU (VK_PHYSICAL_DEVICE_TYPE_CPU, e.g.
 * lavapipe); false when there is none or a GPU. Logs nothing. */
bool vk_context_cpu_only(void);

/* Number of Vulkan physical devices; 0 when there is no loader, driver or device. Logs nothing. */
int vk_context_device_count(void);
/* Prints every device (index, name, type, driver and its version, whether it offers
 * VK_KHR_ray_query and VK_KHR_acceleration_structure, its probed loop budget), marking the
 * default; false when none. */
bool vk_context_print_devices(void);

/* Where a buffer lives: DEVICE is read and written by shaders (mapped as well when that memory
 * is host-visible, coherent and cached, as on lavapipe and integrated GPUs); UPLOAD and READBACK
 * are host-visible staging buffers. */
typedef enum vk_memory_use { VK_MEMORY_DEVICE, VK_MEMORY_UPLOAD, VK_MEMORY_READBACK } vk_memory_use;

typedef struct vk_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    void *mapped;      /* NULL when the host cannot see the memory: copy through staging */
    void *host;        /* the process's memory imported as the buffer's (vk_context.host_import),
                          freed with it; NULL otherwise */
    VkBufferView view; /* for texel-buffer bindings, from vk_buffer_create_view */
} vk_buffer;

/* Creates a buffer with its own memory; false (logged) on failure, with nothing left behind. */
bool vk_buffer_create(vk_context *ctx, VkDeviceSize size, VkBufferUsageFlags usage,
                      vk_memory_use use, vk_buffer *out);
/* False (logged) when the driver keeps device memory in a memfd (lavapipe of Mesa 25) that the
 * file-size limit (RLIMIT_FSIZE, `ulimit -f`) leaves too small for `bytes` more and the driver's
 * own allocations: the driver would die of SIGBUS. True without such a file or limit. */
bool vk_memory_file_fits(uint64_t bytes);
/* Gives the buffer a view of the whole of it in `format`; false (logged) on failure. */
bool vk_buffer_create_view(vk_context *ctx, vk_buffer *b, VkFormat format);
/* Destroys the buffer (and its view) and frees its memory; safe on a zeroed vk_buffer. */
void vk_buffer_destroy(vk_context *ctx, vk_buffer *b);

#define VK_KERNEL_MAX_BINDINGS 17

/* One compute pipeline with one descriptor set of buffers (binding k has types[k]). */
typedef struct vk_kernel_desc {
    const uint32_t *code;
    size_t code_size; /* bytes */
    const VkDescriptorType *types;
    uint32_t binding_count;
    uint32_t push_size;               /* bytes of push constants, 0 for none */
    const VkSpecializationInfo *spec; /* optional */
} vk_kernel_desc;

typedef struct vk_kernel {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkPipeline pipeline;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkDescriptorType types[VK_KERNEL_MAX_BINDINGS];
    uint32_t binding_count;
} vk_kernel;

/* Builds the pipeline and allocates its descriptor set; false (logged) on failure, with nothing
 * left behind. */
bool vk_kernel_create(vk_context *ctx, const vk_kernel_desc *desc, vk_kernel *out);
/* Points binding k at buffers[k] (ranges[k] bytes from offset 0, VK_WHOLE_SIZE for all; texel
 * buffers through their view), for every binding; never fails (misuse surfaces through
 * validation). */
void vk_kernel_bind(vk_context *ctx, vk_kernel *k, const vk_buffer *const *buffers,
                    const VkDeviceSize *ranges);
/* Destroys the kernel; safe on a zeroed vk_kernel. */
void vk_kernel_destroy(vk_context *ctx, vk_kernel *k);

/* Begins *cmd for one submission, first allocating it from the context's pool when it is
 * VK_NULL_HANDLE (a recorded buffer is reset and reused); false (logged) on failure. */
bool vk_commands_begin(vk_context *ctx, VkCommandBuffer *cmd);
/* Ends, submits and waits for cmd with fence (reset first), then checks validation; false
 * (logged) on any failure or on a validation error reported meanwhile. */
bool vk_commands_submit_wait(vk_context *ctx, VkCommandBuffer cmd, VkFence fence);
/* Records one global memory barrier between two stages; never fails. */
void vk_commands_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage,
                         VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                         VkAccessFlags dst_access);

#endif
