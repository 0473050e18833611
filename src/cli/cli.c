/* cli.c: what the subcommands share: reading numbers from arguments, and rendering with the
 * back end chosen (auto: Vulkan when it can, else the CPU, with one line saying why). */
#include "cli/cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/log.h"
#include "render/vk/vk_context.h"

bool cli_parse_int(const char *text, long long min, long long max, long long *out) {
    if (!text || !*text || strspn(text, "+-0123456789") != strlen(text)) return false;
    char *end;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (errno || *end || v < min || v > max) return false;
    *out = v;
    return true;
}

bool cli_parse_number(const char *text, double *out) {
    if (text && !strcmp(text, "inf")) {
        *out = INFINITY;
        return true;
    }
    if (!text || !*text || strspn(text, "+-.0123456789eE") != strlen(text)) return false;
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end || !isfinite(v)) return false;
    *out = v;
    return true;
}

bool cli_render(const scene *s, const render_opts *opts, backend_choice backend, film *f,
                const char **used) {
    *used = backend == BACKEND_VULKAN ? "vulkan" : "cpu";
    if (backend == BACKEND_CPU) return render_cpu(s, opts, f);
    if (backend == BACKEND_VULKAN) return render_vk(s, opts, f);
    /* auto: Vulkan when a device exists and can render the scene, else the C renderer. */
    if (vk_context_device_count() == 0) {
        log_info("no Vulkan device found; rendering with the CPU back end");
    } else {
        *used = "vulkan";
        render_opts tried = *opts;
        render_stats stats = {0};
        if (!tried.stats) tried.stats = &stats;
        log_hold_errors();
        bool ok = render_vk(s, &tried, f);
        const char *why = log_release_errors();
        /* Validation or a device asked for (--validate, --device), or validation failed: the
         * verdict stands, in full. */
        if (ok || opts->validate || opts->device >= 0 || tried.stats->validation_errors > 0) {
            for (const char *line = why; *line;) {
                const char *end = strchr(line, '\n');
                log_error("%.*s", (int)(end - line), line);
                line = end + 1;
            }
            return ok;
        }
        /* One line: why Vulkan could not, less its advice to use the CPU, which follows. */
        int length = (int)strcspn(why, "\n");
        int advice_length = (int)strlen(VK_CONTEXT_USE_CPU);
        if (length >= advice_length &&
            !strncmp(why + length - advice_length, VK_CONTEXT_USE_CPU, advice_length))
            length -= advice_length;
        log_info("%.*s%srendering with the CPU back end instead", length, why, length ? "; " : "");
    }
    *used = "cpu";
    return render_cpu(s, opts, f);
}
