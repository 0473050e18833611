/* vk_device.c: physical devices (what each offers, which is the default, the listing the user
 * sees) and the logical device, queue and command pool of a context. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"
#include "render/vk/vk_internal.h"
#include "util/log.h"

static bool has_device_extension(VkPhysicalDevice device, const char *name) {
    uint32_t count = 0;
    if (vkEnumerateDeviceExtensionProperties(device, NULL, &count, NULL) != VK_SUCCESS ||
        count == 0)
        return false;
    VkExtensionProperties *exts = calloc(count, sizeof *exts);
    bool found = false;
    if (exts && vkEnumerateDeviceExtensionProperties(device, NULL, &count, exts) >= 0)
        for (uint32_t k = 0; k < count && !found; k++) found = !strcmp(exts[k].extensionName, name);
    free(exts);
    return found;
}

/* The device extensions the ray query walk enables (the deferred host operations are a
 * requirement of VK_KHR_acceleration_structure). */
static const char *const RAY_QUERY_EXTENSIONS[] = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
                                                   VK_KHR_RAY_QUERY_EXTENSION_NAME,
                                                   VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};
#define RAY_QUERY_EXTENSION_COUNT 3

bool vk_device_has_ray_query(VkPhysicalDevice device) {
    VkPhysicalDeviceProperties props;
    vkGetPhysicalDeviceProperties(device, &props);
    if (props.apiVersion < VK_API_VERSION_1_2) return false;
    for (int k = 0; k < RAY_QUERY_EXTENSION_COUNT; k++)
        if (!has_device_extension(device, RAY_QUERY_EXTENSIONS[k])) return false;
    VkPhysicalDeviceRayQueryFeaturesKHR query = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
    VkPhysicalDeviceAccelerationStructureFeaturesKHR structure = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR,
        .pNext = &query};
    VkPhysicalDeviceVulkan12Features v12 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES, .pNext = &structure};
    VkPhysicalDeviceFeatures2 features = {.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2,
                                          .pNext = &v12};
    vkGetPhysicalDeviceFeatures2(device, &features);
    return query.rayQuery && structure.accelerationStructure && v12.bufferDeviceAddress;
}

/* What trazador needs to know of one physical device to list or choose it. */
typedef struct device_info {
    VkPhysicalDeviceProperties properties;
    VkPhysicalDeviceSubgroupProperties subgroup;
    VkDriverId driver_id;
    char driver_name[VK_MAX_DRIVER_NAME_SIZE];
    char driver_info[VK_MAX_DRIVER_INFO_SIZE];
    uint32_t compute_family; /* UINT32_MAX when the device has no compute queue */
    bool usable;             /* Vulkan 1.1 and a compute queue */
} device_info;

static void query_device(VkPhysicalDevice device, device_info *out) {
    *out = (device_info){.compute_family = UINT32_MAX};
    vkGetPhysicalDeviceProperties(device, &out->properties);
    /* Driver properties are core in 1.2 and an extension before: ask only when offered. */
    if (out->properties.apiVersion >= VK_API_VERSION_1_2 ||
        has_device_extension(device, VK_KHR_DRIVER_PROPERTIES_EXTENSION_NAME)) {
        VkPhysicalDeviceDriverProperties driver = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 props2 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &driver};
        vkGetPhysicalDeviceProperties2(device, &props2);
        out->driver_id = driver.driverID;
        memcpy(out->driver_name, driver.driverName, sizeof out->driver_name);
        memcpy(out->driver_info, driver.driverInfo, sizeof out->driver_info);
        out->driver_name[sizeof out->driver_name - 1] = '\0';
        out->driver_info[sizeof out->driver_info - 1] = '\0';
    }
    if (out->properties.apiVersion >= VK_API_VERSION_1_1) {
        out->subgroup = (VkPhysicalDeviceSubgroupProperties){
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
        VkPhysicalDeviceProperties2 props2 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &out->subgroup};
        vkGetPhysicalDeviceProperties2(device, &props2);
        out->subgroup.pNext = NULL;
    }
    uint32_t count = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(device, &count, NULL);
    VkQueueFamilyProperties *families = calloc(count ? count : 1, sizeof *families);
    if (families) {
        vkGetPhysicalDeviceQueueFamilyProperties(device, &count, families);
        for (uint32_t k = 0; k < count && out->compute_family == UINT32_MAX; k++)
            if (families[k].queueFlags & VK_QUEUE_COMPUTE_BIT) out->compute_family = k;
        free(families);
    }
    out->usable =
        out->properties.apiVersion >= VK_API_VERSION_1_1 && out->compute_family != UINT32_MAX;
}

/* Enumerates the instance's devices into a new array; false (nothing allocated) when none. */
static bool list_devices(VkInstance instance, VkPhysicalDevice **out, uint32_t *count) {
    *out = NULL;
    *count = 0;
    if (vkEnumeratePhysicalDevices(instance, count, NULL) < 0 || *count == 0) return false;
    *out = calloc(*count, sizeof **out);
    if (!*out || vkEnumeratePhysicalDevices(instance, count, *out) < 0 || *count == 0) {
        free(*out);
        *out = NULL;
        *count = 0;
        return false;
    }
    return true;
}

/* Index of the first usable device, -1 when none is. */
static int default_device(VkPhysicalDevice *devices, uint32_t count) {
    for (uint32_t k = 0; k < count; k++) {
        device_info info;
        query_device(devices[k], &info);
        if (info.usable) return (int)k;
    }
    return -1;
}

/* A bare instance for listing and counting; VK_NULL_HANDLE (nothing logged) when there is none. */
static VkInstance open_listing_instance(void) {
    VkInstance instance = VK_NULL_HANDLE;
    if (!vk_loader_ready() || vk_instance_create(NULL, &instance) != VK_SUCCESS)
        return VK_NULL_HANDLE;
    if (!vk_loader_load_instance(instance)) {
        PFN_vkDestroyInstance destroy =
            (PFN_vkDestroyInstance)vk_loader_proc(instance, "vkDestroyInstance");
        if (destroy) destroy(instance, NULL);
        return VK_NULL_HANDLE;
    }
    return instance;
}

/* The devices, counted and typed once for each driver setting of the loader's environment: each
 * listing opens an instance, which costs lavapipe tens of milliseconds, and auto asks for both. */
typedef struct device_census {
    bool taken;
    char drivers[1024]; /* the variables that choose the drivers, when it was taken */
    int count;
    bool cpu_only; /* every device a CPU; false with none */
} device_census;
static device_census census;
static pthread_mutex_t census_lock = PTHREAD_MUTEX_INITIALIZER;

/* The loader's driver variables, joined (cut to size: a census retaken in vain at worst). */
static void driver_setting(char *out, size_t size) {
    const char *names[] = {"VK_DRIVER_FILES", "VK_ICD_FILENAMES", "VK_ADD_DRIVER_FILES"};
    size_t at = 0;
    out[0] = '\0';
    for (size_t k = 0; k < sizeof names / sizeof names[0] && at < size; k++) {
        const char *v = getenv(names[k]);
        int n = snprintf(out + at, size - at, "%s\n", v ? v : "-");
        at += n > 0 ? (size_t)n : 0;
    }
}

static device_census take_census(void) {
    char drivers[sizeof census.drivers];
    driver_setting(drivers, sizeof drivers);
    pthread_mutex_lock(&census_lock);
    if (!census.taken || strcmp(census.drivers, drivers)) {
        census = (device_census){.taken = true};
        memcpy(census.drivers, drivers, sizeof drivers);
        VkInstance instance = open_listing_instance();
        VkPhysicalDevice *devices = NULL;
        uint32_t count = 0;
        bool cpu = instance && list_devices(instance, &devices, &count);
        for (uint32_t k = 0; k < count && cpu; k++) {
            device_info info;
            query_device(devices[k], &info);
            cpu = info.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
        }
        census.count = (int)count;
        census.cpu_only = cpu;
        free(devices);
        if (instance) vkDestroyInstance(instance, NULL);
    }
    device_census taken = census;
    pthread_mutex_unlock(&census_lock);
    return taken;
}

int vk_context_device_count(void) { return take_census().count; }

static const char *device_type_name(VkPhysicalDeviceType type) {
    switch (type) {
        case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU:
            return "integrated GPU";
        case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU:
            return "discrete GPU";
        case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU:
            return "virtual GPU";
        case VK_PHYSICAL_DEVICE_TYPE_CPU:
            return "CPU";
        default:
            return "other";
    }
}

/* The driver's own version: NVIDIA packs it 10.8.8.6 bits, the others (Mesa among them) as
 * VK_MAKE_VERSION; lavapipe always says 0.0.1, its release is in driverInfo. */
static void format_driver_version(const VkPhysicalDeviceProperties *p, char *out, size_t size) {
    uint32_t v = p->driverVersion;
    if (p->vendorID == 0x10DEu)
        snprintf(out, size, "%u.%u.%u.%u", v >> 22, (v >> 14) & 0xffu, (v >> 6) & 0xffu, v & 0x3fu);
    else
        snprintf(out, size, "%u.%u.%u", VK_VERSION_MAJOR(v), VK_VERSION_MINOR(v),
                 VK_VERSION_PATCH(v));
}

/* The second line of a device in the listing: driver version, the ray tracing extensions a ray
 * query walk would use, the walks trazador has that it offers (`render --walk`), and the loop
 * budget a context on it was probed to have. */
static void print_device_details(VkPhysicalDevice device, const device_info *info, int index) {
    char version[48];
    format_driver_version(&info->properties, version, sizeof version);
    bool query = has_device_extension(device, VK_KHR_RAY_QUERY_EXTENSION_NAME);
    bool structure = has_device_extension(device, VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME);
    char loops[96] = "not probed (unusable)";
    const char *walks = "none (unusable)";
    if (info->usable) {
        /* The loop probe needs a device of its own; its errors would only repeat the listing's. */
        vk_context ctx;
        vk_context_desc desc = {.device = index};
        log_hold_errors();
        bool opened = vk_context_init(&ctx, &desc);
        log_release_errors();
        if (!opened)
            snprintf(loops, sizeof loops, "not probed (the device does not open)");
        else if (ctx.loop_limit)
            snprintf(loops, sizeof loops, "stop silently after %u passes", ctx.loop_limit);
        else
            snprintf(loops, sizeof loops, "run to the end");
        /* The ray query walk needs loops that run to the end (its candidate loop is the
         * device's). */
        bool rq = opened && ctx.loop_limit == 0u && vk_device_has_ray_query(device);
        bool coop = opened && vk_context_has_subgroup_walk(&ctx);
        walks = !opened      ? "unknown"
                : coop && rq ? "compute, cooperative, rayquery"
                : coop       ? "compute, cooperative"
                : rq         ? "compute, rayquery"
                             : "compute";
        vk_context_destroy(&ctx);
    }
    printf("    driverVersion %s; %s %s; %s %s; walks: %s; loops %s\n", version,
           VK_KHR_RAY_QUERY_EXTENSION_NAME, query ? "yes" : "no",
           VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME, structure ? "yes" : "no", walks, loops);
}

bool vk_context_print_devices(void) {
    VkInstance instance = open_listing_instance();
    VkPhysicalDevice *devices = NULL;
    uint32_t count = 0;
    if (!instance || !list_devices(instance, &devices, &count)) {
        if (vk_loader_ready())
            log_error(RENDER_NO_VULKAN_DEVICE);
        else
            vk_loader_report();
        if (instance) vkDestroyInstance(instance, NULL);
        return false;
    }
    int chosen = default_device(devices, count);
    for (uint32_t k = 0; k < count; k++) {
        device_info info;
        query_device(devices[k], &info);
        uint32_t v = info.properties.apiVersion;
        printf("%c %u: %s (%s), driver %s%s%s, Vulkan %u.%u.%u%s\n", (int)k == chosen ? '*' : ' ',
               k, info.properties.deviceName, device_type_name(info.properties.deviceType),
               info.driver_name[0] ? info.driver_name : "(unnamed)", info.driver_info[0] ? " " : "",
               info.driver_info, VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v),
               VK_API_VERSION_PATCH(v),
               info.usable ? "" : " (unusable: needs Vulkan 1.1 and a compute queue)");
        print_device_details(devices[k], &info, (int)k);
    }
    if (chosen >= 0) printf("(* marks the device used when --device is not given)\n");
    free(devices);
    vkDestroyInstance(instance, NULL);
    return true;
}

bool vk_device_open(vk_context *ctx, int requested, bool ray_query) {
    VkPhysicalDevice *devices = NULL;
    uint32_t count = 0;
    if (!list_devices(ctx->instance, &devices, &count)) {
        log_error(RENDER_NO_VULKAN_DEVICE);
        return false;
    }
    int index = requested >= 0 ? requested : default_device(devices, count);
    if (requested >= (int)count) {
        log_error("--device %d is out of range: %u Vulkan device%s found (see `trazador devices`)",
                  requested, count, count == 1 ? "" : "s");
        free(devices);
        return false;
    }
    if (index < 0) {
        log_error(
            "no usable Vulkan device: none of the %u found has Vulkan 1.1 and a compute "
            "queue" RENDER_USE_CPU,
            count);
        free(devices);
        return false;
    }
    ctx->physical = devices[index];
    free(devices);
    device_info info;
    query_device(ctx->physical, &info);
    if (!info.usable) {
        log_error("Vulkan device %d (%s) is unusable: it needs Vulkan 1.1 and a compute queue",
                  index, info.properties.deviceName);
        return false;
    }
    ctx->device_index = index;
    ctx->properties = info.properties;
    ctx->driver_id = info.driver_id;
    ctx->subgroup = info.subgroup;
    memcpy(ctx->driver_name, info.driver_name, sizeof ctx->driver_name);
    memcpy(ctx->driver_info, info.driver_info, sizeof ctx->driver_info);
    ctx->queue_family = info.compute_family;
    vkGetPhysicalDeviceMemoryProperties(ctx->physical, &ctx->memory);

    float priority = 1.0f;
    VkDeviceQueueCreateInfo queue = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO,
        .queueFamilyIndex = ctx->queue_family,
        .queueCount = 1,
        .pQueuePriorities = &priority,
    };
    /* A portability (MoltenVK) device must have its subset extension enabled when it offers it. */
    const char *extensions[2 + RAY_QUERY_EXTENSION_COUNT];
    uint32_t extension_count = 0;
    const char *portability = "VK_KHR_portability_subset";
    if (has_device_extension(ctx->physical, portability))
        extensions[extension_count++] = portability;
    /* A CPU device reads the process's own memory: imported as the scene's buffers, it can be
     * on huge pages, which Mesa 25's memfd-backed device memory is not (vk_buffer.c). */
    ctx->host_import = 0;
    if (!ctx->no_import && info.properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU &&
        has_device_extension(ctx->physical, VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME)) {
        VkPhysicalDeviceExternalMemoryHostPropertiesEXT host = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_EXTERNAL_MEMORY_HOST_PROPERTIES_EXT};
        VkPhysicalDeviceProperties2 props2 = {
            .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, .pNext = &host};
        vkGetPhysicalDeviceProperties2(ctx->physical, &props2);
        VkDeviceSize a = host.minImportedHostPointerAlignment;
        if (a > 0 && (a & (a - 1)) == 0) {
            ctx->host_import = a;
            extensions[extension_count++] = VK_EXT_EXTERNAL_MEMORY_HOST_EXTENSION_NAME;
        }
    }
    ctx->ray_query = ray_query && vk_device_has_ray_query(ctx->physical);
    for (int k = 0; ctx->ray_query && k < RAY_QUERY_EXTENSION_COUNT; k++)
        extensions[extension_count++] = RAY_QUERY_EXTENSIONS[k];
    VkPhysicalDeviceRayQueryFeaturesKHR query = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR, .rayQuery = VK_TRUE};
    VkPhysicalDeviceAccelerationStructureFeaturesKHR structure = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR,
        .pNext = &query,
        .accelerationStructure = VK_TRUE};
    VkPhysicalDeviceVulkan12Features v12 = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES,
        .pNext = &structure,
        .bufferDeviceAddress = VK_TRUE};
    VkDeviceCreateInfo create_info = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .pNext = ctx->ray_query ? &v12 : NULL,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &queue,
        .enabledExtensionCount = extension_count,
        .ppEnabledExtensionNames = extensions,
    };
    if (!VK_CHECK(vkCreateDevice(ctx->physical, &create_info, NULL, &ctx->device))) return false;
    if (ctx->host_import) {
        ctx->host_pointer_properties = (PFN_vkGetMemoryHostPointerPropertiesEXT)vk_loader_proc(
            ctx->instance, "vkGetMemoryHostPointerPropertiesEXT");
        if (!ctx->host_pointer_properties) ctx->host_import = 0;
    }
    vkGetDeviceQueue(ctx->device, ctx->queue_family, 0, &ctx->queue);
    VkCommandPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = ctx->queue_family,
    };
    return VK_CHECK(vkCreateCommandPool(ctx->device, &pool, NULL, &ctx->command_pool));
}

bool vk_context_is_lavapipe(const vk_context *ctx) {
    return ctx->driver_id == VK_DRIVER_ID_MESA_LLVMPIPE;
}

bool vk_context_has_subgroup_walk(const vk_context *ctx) {
    const VkSubgroupFeatureFlags needed =
        VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
    /* The walk counts lanes in 6-bit fields (shaders/intersect.glsl, COOP_BITS). */
    return (ctx->subgroup.supportedOperations & needed) == needed &&
           (ctx->subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
           ctx->subgroup.subgroupSize >= 1u && ctx->subgroup.subgroupSize <= 63u;
}

bool vk_context_cpu_only(void) { return take_census().cpu_only; }
