/* render_choose.c: rendering with a back end of the table (render.h): the one asked for, or with
 * auto Vulkan when it can render the scene and else the CPU back end, with one line saying why;
 * where every Vulkan device is a CPU, auto takes the one measured faster for the scene. */
#include <string.h>

#include "render/part.h"
#include "render/render.h"
#include "shared_layout.h"
#include "util/log.h"

/* The render of film f through a whole part of scene s, rendered by `render`; false on failure
 * (logged). */
static bool film_by_part(const scene *s, const render_opts *opts, film *f,
                         bool (*render)(void *user, part *p, uint32_t sample_end), void *user) {
    *f = (film){0};
    part_meta meta;
    render_part_meta(s, opts, &meta);
    part p;
    if (!part_init(&p, &meta)) return false;
    bool ok = render(user, &p, meta.spp) && part_film(&p, f);
    part_free(&p);
    return ok;
}

typedef struct backend_render {
    const render_backend *backend;
    const scene *s;
    const render_opts *opts;
} backend_render;

/* film_by_part's render through one back end, a refusal logged as an error. */
static bool backend_render_part(void *user, part *p, uint32_t sample_end) {
    const backend_render *r = user;
    char reason[RENDER_REASON_SIZE];
    render_status status = r->backend->render_part(r->s, r->opts, p, sample_end, reason);
    if (status == RENDER_REFUSED) log_error("%s" RENDER_USE_CPU, reason);
    return status == RENDER_DONE;
}

bool render_film(const render_backend *b, const scene *s, const render_opts *opts, film *f) {
    backend_render r = {.backend = b, .s = s, .opts = opts};
    return film_by_part(s, opts, f, backend_render_part, &r);
}

typedef struct chosen_render {
    const scene *s;
    const render_opts *opts;
    backend_choice backend;
    const char **used;
} chosen_render;

/* film_by_part's render through the back end chosen. */
static bool chosen_render_part(void *user, part *p, uint32_t sample_end) {
    const chosen_render *r = user;
    return render_choose_part(r->s, r->opts, r->backend, p, sample_end, r->used);
}

bool render_choose(const scene *s, const render_opts *opts, backend_choice backend, film *f,
                   const char **used) {
    *used = backend == BACKEND_VULKAN ? "vulkan" : "cpu";
    chosen_render r = {.s = s, .opts = opts, .backend = backend, .used = used};
    return film_by_part(s, opts, f, chosen_render_part, &r);
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

/* Why auto takes the CPU back end where every Vulkan device is a CPU: it measured faster than
 * lavapipe 22.3 and 25 in every mode, scene size and packet build (docs/PERF.md, "Cooperative
 * walk", "Path mode on the CPU" and "auto on lavapipe"). */
static const char *cpu_faster_reason(const scene *s, const render_opts *opts) {
    if (opts->mode == RENDER_MODE_PATH)
        return "path mode, where the CPU back end measured faster than lavapipe";
    return s->sphere_count + s->triangle_count <= TZ_UNROLL_MAX_SPHERES
               ? "report mode, where the CPU back end measured faster than lavapipe"
               : "report mode through the BVH, where the CPU back end measured faster than "
                 "lavapipe";
}

/* Renders with the CPU back end (which never refuses); false on failure (logged). */
static bool cpu_render_part(const scene *s, const render_opts *opts, part *p, uint32_t end) {
    char reason[RENDER_REASON_SIZE];
    return render_backend_cpu.render_part(s, opts, p, end, reason) == RENDER_DONE;
}

/* render_choose_part without the feature images. */
static bool choose_part(const scene *s, const render_opts *opts, backend_choice backend, part *p,
                        uint32_t sample_end, const char **used) {
    const render_backend *vk = &render_backend_vulkan, *cpu = &render_backend_cpu;
    /* auto goes on from a part on the back end that began it: the two do not mix. */
    if (backend == BACKEND_AUTO && p->meta.backend[0])
        backend = strcmp(p->meta.backend, cpu->name) ? BACKEND_VULKAN : BACKEND_CPU;
    *used = backend == BACKEND_VULKAN ? vk->name : cpu->name;
    uint32_t begin = p->meta.sample_end;
    if (backend == BACKEND_CPU) return cpu_render_part(s, opts, p, sample_end);
    char reason[RENDER_REASON_SIZE];
    if (backend == BACKEND_VULKAN || opts->validate || opts->device_given ||
        opts->walk != RENDER_WALK_AUTO) {
        *used = vk->name;
        render_status status = vk->render_part(s, opts, p, sample_end, reason);
        if (status == RENDER_REFUSED) log_error("%s" RENDER_USE_CPU, reason);
        return status == RENDER_DONE;
    }
    if (vk->device_count() == 0) {
        log_info("no Vulkan device found; rendering with the CPU back end");
        return cpu_render_part(s, opts, p, sample_end);
    }
    if (vk->cpu_only()) {
        log_debug("auto: the only Vulkan devices are CPUs; the CPU back end: %s",
                  cpu_faster_reason(s, opts));
        return cpu_render_part(s, opts, p, sample_end);
    }
    *used = vk->name;
    render_status status = vk->render_part(s, opts, p, sample_end, reason);
    if (status == RENDER_DONE) return true;
    if (status == RENDER_INVALID) return false;
    if (status == RENDER_REFUSED)
        log_info("%s; rendering with the CPU back end instead", reason);
    else
        log_info(
            "the Vulkan back end failed (said above); rendering with the CPU back end instead");
    *used = cpu->name;
    return restart_part(p, begin) && cpu_render_part(s, opts, p, sample_end);
}

bool render_choose_part(const scene *s, const render_opts *opts, backend_choice backend, part *p,
                        uint32_t sample_end, const char **used) {
    if (!choose_part(s, opts, backend, p, sample_end, used)) return false;
    /* A part of chunk 0 has the feature images asked for, whichever back end rendered it. */
    if (p->aov.mask == opts->aov && (opts->aov == 0 || p->meta.sample_begin != 0)) return true;
    aov_free(&p->aov);
    return !opts->aov || p->meta.sample_begin != 0 || render_aov(s, opts, p);
}
