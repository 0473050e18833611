/* bench.c: `trazador bench`, fixed workloads timed on each back end (a benchmark, not a test). */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "cli.h"
#include "default_scene.h"
#include "log.h"
#include "vk_context.h"

typedef struct workload {
    const char *name;
    int size;     /* square image side in pixels */
    int samples;
    bool indirect;
} workload;

static const workload workloads[] = {
    {"cornell 512x512 indirect", 512, 16, true},
    {"cornell 512x512 direct", 512, 16, false},
};

static double seconds_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* Renders the workload once and returns Msamples/s, or a negative number on failure. */
static double run_workload(const scene *base, const workload *w, backend_choice backend, int spp) {
    scene s = *base;
    s.plane_height = s.plane_width;
    s.pixel_size = s.plane_width / (float)w->size;
    s.width = s.height = w->size;
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.samples = spp > 0 ? spp : w->samples;
    opts.indirect = w->indirect;
    film f = {0};
    const char *used;
    double start = seconds_now();
    bool ok = cli_render(&s, &opts, backend, &f, &used);
    double elapsed = seconds_now() - start;
    film_free(&f);
    return ok ? (double)w->size * w->size * opts.samples / elapsed * 1e-6 : -1.0;
}

int bench_command(int argc, char **argv) {
    bool want_cpu = true, want_vk = vk_context_device_count() > 0;
    long long spp = 0;
    for (int k = 1; k < argc; k++) {
        const char *value = k + 1 < argc ? argv[k + 1] : "";
        if (!strcmp(argv[k], "--backend")) {
            want_cpu = !strcmp(value, "cpu") || !strcmp(value, "both") || !strcmp(value, "auto");
            want_vk = !strcmp(value, "vulkan") || !strcmp(value, "both") ||
                      (!strcmp(value, "auto") && want_vk);
            if (!want_cpu && !want_vk) {
                fprintf(stderr, "trazador: bench --backend takes auto, vulkan, cpu or both\n");
                return 2;
            }
            k++;
        } else if (!strcmp(argv[k], "--spp") && cli_parse_int(value, 1, 65536, &spp)) {
            k++;
        } else {
            fprintf(stderr, "trazador: usage: trazador bench [--backend auto|vulkan|cpu|both] [--spp N]\n");
            return 2;
        }
    }
    scene s;
    scene_error err;
    if (!scene_parse_string(default_scene_text, strlen(default_scene_text), "cornell.scene", &s, &err)) {
        fprintf(stderr, "%s:%d:%d: %s\n", err.file, err.line, err.col, err.message);
        return 1;
    }
    int failures = 0;
    printf("%-28s %14s %14s %8s\n", "workload", "cpu Msamples/s", "vk Msamples/s", "vk/cpu");
    for (size_t k = 0; k < sizeof workloads / sizeof workloads[0]; k++) {
        const workload *w = &workloads[k];
        double cpu = want_cpu ? run_workload(&s, w, BACKEND_CPU, (int)spp) : 0.0;
        double vk = want_vk ? run_workload(&s, w, BACKEND_VULKAN, (int)spp) : 0.0;
        failures += cpu < 0.0 || vk < 0.0;
        printf("%-28s %14.2f %14.2f", w->name, cpu, vk);
        if (cpu > 0.0 && vk > 0.0) printf(" %8.2f", vk / cpu);
        printf("\n");
        fflush(stdout);
    }
    scene_free(&s);
    return failures ? 1 : 0;
}
