/* vk_instance.c: the Vulkan instance: layers and extensions asked for (validation, debug utils,
 * portability), the debug messenger's callback, and why an instance could not be created. */
#define _GNU_SOURCE /* dl_iterate_phdr, RTLD_NODELETE: see pin_loaded_libraries */
#include <dlfcn.h>
#include <link.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/vk/vk_internal.h"
#include "util/big_memory.h"
#include "util/log.h"

#define VALIDATION_LAYER "VK_LAYER_KHRONOS_validation"

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
        /* The first error is the most specific (a library that cannot be opened); later ones
         * only say that what needed it failed. */
        if ((severity & VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT) && !ctx->loader_error[0])
            snprintf(ctx->loader_error, sizeof ctx->loader_error, "%s", text);
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

/* The heap reserved before the first instance: lavapipe makes many small allocations setting up
 * llvmpipe, opening a device and compiling a pipeline, each first touch of a 4 KB page a fault
 * that a virtual machine charges microseconds (docs/PERF.md, "Vulkan set-up"). */
#define DRIVER_HEAP_RESERVE ((size_t)128 << 20)

static void reserve_driver_heap(void) { big_memory_reserve_heap(DRIVER_HEAP_RESERVE); }

VkResult vk_instance_create(const VkDebugUtilsMessengerCreateInfoEXT *messenger, VkInstance *out) {
    static pthread_once_t reserved = PTHREAD_ONCE_INIT;
    pthread_once(&reserved, reserve_driver_heap);
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
    /* The layer's manifest was found above, so its library failed to load (missing, of another
     * architecture, or missing a dependency): the loader told the messenger why. */
    if (messenger &&
        (result == VK_ERROR_LAYER_NOT_PRESENT || result == VK_ERROR_EXTENSION_NOT_PRESENT)) {
        const vk_context *ctx = messenger->pUserData;
        log_error(
            "validation was requested but %s could not be loaded: %s (its manifest is found "
            "through VK_LAYER_PATH or vulkan/explicit_layer.d; Debian: apt-get install --reinstall "
            "vulkan-validationlayers)",
            VALIDATION_LAYER, ctx->loader_error[0] ? ctx->loader_error : vk_result_name(result));
    }
#if defined(__SANITIZE_ADDRESS__)
    if (result == VK_SUCCESS) pin_loaded_libraries();
#endif
    return result;
}

void vk_instance_messenger_info(vk_context *ctx, VkDebugUtilsMessengerCreateInfoEXT *out) {
    *out = (VkDebugUtilsMessengerCreateInfoEXT){
        .sType = VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT,
        .messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT |
                           VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT,
        .messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                       VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT,
        .pfnUserCallback = on_debug_message,
        .pUserData = ctx,
    };
}
