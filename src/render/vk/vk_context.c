/* vk_context.c: opens the Vulkan loader at run time, owns the instance / messenger / device /
 * queue / command pool of a render (vkcube-style: one context, reverse-order teardown, validation
 * errors decide the outcome), lists devices, and builds buffers and compute kernels. */
#define _GNU_SOURCE /* dl_iterate_phdr, RTLD_NODELETE: see pin_loaded_libraries */
#include "render/vk/vk_context.h"

#include <dlfcn.h>
#include <inttypes.h>
#include <link.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/log.h"

#define VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"

#define VK_CONTEXT_DEFINE_FUNCTION(name) PFN_##name name;
VK_CONTEXT_GLOBAL_FUNCTIONS(VK_CONTEXT_DEFINE_FUNCTION)
VK_CONTEXT_INSTANCE_FUNCTIONS(VK_CONTEXT_DEFINE_FUNCTION)
#undef VK_CONTEXT_DEFINE_FUNCTION

static PFN_vkGetInstanceProcAddr get_instance_proc;
static pthread_once_t loader_once = PTHREAD_ONCE_INIT;

/* The VkResult's enumerant name, or "VK_RESULT_<number>" for one this build does not know. */
static const char *vk_result_name(VkResult result) {
    switch (result) {
#define NAME(r) \
    case r:     \
        return #r;
        NAME(VK_SUCCESS)
        NAME(VK_NOT_READY)
        NAME(VK_TIMEOUT)
        NAME(VK_EVENT_SET)
        NAME(VK_EVENT_RESET)
        NAME(VK_INCOMPLETE)
        NAME(VK_ERROR_OUT_OF_HOST_MEMORY)
        NAME(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        NAME(VK_ERROR_INITIALIZATION_FAILED)
        NAME(VK_ERROR_DEVICE_LOST)
        NAME(VK_ERROR_MEMORY_MAP_FAILED)
        NAME(VK_ERROR_LAYER_NOT_PRESENT)
        NAME(VK_ERROR_EXTENSION_NOT_PRESENT)
        NAME(VK_ERROR_FEATURE_NOT_PRESENT)
        NAME(VK_ERROR_INCOMPATIBLE_DRIVER)
        NAME(VK_ERROR_TOO_MANY_OBJECTS)
        NAME(VK_ERROR_FORMAT_NOT_SUPPORTED)
        NAME(VK_ERROR_FRAGMENTED_POOL)
        NAME(VK_ERROR_UNKNOWN)
        NAME(VK_ERROR_OUT_OF_POOL_MEMORY)
        NAME(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        NAME(VK_ERROR_FRAGMENTATION)
        NAME(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
        NAME(VK_PIPELINE_COMPILE_REQUIRED)
        NAME(VK_ERROR_VALIDATION_FAILED_EXT)
#undef NAME
        default: {
            /* Not reentrant, but only ever used to word a log line on the failing thread. */
            static _Thread_local char buffer[32];
            snprintf(buffer, sizeof buffer, "VK_RESULT_%d", (int)result);
            return buffer;
        }
    }
}

bool vk_check_result(VkResult result, const char *call, const char *file, int line) {
    if (result >= 0) return true;
    log_error("%s:%d: %s failed: %s", file, line, call, vk_result_name(result));
    return false;
}

/* dlsym hands back an object pointer; copying the bits is the POSIX way to a function pointer. */
static void loader_open(void) {
    static const char *const names[] = {"libvulkan.so.1", "libvulkan.so", "libvulkan.1.dylib"};
    for (size_t k = 0; k < sizeof names / sizeof names[0] && !get_instance_proc; k++) {
        void *handle = dlopen(names[k], RTLD_NOW | RTLD_LOCAL);
        if (!handle) continue;
        void *symbol = dlsym(handle, "vkGetInstanceProcAddr");
        if (symbol)
            memcpy(&get_instance_proc, &symbol, sizeof get_instance_proc);
        else
            dlclose(handle);
    }
    if (!get_instance_proc) return;
#define LOAD(name) name = (PFN_##name)get_instance_proc(VK_NULL_HANDLE, #name);
    VK_CONTEXT_GLOBAL_FUNCTIONS(LOAD)
#undef LOAD
    /* vkEnumerateInstanceVersion is missing from 1.0 loaders, which trazador cannot use. */
    if (!vkCreateInstance || !vkEnumerateInstanceVersion || !vkEnumerateInstanceLayerProperties ||
        !vkEnumerateInstanceExtensionProperties)
        get_instance_proc = NULL;
}

/* True when a Vulkan 1.1 loader was found and its global functions loaded. Logs nothing. */
static bool loader_ready(void) {
    pthread_once(&loader_once, loader_open);
    return get_instance_proc != NULL;
}

/* Instance-level pointers are loader trampolines that dispatch on their first argument, so any
 * instance can load them; they are reloaded for each new instance all the same. */
static bool load_instance_functions(VkInstance instance) {
    bool ok = true;
#define LOAD(name)                                                 \
    name = (PFN_##name)get_instance_proc(instance, #name);         \
    if (!name) {                                                   \
        log_error("the Vulkan loader does not provide %s", #name); \
        ok = false;                                                \
    }
    VK_CONTEXT_INSTANCE_FUNCTIONS(LOAD)
#undef LOAD
    return ok;
}

static bool has_layer(const char *name) {
    uint32_t count = 0;
    if (vkEnumerateInstanceLayerProperties(&count, NULL) != VK_SUCCESS || count == 0) return false;
    VkLayerProperties *layers = calloc(count, sizeof *layers);
    bool found = false;
    if (layers && vkEnumerateInstanceLayerProperties(&count, layers) >= 0)
        for (uint32_t k = 0; k < count && !found; k++) found = !strcmp(layers[k].layerName, name);
    free(layers);
    return found;
}

/* Whether an instance extension is offered by the loader and drivers, or by `layer` if given. */
static bool has_instance_extension(const char *layer, const char *name) {
    uint32_t count = 0;
    if (vkEnumerateInstanceExtensionProperties(layer, &count, NULL) != VK_SUCCESS || count == 0)
        return false;
    VkExtensionProperties *exts = calloc(count, sizeof *exts);
    bool found = false;
    if (exts && vkEnumerateInstanceExtensionProperties(layer, &count, exts) >= 0)
        for (uint32_t k = 0; k < count && !found; k++) found = !strcmp(exts[k].extensionName, name);
    free(exts);
    return found;
}

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

static VKAPI_ATTR VkBool32 VKAPI_CALL on_debug_message(
    VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
    const VkDebugUtilsMessengerCallbackDataEXT *data, void *user) {
    vk_context *ctx = user;
    const char *text = data && data->pMessage ? data->pMessage : "(no message)";
    /* General messages come from the loader (manifests, drivers), the others from the layer. */
    bool from_loader = !(types & (VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                                  VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT));
    const char *source = from_loader                                              ? "loader"
                         : types & VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT ? "validation"
                                                                                  : "performance";
    /* The loader's complaints (no driver, a bad manifest) end in a failed call, which says so in
     * one line: theirs are details for --verbose, and no validation error. */
    if (from_loader) {
        log_debug("Vulkan %s: %s", source, text);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) {
        atomic_fetch_add(&ctx->validation_errors, 1u);
        log_error("Vulkan %s: %s", source, text);
    } else if (severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) {
        log_warn("Vulkan %s: %s", source, text);
    } else {
        log_debug("Vulkan %s: %s", source, text);
    }
    return VK_FALSE; /* never abort the call: the error count decides the outcome */
}

#if defined(__SANITIZE_ADDRESS__)
/* The driver, LLVM and the validation layer keep some allocations past vkDestroyInstance, and the
 * loader unmaps them, after which LeakSanitizer cannot name their module and tests/lsan.supp
 * cannot match them. ASan builds keep every loaded library mapped to the end of the process. */
static int collect_library(struct dl_phdr_info *info, size_t size, void *names) {
    (void)size;
    char **list = names;
    for (int k = 0; k < 256; k++)
        if (!list[k]) return info->dlpi_name[0] ? (list[k] = strdup(info->dlpi_name), 0) : 0;
    return 1;
}

static void pin_loaded_libraries(void) {
    char *names[257] = {0}; /* dlopen is not called while dl_iterate_phdr holds its lock */
    dl_iterate_phdr(collect_library, names);
    for (int k = 0; names[k]; k++) {
        dlopen(names[k], RTLD_NOW | RTLD_NOLOAD | RTLD_NODELETE);
        free(names[k]);
    }
}
#endif

/* Creates an instance: Vulkan 1.1 or later, portability enumeration where offered (MoltenVK),
 * and with `messenger` (validation on) the Khronos layer, debug utils and synchronization
 * validation. Returns the VkResult; logs only the missing-validation case. */
static VkResult create_instance(const VkDebugUtilsMessengerCreateInfoEXT *messenger,
                                VkInstance *out) {
    uint32_t loader_version = 0;
    if (vkEnumerateInstanceVersion(&loader_version) != VK_SUCCESS ||
        loader_version < VK_API_VERSION_1_1)
        return VK_ERROR_INCOMPATIBLE_DRIVER;
    const char *extensions[3];
    uint32_t extension_count = 0;
    VkInstanceCreateFlags flags = 0;
    if (has_instance_extension(NULL, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME)) {
        extensions[extension_count++] = VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME;
        flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
    }
    const char *layers[] = {VALIDATION_LAYER};
    const void *next = NULL;
    VkValidationFeatureEnableEXT enables[] = {
        VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
    VkValidationFeaturesEXT features = {
        .sType = VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT,
        .pNext = messenger,
        .enabledValidationFeatureCount = 1,
        .pEnabledValidationFeatures = enables,
    };
    if (messenger) {
        /* A misspelt or missing layer would otherwise be skipped without a word by some
         * loaders: check that it is installed before asking for it. */
        if (!has_layer(VALIDATION_LAYER)) {
            log_error(
                "validation was requested but %s is not installed (Debian: apt-get install "
                "vulkan-validationlayers)",
                VALIDATION_LAYER);
            return VK_ERROR_LAYER_NOT_PRESENT;
        }
        if (!has_instance_extension(NULL, VK_EXT_DEBUG_UTILS_EXTENSION_NAME) &&
            !has_instance_extension(VALIDATION_LAYER, VK_EXT_DEBUG_UTILS_EXTENSION_NAME)) {
            log_error("validation was requested but %s is not available",
                      VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
            return VK_ERROR_EXTENSION_NOT_PRESENT;
        }
        extensions[extension_count++] = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        next = messenger;
        if (has_instance_extension(VALIDATION_LAYER, VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME)) {
            extensions[extension_count++] = VK_EXT_VALIDATION_FEATURES_EXTENSION_NAME;
            next = &features;
        }
    }
    VkApplicationInfo app = {
        .sType = VK_STRUCTURE_TYPE_APPLICATION_INFO,
        .pApplicationName = "trazador",
        .pEngineName = "trazador",
        .apiVersion = VK_API_VERSION_1_2,
    };
    VkInstanceCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO,
        .pNext = next,
        .flags = flags,
        .pApplicationInfo = &app,
        .enabledLayerCount = messenger ? 1u : 0u,
        .ppEnabledLayerNames = layers,
        .enabledExtensionCount = extension_count,
        .ppEnabledExtensionNames = extensions,
    };
    VkResult result = vkCreateInstance(&info, NULL, out);
#if defined(__SANITIZE_ADDRESS__)
    if (result == VK_SUCCESS) pin_loaded_libraries();
#endif
    return result;
}

/* What trazador needs to know of one physical device to list or choose it. */
typedef struct device_info {
    VkPhysicalDeviceProperties properties;
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
    if (!loader_ready() || create_instance(NULL, &instance) != VK_SUCCESS) return VK_NULL_HANDLE;
    if (!load_instance_functions(instance)) {
        PFN_vkDestroyInstance destroy =
            (PFN_vkDestroyInstance)get_instance_proc(instance, "vkDestroyInstance");
        if (destroy) destroy(instance, NULL);
        return VK_NULL_HANDLE;
    }
    return instance;
}

int vk_context_device_count(void) {
    VkInstance instance = open_listing_instance();
    if (!instance) return 0;
    uint32_t count = 0;
    if (vkEnumeratePhysicalDevices(instance, &count, NULL) < 0) count = 0;
    vkDestroyInstance(instance, NULL);
    return (int)count;
}

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

bool vk_context_print_devices(void) {
    VkInstance instance = open_listing_instance();
    VkPhysicalDevice *devices = NULL;
    uint32_t count = 0;
    if (!instance || !list_devices(instance, &devices, &count)) {
        log_error(VK_CONTEXT_NO_DEVICE_MESSAGE);
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
    }
    if (chosen >= 0) printf("(* marks the device used when --device is not given)\n");
    free(devices);
    vkDestroyInstance(instance, NULL);
    return true;
}

/* TRAZADOR_VALIDATE=1 (or any value but "" and "0") forces validation on. */
static bool env_flag(const char *name) {
    const char *value = getenv(name);
    return value && *value && strcmp(value, "0") != 0;
}

/* Picks the physical device and creates the logical device, queue and command pool. */
static bool open_device(vk_context *ctx, int requested) {
    VkPhysicalDevice *devices = NULL;
    uint32_t count = 0;
    if (!list_devices(ctx->instance, &devices, &count)) {
        log_error(VK_CONTEXT_NO_DEVICE_MESSAGE);
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
            "queue" VK_CONTEXT_USE_CPU,
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
    memcpy(ctx->driver_name, info.driver_name, sizeof ctx->driver_name);
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
    const char *portability = "VK_KHR_portability_subset";
    bool subset = has_device_extension(ctx->physical, portability);
    VkDeviceCreateInfo create_info = {
        .sType = VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO,
        .queueCreateInfoCount = 1,
        .pQueueCreateInfos = &queue,
        .enabledExtensionCount = subset ? 1u : 0u,
        .ppEnabledExtensionNames = &portability,
    };
    if (!VK_CHECK(vkCreateDevice(ctx->physical, &create_info, NULL, &ctx->device))) return false;
    vkGetDeviceQueue(ctx->device, ctx->queue_family, 0, &ctx->queue);
    VkCommandPoolCreateInfo pool = {
        .sType = VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO,
        .flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT,
        .queueFamilyIndex = ctx->queue_family,
    };
    return VK_CHECK(vkCreateCommandPool(ctx->device, &pool, NULL, &ctx->command_pool));
}

bool vk_context_init(vk_context *ctx, const vk_context_desc *desc) {
    *ctx = (vk_context){.device_index = -1};
    atomic_init(&ctx->validation_errors, 0u);
    ctx->validate = desc->validate || env_flag("TRAZADOR_VALIDATE");
    ctx->force_staging = env_flag("TRAZADOR_VK_STAGING");
    if (!loader_ready()) {
        log_error(VK_CONTEXT_NO_DEVICE_MESSAGE);
        return false;
    }
    VkDebugUtilsMessengerCreateInfoEXT messenger = {
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_debug_message,
        .pUserData = ctx,
    };
    VkResult result = create_instance(ctx->validate ? &messenger : NULL, &ctx->instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
        log_error(VK_CONTEXT_NO_DEVICE_MESSAGE);
        return false;
    }
    if (result != VK_SUCCESS) {
        /* A broken driver manifest makes the loader fail with an unrelated code (out of host
         * memory for a JSON syntax error): the code alone would mislead. */
        if (result != VK_ERROR_LAYER_NOT_PRESENT && result != VK_ERROR_EXTENSION_NOT_PRESENT)
            log_error(
                "cannot start Vulkan: vkCreateInstance failed with %s (a broken driver "
                "manifest in VK_ICD_FILENAMES, VK_DRIVER_FILES or vulkan/icd.d can do this; "
                "VK_LOADER_DEBUG=all shows the loader's reasons)" VK_CONTEXT_USE_CPU,
                vk_result_name(result));
        ctx->instance = VK_NULL_HANDLE;
        return false;
    }
    if (!load_instance_functions(ctx->instance)) goto fail;
    if (ctx->validate) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)get_instance_proc(ctx->instance,
                                                                  "vkCreateDebugUtilsMessengerEXT");
        ctx->destroy_messenger = (PFN_vkDestroyDebugUtilsMessengerEXT)get_instance_proc(
            ctx->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (!create || !ctx->destroy_messenger) {
            log_error("validation was requested but the debug messenger could not be loaded");
            goto fail;
        }
        if (!VK_CHECK(create(ctx->instance, &messenger, NULL, &ctx->messenger))) goto fail;
    }
    if (!open_device(ctx, desc->device)) goto fail;
    return true;
fail:
    vk_context_destroy(ctx);
    return false;
}

bool vk_context_destroy(vk_context *ctx) {
    if (ctx->device) {
        VK_CHECK(vkDeviceWaitIdle(ctx->device)); /* teardown goes on either way */
        if (ctx->command_pool) vkDestroyCommandPool(ctx->device, ctx->command_pool, NULL);
        vkDestroyDevice(ctx->device, NULL);
    }
    if (ctx->messenger) ctx->destroy_messenger(ctx->instance, ctx->messenger, NULL);
    if (ctx->instance) vkDestroyInstance(ctx->instance, NULL);
    unsigned errors = atomic_load(&ctx->validation_errors);
    *ctx = (vk_context){.device_index = -1};
    atomic_init(&ctx->validation_errors, errors);
    return errors == 0;
}

unsigned vk_context_validation_errors(vk_context *ctx) {
    return atomic_load(&ctx->validation_errors);
}

bool vk_context_is_lavapipe(const vk_context *ctx) {
    return ctx->driver_id == VK_DRIVER_ID_MESA_LLVMPIPE;
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

bool vk_buffer_create(vk_context *ctx, VkDeviceSize size, VkBufferUsageFlags usage,
                      vk_memory_use use, vk_buffer *out) {
    *out = (vk_buffer){.size = size};
    VkBufferCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = size,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    if (!VK_CHECK(vkCreateBuffer(ctx->device, &info, NULL, &out->buffer))) return false;
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx->device, out->buffer, &req);
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
    VkMemoryAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .allocationSize = req.size,
        .memoryTypeIndex = (uint32_t)type,
    };
    if (!VK_CHECK(vkAllocateMemory(ctx->device, &alloc, NULL, &out->memory)) ||
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
    if (b->mapped) vkUnmapMemory(ctx->device, b->memory);
    if (b->buffer) vkDestroyBuffer(ctx->device, b->buffer, NULL);
    if (b->memory) vkFreeMemory(ctx->device, b->memory, NULL);
    *b = (vk_buffer){0};
}

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
    for (uint32_t n = 0; n < k->binding_count; n++) {
        bool texel = k->types[n] == VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER ||
                     k->types[n] == VK_DESCRIPTOR_TYPE_STORAGE_TEXEL_BUFFER;
        infos[n] = (VkDescriptorBufferInfo){buffers[n]->buffer, 0, ranges[n]};
        writes[n] = (VkWriteDescriptorSet){
            .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
            .dstSet = k->set,
            .dstBinding = n,
            .descriptorCount = 1,
            .descriptorType = k->types[n],
            .pBufferInfo = texel ? NULL : &infos[n],
            .pTexelBufferView = texel ? &buffers[n]->view : NULL,
        };
    }
    vkUpdateDescriptorSets(ctx->device, k->binding_count, writes, 0, NULL);
}

void vk_kernel_destroy(vk_context *ctx, vk_kernel *k) {
    if (k->pool) vkDestroyDescriptorPool(ctx->device, k->pool, NULL);
    if (k->pipeline) vkDestroyPipeline(ctx->device, k->pipeline, NULL);
    if (k->layout) vkDestroyPipelineLayout(ctx->device, k->layout, NULL);
    if (k->set_layout) vkDestroyDescriptorSetLayout(ctx->device, k->set_layout, NULL);
    *k = (vk_kernel){0};
}

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
