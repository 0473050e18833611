/* vk_loader.c: opens the Vulkan loader at run time (so that a machine without Vulkan still runs
 * the CPU back end), holds the function pointers loaded through it, and names VkResults. */
#include <dlfcn.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/vk/vk_internal.h"
#include "util/log.h"

#define VK_CONTEXT_DEFINE_FUNCTION(name) PFN_##name name;
VK_CONTEXT_GLOBAL_FUNCTIONS(VK_CONTEXT_DEFINE_FUNCTION)
VK_CONTEXT_INSTANCE_FUNCTIONS(VK_CONTEXT_DEFINE_FUNCTION)
#undef VK_CONTEXT_DEFINE_FUNCTION

static PFN_vkGetInstanceProcAddr get_instance_proc;
static pthread_once_t loader_once = PTHREAD_ONCE_INIT;

/* The VkResult's enumerant name, or "VK_RESULT_<number>" for one this build does not know. */
const char *vk_result_name(VkResult result) {
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

/* dlerror's text for the last name that failed to open, for --verbose. */
static char loader_error[512];

/* TRAZADOR_VK_LOADER names the one loader to open instead (a loader outside the library path;
 * the tests use it to run without one). dlsym hands back an object pointer; copying the bits is
 * the POSIX way to a function pointer. */
static void loader_open(void) {
    static const char *const names[] = {"libvulkan.so.1", "libvulkan.so", "libvulkan.1.dylib"};
    const char *chosen = getenv("TRAZADOR_VK_LOADER");
    size_t name_count = chosen && *chosen ? 1 : sizeof names / sizeof names[0];
    for (size_t k = 0; k < name_count && !get_instance_proc; k++) {
        const char *name = chosen && *chosen ? chosen : names[k];
        void *handle = dlopen(name, RTLD_NOW | RTLD_LOCAL);
        if (!handle) {
            const char *why = dlerror();
            if (k == 0) snprintf(loader_error, sizeof loader_error, "%s", why ? why : name);
            continue;
        }
        void *symbol = dlsym(handle, "vkGetInstanceProcAddr");
        if (symbol) {
            memcpy(&get_instance_proc, &symbol, sizeof get_instance_proc);
        } else {
            snprintf(loader_error, sizeof loader_error, "%s has no vkGetInstanceProcAddr", name);
            dlclose(handle);
        }
    }
    if (!get_instance_proc) return;
#define LOAD(name) name = (PFN_##name)get_instance_proc(VK_NULL_HANDLE, #name);
    VK_CONTEXT_GLOBAL_FUNCTIONS(LOAD)
#undef LOAD
    /* vkEnumerateInstanceVersion is missing from 1.0 loaders, which trazador cannot use. */
    if (!vkCreateInstance || !vkEnumerateInstanceVersion || !vkEnumerateInstanceLayerProperties ||
        !vkEnumerateInstanceExtensionProperties) {
        snprintf(loader_error, sizeof loader_error, "the Vulkan loader is older than Vulkan 1.1");
        get_instance_proc = NULL;
    }
}

bool vk_loader_ready(void) {
    pthread_once(&loader_once, loader_open);
    return get_instance_proc != NULL;
}

void vk_loader_report(void) {
    const char *chosen = getenv("TRAZADOR_VK_LOADER");
    log_error(
        "cannot open the Vulkan loader %s: install it (Debian: apt-get install libvulkan1 "
        "mesa-vulkan-drivers) or use --backend cpu",
        chosen && *chosen ? chosen : "libvulkan.so.1");
    log_debug("Vulkan loader: %s", loader_error);
}

PFN_vkVoidFunction vk_loader_proc(VkInstance instance, const char *name) {
    return get_instance_proc ? get_instance_proc(instance, name) : NULL;
}

/* Instance-level pointers are loader trampolines that dispatch on their first argument, so any
 * instance can load them; they are reloaded for each new instance all the same. */
bool vk_loader_load_instance(VkInstance instance) {
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
