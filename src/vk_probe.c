/* placeholder */ typedef int placeholder_vk_probe;
