/* render_choose.c: choosing the back end of a render: the one asked for, or with auto Vulkan
 * when it can render the scene and else the CPU back end, with one line saying why; where every
 * Vulkan device is a CPU, auto takes the engine measured faster for the scene. */
#include <string.h>

#include "render/cpu/integrator.h"
#include "render/part.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "shared_layout.h"
#include "util/log.h"

/* With only CPU Vulkan devices (lavapipe), whether the CPU back end renders the scene faster,
 * the reason in *why (docs/PERF.md, "Cooperative walk" and "Path mode on the CPU"): the CPU back
 * end everywhere, but for path mode on scenes small enough to unroll where it has no 16-lane
 * path build, whose narrower builds are no faster than the one-sample text, which lavapipe
 * beats there. */
static bool cpu_faster(const scene *s, const render_opts *opts, const char **why) {
    bool small = s->sphere_count <= TZ_UNROLL_MAX_SPHERES;
    if (opts->mode == RENDER_MODE_PATH && small && integrator_path_choose(NULL, false).width < 16) {
        *why =
            "path mode on a scene of at most 16 spheres, no 16-lane CPU build: lavapipe "
            "measured faster";
        return false;
    }
    *why = opts->mode == RENDER_MODE_PATH
               ? "path mode, where the CPU back end measured faster than lavapipe"
           : small ? "report mode, where the CPU back end measured faster than lavapipe"
                   : "report mode through the BVH, where the CPU back end measured faster than "
                     "lavapipe";
    return true;
}

bool render_choose(const scene *s, const render_opts *opts, backend_choice backend, film *f,
                   const char **used) {
    *f = (film){0};
    part_meta meta;
    render_part_meta(s, opts, &meta);
    part p;
    *used = backend == BACKEND_VULKAN ? "vulkan" : "cpu";
    if (!part_init(&p, &meta)) return false;
    bool ok = render_choose_part(s, opts, backend, &p, meta.spp, used) && part_film(&p, f);
    part_free(&p);
    return ok;
}

/* Forgets what a failed Vulkan render of a fresh part did (its samples, its back end), so that
 * the CPU back end starts it again rather than mixing its samples with Vulkan's; false (logged)
 * on out of memory. A resumed part is never handed from one back end to the other. */
static bool restart_part(part *p, uint32_t begin) {
    if (p->meta.sample_end == begin) { /* nothing rendered */
        p->meta.backend[0] = '\0';
        return true;
    }
    if (begin != p->meta.sample_begin) {
        log_error(
            "the Vulkan back end failed after rendering samples %u:%u of a resumed part: "
            "the CPU back end cannot go on from them",
            begin, p->meta.sample_end);
        return false;
    }
    part_meta m = p->meta;
    m.backend[0] = '\0';
    m.nonfinite = 0;
    part_free(p);
    return part_init(p, &m);
}

bool render_choose_part(const scene *s, const render_opts *opts, backend_choice backend, part *p,
                        uint32_t sample_end, const char **used) {
    /* auto goes on from a part on the back end that began it: the two do not mix. */
    if (backend == BACKEND_AUTO && p->meta.backend[0])
        backend = strcmp(p->meta.backend, "cpu") ? BACKEND_VULKAN : BACKEND_CPU;
    *used = backend == BACKEND_VULKAN ? "vulkan" : "cpu";
    uint32_t begin = p->meta.sample_end;
    if (backend == BACKEND_CPU) return render_cpu_part(s, opts, p, sample_end);
    char reason[RENDER_REASON_SIZE];
    if (backend == BACKEND_VULKAN || opts->validate || opts->device_given ||
        opts->walk != RENDER_WALK_AUTO) {
        *used = "vulkan";
        render_status status = render_vk_part_try(s, opts, p, sample_end, reason);
        if (status == RENDER_REFUSED) log_error("%s" VK_CONTEXT_USE_CPU, reason);
        return status == RENDER_DONE;
    }
    if (vk_context_device_count() == 0) {
        log_info("no Vulkan device found; rendering with the CPU back end");
        return render_cpu_part(s, opts, p, sample_end);
    }
    if (vk_context_cpu_only()) {
        const char *why;
        bool cpu = cpu_faster(s, opts, &why);
        log_debug("auto: the only Vulkan devices are CPUs; the %s back end: %s",
                  cpu ? "CPU" : "Vulkan", why);
        if (cpu) return render_cpu_part(s, opts, p, sample_end);
    }
    *used = "vulkan";
    render_status status = render_vk_part_try(s, opts, p, sample_end, reason);
    if (status == RENDER_DONE) return true;
    if (status == RENDER_INVALID) return false;
    if (status == RENDER_REFUSED)
        log_info("%s; rendering with the CPU back end instead", reason);
    else
        log_info(
            "the Vulkan back end failed (said above); rendering with the CPU back end instead");
    *used = "cpu";
    return restart_part(p, begin) && render_cpu_part(s, opts, p, sample_end);
}
