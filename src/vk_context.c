/* TEMPORARY placeholder until the Vulkan back end lands. */
#include "vk_context.h"
int vk_context_device_count(void) { return 0; }
bool vk_context_print_devices(void) { return false; }
