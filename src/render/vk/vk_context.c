/* vk_context.c: a render's context (vkcube-style): instance, messenger, device, queue and
 * command pool created in order and torn down in reverse, validation errors deciding the
 * outcome. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/render.h"
#include "render/vk/vk_internal.h"
#include "render/vk/vk_probe.h"
#include "util/log.h"

/* TRAZADOR_VALIDATE=1 (or any value but "" and "0") forces validation on. */
static bool env_flag(const char *name) {
    const char *value = getenv(name);
    return value && *value && strcmp(value, "0") != 0;
}

/* vk_context_init but for the thread setting. */
static bool open_context(vk_context *ctx, const vk_context_desc *desc) {
    *ctx = (vk_context){.device_index = -1};
    atomic_init(&ctx->validation_errors, 0u);
    ctx->validate = desc->validate || env_flag("TRAZADOR_VALIDATE");
    ctx->force_staging = env_flag("TRAZADOR_VK_STAGING");
    ctx->no_import = env_flag("TRAZADOR_VK_NO_IMPORT");
    if (!vk_loader_ready()) {
        vk_loader_report();
        return false;
    }
    VkDebugUtilsMessengerCreateInfoEXT messenger;
    vk_instance_messenger_info(ctx, &messenger);
    VkResult result = vk_instance_create(ctx->validate ? &messenger : NULL, &ctx->instance);
    if (result == VK_ERROR_INCOMPATIBLE_DRIVER) {
        log_error(RENDER_NO_VULKAN_DEVICE);
        return false;
    }
    if (result != VK_SUCCESS) {
        /* A broken driver manifest makes the loader fail with an unrelated code (out of host
         * memory for a JSON syntax error): the code alone would mislead. vk_instance_create
         * has said why a layer or extension is missing. */
        if (result != VK_ERROR_LAYER_NOT_PRESENT && result != VK_ERROR_EXTENSION_NOT_PRESENT)
            log_error(
                "cannot start Vulkan: vkCreateInstance failed with %s (a broken driver "
                "manifest in VK_ICD_FILENAMES, VK_DRIVER_FILES or vulkan/icd.d can do this; "
                "VK_LOADER_DEBUG=all shows the loader's reasons)" RENDER_USE_CPU,
                vk_result_name(result));
        ctx->instance = VK_NULL_HANDLE;
        return false;
    }
    if (!vk_loader_load_instance(ctx->instance)) goto fail;
    if (ctx->validate) {
        PFN_vkCreateDebugUtilsMessengerEXT create =
            (PFN_vkCreateDebugUtilsMessengerEXT)vk_loader_proc(ctx->instance,
                                                               "vkCreateDebugUtilsMessengerEXT");
        ctx->destroy_messenger = (PFN_vkDestroyDebugUtilsMessengerEXT)vk_loader_proc(
            ctx->instance, "vkDestroyDebugUtilsMessengerEXT");
        if (!create || !ctx->destroy_messenger) {
            log_error("validation was requested but the debug messenger could not be loaded");
            goto fail;
        }
        if (!VK_CHECK(create(ctx->instance, &messenger, NULL, &ctx->messenger))) goto fail;
    }
    if (!vk_device_open(ctx, desc->device, desc->ray_query) || !vk_memory_file_fits(0) ||
        !vk_probe_loop_limit(ctx))
        goto fail;
    return true;
fail:
    vk_context_destroy(ctx);
    return false;
}

/* Sets LP_NUM_THREADS to `threads` (when positive) for as long as the driver may read it, keeping
 * the user's own value in *saved (NULL when there was none) for restore_threads. */
static bool set_threads(int threads, char **saved) {
    *saved = NULL;
    if (threads <= 0) return true;
    const char *old = getenv("LP_NUM_THREADS");
    if (old && !(*saved = strdup(old))) return false;
    char value[16];
    snprintf(value, sizeof value, "%d", threads);
    return setenv("LP_NUM_THREADS", value, 1) == 0;
}

static void restore_threads(int threads, char *saved) {
    if (threads <= 0) return;
    if (saved)
        setenv("LP_NUM_THREADS", saved, 1);
    else
        unsetenv("LP_NUM_THREADS");
    free(saved);
}

/* lavapipe reads LP_NUM_THREADS when it opens its devices (vkEnumeratePhysicalDevices), so it
 * is set around everything that opens them, and put back after. */
bool vk_context_init(vk_context *ctx, const vk_context_desc *desc) {
    char *saved;
    if (!set_threads(desc->threads, &saved)) {
        *ctx = (vk_context){.device_index = -1};
        atomic_init(&ctx->validation_errors, 0u);
        log_error("out of memory setting LP_NUM_THREADS");
        return false;
    }
    bool ok = open_context(ctx, desc);
    restore_threads(desc->threads, saved);
    return ok;
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
