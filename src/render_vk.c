/* placeholder */ typedef int placeholder_render_vk;
