/* render_choose.c: choosing the back end of a render: the one asked for, or with auto Vulkan
 * when it can render the scene and else the CPU back end, with one line saying why. */
#include "render/part.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "util/log.h"

bool render_choose(const scene *s, const render_opts *opts, backend_choice backend, film *f,
                   const char **used) {
    *used = backend == BACKEND_VULKAN ? "vulkan" : "cpu";
    if (backend == BACKEND_CPU) return render_cpu(s, opts, f);
    if (backend == BACKEND_VULKAN) return render_vk(s, opts, f);
    if (vk_context_device_count() == 0) {
        log_info("no Vulkan device found; rendering with the CPU back end");
        return render_cpu(s, opts, f);
    }
    *used = "vulkan";
    /* A device or validation asked for (--device, --validate) asks for Vulkan: its verdict stands,
     * a refusal included. */
    if (opts->validate || opts->device >= 0) return render_vk(s, opts, f);
    render_stats vk_stats = {0};
    render_opts tried = *opts;
    if (!tried.stats) tried.stats = &vk_stats;
    char reason[RENDER_REASON_SIZE];
    render_status status = render_vk_try(s, &tried, f, reason);
    if (status == RENDER_DONE) return true;
    /* Validation errors fail the run: they say the back end is wrong, not the scene too big. */
    if (tried.stats->validation_errors > 0) return false;
    if (status == RENDER_REFUSED)
        log_info("%s; rendering with the CPU back end instead", reason);
    else
        log_info(
            "the Vulkan back end failed (said above); rendering with the CPU back end instead");
    *used = "cpu";
    return render_cpu(s, opts, f);
}

bool render_choose_part(const scene *s, const render_opts *opts, backend_choice backend, part *p,
                        uint32_t sample_end, const char **used) {
    *used = backend == BACKEND_VULKAN ? "vulkan" : "cpu";
    if (backend == BACKEND_CPU) return render_cpu_part(s, opts, p, sample_end);
    char reason[RENDER_REASON_SIZE];
    if (backend == BACKEND_VULKAN || opts->validate || opts->device >= 0) {
        *used = "vulkan";
        render_status status = render_vk_part_try(s, opts, p, sample_end, reason);
        if (status == RENDER_REFUSED) log_error("%s" VK_CONTEXT_USE_CPU, reason);
        return status == RENDER_DONE;
    }
    if (vk_context_device_count() == 0) {
        log_info("no Vulkan device found; rendering with the CPU back end");
        return render_cpu_part(s, opts, p, sample_end);
    }
    *used = "vulkan";
    render_stats vk_stats = {0};
    render_opts tried = *opts;
    if (!tried.stats) tried.stats = &vk_stats;
    render_status status = render_vk_part_try(s, &tried, p, sample_end, reason);
    if (status == RENDER_DONE) return true;
    if (tried.stats->validation_errors > 0) return false;
    if (status == RENDER_REFUSED)
        log_info("%s; rendering with the CPU back end instead", reason);
    else
        log_info(
            "the Vulkan back end failed (said above); rendering with the CPU back end instead");
    *used = "cpu";
    return render_cpu_part(s, opts, p, sample_end); /* from what Vulkan last synced */
}
