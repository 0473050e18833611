/* vk_internal.h: what the files of the Vulkan layer share among themselves (the loader's entry
 * point, instance creation, device queries) and the renderer does not use. */
#ifndef TRAZADOR_VK_INTERNAL_H
#define TRAZADOR_VK_INTERNAL_H

#include "render/vk/vk_context.h"

/* Opens the Vulkan loader once (thread-safe); true when a Vulkan 1.1 loader was found and its
 * global functions loaded. Logs nothing. */
bool vk_loader_ready(void);
/* Logs why the loader could not be opened (the no-loader message, dlerror's text at --verbose);
 * never fails. */
void vk_loader_report(void);
/* The named function of `instance` (VK_NULL_HANDLE for a global one); NULL when missing. */
PFN_vkVoidFunction vk_loader_proc(VkInstance instance, const char *name);
/* Loads every VK_CONTEXT_INSTANCE_FUNCTIONS pointer; false (each missing one logged) on failure. */
bool vk_loader_load_instance(VkInstance instance);
/* The VkResult's enumerant name, or "VK_RESULT_<number>" for one this build does not know. */
const char *vk_result_name(VkResult result);

/* Creates an instance: Vulkan 1.1 or later, portability enumeration where offered (MoltenVK),
 * and with `messenger` (validation on) the Khronos layer, debug utils and synchronization
 * validation. Returns the VkResult; logs only the missing-validation cases. */
VkResult vk_instance_create(const VkDebugUtilsMessengerCreateInfoEXT *messenger, VkInstance *out);
/* Fills the messenger's create info: errors and warnings of every type, reported to ctx. */
void vk_instance_messenger_info(vk_context *ctx, VkDebugUtilsMessengerCreateInfoEXT *out);

/* Picks the physical device (`requested`, or the first usable one when -1) and creates the
 * logical device, queue and command pool in ctx, with ray queries enabled when `ray_query` asks
 * and the device has them (ctx->ray_query); false (logged) on failure. */
bool vk_device_open(vk_context *ctx, int requested, bool ray_query);

#endif
