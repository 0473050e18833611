/* TEMPORARY placeholder until the Vulkan back end lands. */
#include "log.h"
#include "render.h"
bool render_vk(const scene *s, const render_opts *opts, film *f) {
    (void)s; (void)opts; (void)f;
    log_error("Vulkan back end not built yet");
    return false;
}
