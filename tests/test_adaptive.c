/* test_adaptive.c: the noise threshold (render --noise-threshold, common/adaptive.h) on the back
 * end named by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 when no device exists): a flat region
 * stops at the first decision and a noisy one goes on to the cap; every pixel that stopped early
 * did so with its estimated error at most the threshold, from the very sums it ends with; the
 * same bytes on 1, 2 and 3 threads (CPU), split by regions and merged, resumed from a part file
 * (Vulkan: through staging copies), and the Vulkan back end's bytes are the CPU back end's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "common/adaptive.h"
#include "render/part.h"
#include "render/part_internal.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"

static backend_choice backend = BACKEND_CPU;

/* Left: a black emitter seen head-on, every sample the same (flat). Right: a wall lit by a small
 * emitter out of view and the light a floor out of view sends back, in path mode (noisy).
 * 24 x 12 pixels. */
static const char *const halves =
    "camera position 0 0 -10\nplane width 0.48 height 0.24 pixel 0.02\n"
    "quad lambertian v0 -5 -5 5 v1 0 -5 5 v2 0 5 5 v3 -5 5 5 color 0 0 0 emission 0.5 0.5 0.5\n"
    "quad lambertian v0 0 -5 5 v1 5 -5 5 v2 5 5 5 v3 0 5 5 color 0.7 0.7 0.7\n"
    "sphere lambertian center 2 0 -9 radius 0.2 color 0 0 0 emission 200 200 200\n"
    "quad lambertian v0 -9 -3 -12 v1 -9 -3 5 v2 9 -3 5 v3 9 -3 -12 color 0.9 0.9 0.9\n"
    "render mode path samples 160\n";

/* The flat half's error is rounding's (1e-8); the noisy half's is far above. */
#define THRESHOLD 1e-5f

/* Renders region x0,x1,y0,y1 (x1 0: all) of samples 0:end of text with the noise threshold on
 * `threads` threads into p (a fresh part, or with `go_on` p itself from where it ends); false on
 * failure. */
static bool render_adaptive(const char *text, int x0, int x1, int y0, int y1, uint32_t end,
                            int threads, backend_choice on, bool go_on, part *p) {
    scene s;
    render_opts o;
    if (!go_on) *p = (part){0};
    if (!parse_scene_text(text, &s, &o)) return false;
    o.validate = on == BACKEND_VULKAN;
    o.threads = threads;
    o.noise_threshold = THRESHOLD;
    part_meta m;
    render_part_meta(&s, &o, &m);
    if (x1 > 0) m.x0 = x0, m.x1 = x1, m.y0 = y0, m.y1 = y1;
    const char *used;
    bool ok = (go_on || part_init(p, &m)) && render_choose_part(&s, &o, on, p, end, &used);
    scene_free(&s);
    return ok;
}

/* Whether two parts hold the same sums, counts and adaptive state, byte for byte (said). */
static bool same_part(const part *a, const part *b, const char *what) {
    size_t n = region_pixels(&a->meta);
    bool same = a->stack.count == b->stack.count && a->meta.sample_end == b->meta.sample_end &&
                region_pixels(&b->meta) == n && a->adaptive && b->adaptive &&
                !memcmp(a->count, b->count, n * sizeof *a->count) &&
                !memcmp(a->adaptive, b->adaptive, n * 4 * sizeof(float));
    for (int k = 0; same && k < a->stack.count; k++)
        same = !memcmp(a->block[k], b->block[k], n * 3 * sizeof(float));
    CHECK(same, "%s: the parts differ", what);
    return same;
}

static part whole; /* the whole render on the back end tested, 2 threads */

static void test_flat_and_noisy(void) {
    EXPECT(render_adaptive(halves, 0, 0, 0, 0, 160, 2, backend, false, &whole));
    if (!whole.adaptive) return;
    int width = whole.meta.width, early_flat = 0, capped_noisy = 0, checked = 0;
    for (int y = 0; y < whole.meta.height; y++)
        for (int x = 0; x < width; x++) {
            size_t i = (size_t)y * (size_t)width + (size_t)x;
            uint32_t stop = (uint32_t)whole.adaptive[4 * i + 3];
            if (x < width / 2 - 1) early_flat += stop == TZ_ADAPTIVE_MIN_CHUNKS;
            if (x > width / 2) capped_noisy += stop == 0 && whole.count[i] == 160;
            if (stop == 0) {
                CHECK(whole.count[i] == 160, "pixel (%d, %d) went on, with %u samples", x, y,
                      whole.count[i]);
                continue;
            }
            /* stopped: its sums are those its decision saw, and their error is in bounds */
            float total[3];
            part_pixel_total(&whole, i, total);
            const float *a = &whole.adaptive[4 * i];
            float error =
                adaptive_error(v3(total[0], total[1], total[2]), v3(a[0], a[1], a[2]), stop);
            CHECK(error <= THRESHOLD, "pixel (%d, %d) stopped at chunk %u with error %g", x, y,
                  stop, error);
            CHECK(whole.count[i] == stop * TZ_CHUNK_SAMPLES, "pixel (%d, %d): %u samples", x, y,
                  whole.count[i]);
            checked++;
        }
    int half = (width / 2 - 1) * whole.meta.height;
    CHECK(early_flat == half, "%d of %d flat pixels stopped at the first decision", early_flat,
          half);
    CHECK(capped_noisy == half, "%d of %d noisy pixels went on to the cap", capped_noisy, half);
    CHECK(checked >= half, "%d pixels stopped early", checked);
}

static void test_threads(void) {
    if (backend == BACKEND_VULKAN) return; /* each Vulkan render sets a device up: a few only */
    for (int threads = 1; threads <= 3; threads += 2) {
        part p;
        EXPECT(render_adaptive(halves, 0, 0, 0, 0, 160, threads, backend, false, &p));
        same_part(&whole, &p, threads == 1 ? "1 thread" : "3 threads");
        part_free(&p);
    }
}

static void test_regions(void) {
    part parts[2], merged;
    EXPECT(render_adaptive(halves, 0, 10, 0, 12, 160, 2, backend, false, &parts[0]));
    EXPECT(render_adaptive(halves, 10, 24, 0, 12, 160, 2, backend, false, &parts[1]));
    const char *names[2] = {"left", "right"};
    EXPECT(part_merge(parts, names, 2, &merged));
    same_part(&whole, &merged, "regions merged");
    part_free(&merged);
    for (int k = 0; k < 2; k++) part_free(&parts[k]);
}

static void test_resume(void) {
    part p, back;
    /* past the first decision, then through a file, then on to the end; on Vulkan with every
     * buffer through staging copies */
    if (backend == BACKEND_VULKAN) setenv("TRAZADOR_VK_STAGING", "1", 1);
    EXPECT(render_adaptive(halves, 0, 0, 0, 0, 96, 2, backend, false, &p));
    char path[64];
    snprintf(path, sizeof path, "test_adaptive_%d.exr", (int)getpid());
    EXPECT(part_write(path, &p) && part_read(path, &back));
    remove(path);
    EXPECT(render_adaptive(halves, 0, 0, 0, 0, 160, 2, backend, true, &back));
    unsetenv("TRAZADOR_VK_STAGING");
    same_part(&whole, &back, "resumed from a file");
    part_free(&p);
    part_free(&back);
}

static void test_cpu_agrees(void) {
    if (backend != BACKEND_VULKAN) return;
    part cpu;
    EXPECT(render_adaptive(halves, 0, 0, 0, 0, 160, 2, BACKEND_CPU, false, &cpu));
    size_t n = region_pixels(&whole.meta);
    bool same = cpu.adaptive && whole.adaptive && !memcmp(cpu.count, whole.count, n * 4) &&
                !memcmp(cpu.adaptive, whole.adaptive, n * 4 * sizeof(float));
    for (int k = 0; same && k < cpu.stack.count; k++)
        same = !memcmp(cpu.block[k], whole.block[k], n * 3 * sizeof(float));
    CHECK(same, "vulkan and cpu differ");
    part_free(&cpu);
}

int main(int argc, char **argv) {
    if (argc > 1 && !strcmp(argv[1], "vulkan")) {
        if (vk_context_device_count() == 0) {
            printf("test_adaptive vulkan: no Vulkan device, skipped\n");
            return 77;
        }
        backend = BACKEND_VULKAN;
    }
    CHECK_CASE(test_flat_and_noisy);
    CHECK_CASE(test_threads);
    CHECK_CASE(test_regions);
    CHECK_CASE(test_resume);
    CHECK_CASE(test_cpu_agrees);
    part_free(&whole);
    return check_summary(backend == BACKEND_VULKAN ? "test_adaptive vulkan" : "test_adaptive");
}
