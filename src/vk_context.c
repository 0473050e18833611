/* placeholder */ typedef int placeholder_vk_context;
