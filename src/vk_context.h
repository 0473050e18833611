/* vk_context.h: the Vulkan instance, device, queue and command pool of one render, the
 * validation messenger, and device listing. */
#ifndef TRAZADOR_VK_CONTEXT_H
#define TRAZADOR_VK_CONTEXT_H

#include <stdbool.h>

/* Number of Vulkan physical devices; 0 when there is no loader, driver or device. Logs nothing. */
int vk_context_device_count(void);
/* Prints every device (index, name, type, driver), marking the default; false when none. */
bool vk_context_print_devices(void);

#endif
