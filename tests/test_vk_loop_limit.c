/* test_vk_loop_limit.c: the loop budget the renderer's guard relies on (DESIGN section 5). On
 * lavapipe of Mesa 22.3 one invocation completes exactly 65,535 loop iterations, all loops
 * together, and then every loop stops silently; Mesa 25 and other drivers run every iteration.
 * The context's probed limit (vk_probe_loop_limit) must be that budget, pinned by the driver's
 * version where it is known, and predict every probe case; the renderer must refuse a scene past
 * the safe share of it and render the same scene where loops run to the end. Says which driver it
 * ran on. Validation is on; exits 77 only when no Vulkan device exists. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "render/vk/vk_probe.h"
#include "test_scenes.h"

/* What one invocation should complete of loops of n[0] then n[1] iterations: under a limit a
 * budget of `limit` passes, one spent at the end of every pass of either loop (the pass that
 * finds the loop done included), a loop stopping when none is left; without one (0), all. */
static void expected(uint32_t limit, const uint32_t n[2], uint32_t want[2]) {
    if (!limit) {
        want[0] = n[0];
        want[1] = n[1];
        return;
    }
    int64_t budget = limit;
    for (int loop = 0; loop < 2; loop++) {
        uint32_t done = 0;
        for (;;) {
            bool finished = done >= n[loop];
            if (!finished) done++;
            if (--budget <= 0 || finished) break;
        }
        want[loop] = done;
    }
}

/* The limit the context was probed to have, against what the driver's version says: lavapipe of
 * Mesa 22 and before cuts loops at 65,535 passes (LP_MAX_TGSI_LOOP_ITERATIONS), that of Mesa 25
 * does not, and no other driver cuts them. lavapipe's driverVersion is 1 whatever its release:
 * the release is read from driverInfo ("Mesa 22.3.6 (LLVM 15.0.6)"). */
static void test_limit(const vk_context *ctx) {
    unsigned mesa = 0, minor = 0;
    const char *release = strstr(ctx->driver_info, "Mesa ");
    if (release && sscanf(release, "Mesa %u.%u", &mesa, &minor) != 2) mesa = 0;
    if (ctx->loop_limit)
        printf("test_vk_loop_limit: ran on %s, driver %s %s: loops stop silently after %u passes\n",
               ctx->properties.deviceName, ctx->driver_name, ctx->driver_info, ctx->loop_limit);
    else
        printf("test_vk_loop_limit: ran on %s, driver %s %s: loops run to the end\n",
               ctx->properties.deviceName, ctx->driver_name, ctx->driver_info);
    if (!vk_context_is_lavapipe(ctx))
        CHECK(ctx->loop_limit == 0, "a limit of %u found off lavapipe", ctx->loop_limit);
    else if (mesa == 0)
        CHECK(0, "lavapipe's driverInfo names no Mesa release: \"%s\"", ctx->driver_info);
    else if (mesa <= 22)
        CHECK(ctx->loop_limit == 65535u, "lavapipe of Mesa %u: a limit of %u, want 65535", mesa,
              ctx->loop_limit);
    else if (mesa >= 25)
        CHECK(ctx->loop_limit == 0, "lavapipe of Mesa %u: a limit of %u, want none", mesa,
              ctx->loop_limit);
    CHECK(vk_probe_safe_iterations(65535u) == 60000u, "the safe share of 65,535 moved");
    CHECK(vk_probe_safe_iterations(0u) == UINT64_MAX, "no limit has a safe share");
}

static void test_probe(vk_context *ctx) {
    const uint32_t cases[][2] = {
        {1000, 0},      {65535, 0}, {65536, 0}, {200000, 0}, /* one loop */
        {40000, 40000}, {65534, 5}, {65535, 1}, {65535, 2},  /* the budget is shared */
        {1000, 1000},   {0, 70000},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        uint32_t least[2] = {0, 0}, most[2] = {0, 0}, want[2];
        expected(ctx->loop_limit, cases[k], want);
        CHECK(vk_probe_loops(ctx, cases[k], least, most), "probe (%u, %u) failed", cases[k][0],
              cases[k][1]);
        /* Every invocation of every workgroup and subgroup has a budget of its own. */
        CHECK(least[0] == most[0] && least[1] == most[1],
              "loops of %u then %u: invocations disagree (%u..%u, %u..%u)", cases[k][0],
              cases[k][1], least[0], most[0], least[1], most[1]);
        CHECK(least[0] == want[0] && least[1] == want[1],
              "loops of %u then %u iterations completed %u and %u, want %u and %u on %s",
              cases[k][0], cases[k][1], least[0], least[1], want[0], want[1], ctx->driver_name);
    }
}

static void test_bound(void) {
    /* 8 spheres, 1 light, 5 bounces: 2 paths of (6 chain rays + 1 shadow ray) x (8 + 2) passes
     * and the light loop's exit pass, and the sample's own pass. */
    CHECK(vk_probe_sample_iterations(8, 1, 5, true) == 2 * (7 * 10 + 1) + 1, "cornell bound %llu",
          (unsigned long long)vk_probe_sample_iterations(8, 1, 5, true));
    CHECK(vk_probe_sample_iterations(8, 1, 5, false) == 7 * 10 + 1 + 1, "direct-only bound");
    CHECK(vk_probe_sample_iterations(0, 0, 0, false) == 1 * 2 + 1 + 1, "empty scene bound");
    /* No overflow at the scene limits: 2^24 spheres, 4096 lights, 64 bounces. */
    CHECK(vk_probe_sample_iterations(1u << 24, 4096, 64, true) ==
              2ull * ((65 + 4096) * ((1ull << 24) + 2) + 1) + 1,
          "largest bound");
}

/* A scene of n tiny spheres in a row and one light, 8 x 8 pixels. */
static scene row_of_spheres(int n, sphere *spheres, light *l) {
    for (int k = 0; k < n; k++)
        spheres[k] =
            ball((float)k * 0.01f, 0.0f, 5.0f, 0.004f, TZ_MATERIAL_LAMBERTIAN, 0.5f, 0.5f, 0.5f);
    *l = (light){.position = {0.0f, 2.0f, 0.0f}, .power = 10.0f, .color = {1.0f, 1.0f, 1.0f}};
    scene s = view(0.0f, 0.08f, 0.08f, 8, 1, 1, spheres, n, l, 1);
    s.indirect = false;
    return s;
}

/* Largest relative difference of the two films' pixel means (1 when their sizes differ). */
static double film_difference(const film *a, const film *b) {
    if (!a->accum || !b->accum || a->width != b->width || a->height != b->height) return 1.0;
    double worst = 0.0;
    for (int k = 0; k < a->width * a->height * 4; k++) {
        double x = a->accum[k], y = b->accum[k],
               d = fabs(x - y) / (fabs(x) > 1e-3 ? fabs(x) : 1e-3);
        worst = d > worst ? d : worst;
    }
    return worst;
}

/* Brute force (--no-bvh) past the safe limit is refused where loops are cut (false, no film) and
 * rendered where they run to the end; through the BVH the same scene renders and matches the C
 * renderer. */
static void test_guard(vk_context *ctx) {
    enum { BIG = 4500 }; /* 2 x (7 x 4502 + 1) + 1 = 63031 passes a sample: past 60000 */
    sphere *spheres = calloc(BIG, sizeof *spheres);
    light l;
    if (!spheres) return;
    scene big = row_of_spheres(BIG, spheres, &l), small = row_of_spheres(BIG / 2, spheres, &l);
    render_opts opts;
    render_opts_from_scene(&big, &opts);
    opts.indirect = true;
    opts.no_bvh = true;
    film f = {0}, reference = {0};
    bool rendered = render_film(&render_backend_vulkan, &big, &opts, &f);
    if (ctx->loop_limit)
        CHECK(!rendered && !f.accum, "%s rendered a scene of %llu iterations per sample",
              ctx->driver_name, (unsigned long long)vk_probe_sample_iterations(BIG, 1, 5, true));
    else
        CHECK(rendered, "a %d-sphere scene failed where loops run to the end", BIG);
    film_free(&f);
    CHECK(render_film(&render_backend_vulkan, &small, &opts, &f), "a %d-sphere scene failed",
          BIG / 2);
    film_free(&f);
    opts.no_bvh = false;
    CHECK(render_film(&render_backend_vulkan, &big, &opts, &f),
          "the %d-sphere scene failed through the BVH", BIG);
    CHECK(render_film(&render_backend_cpu, &big, &opts, &reference), "the C renderer failed");
    double diff = film_difference(&reference, &f);
    CHECK(diff < 1e-3, "the BVH render differs from the C renderer by %g relative", diff);
    film_free(&f);
    film_free(&reference);
    free(spheres);
}

/* A pile of n coincident spheres on the axis, one pixel: a ray down its middle visits every
 * leaf. */
static scene pile_of_spheres(int n, sphere *spheres, light *l) {
    scene pile = row_of_spheres(n, spheres, l);
    for (int k = 0; k < n; k++) spheres[k].center = v3(0.0f, 0.0f, 5.0f);
    pile.width = pile.height = 1;
    pile.plane_width = pile.plane_height = pile.pixel_size = 0.01f;
    return pile;
}

/* With the BVH walk TRAZADOR_VK_WALK names (cooperative: the lone lane is the subgroup): a pile
 * of 70,000 spheres is a walk longer than any loop budget, which a driver that cuts loops must
 * refuse (the shader runs out of its budget and says so) rather than cut short; others render
 * it. A
 * pile of `near` spheres, a walk just inside the budget (8,569 passes a ray here, 4,284 a loop
 * cooperatively: about 1.1-1.4 passes a sphere), renders and matches the C renderer. */
static void test_walk_budget(vk_context *ctx, const char *walk, int near_count) {
    enum { PILE = 70000 };
    sphere *spheres = calloc(PILE, sizeof *spheres);
    light l;
    if (!spheres) return;
    setenv("TRAZADOR_VK_WALK", walk, 1);
    scene pile = pile_of_spheres(PILE, spheres, &l);
    render_opts opts;
    render_opts_from_scene(&pile, &opts);
    opts.no_jitter = true; /* the ray down the axis */
    film f = {0}, reference = {0};
    bool rendered = render_film(&render_backend_vulkan, &pile, &opts, &f);
    if (ctx->loop_limit)
        CHECK(!rendered && !f.accum, "%s walk: %s rendered a walk past its loop budget", walk,
              ctx->driver_name);
    else
        CHECK(rendered, "%s walk: a pile of %d spheres failed where loops run to the end", walk,
              PILE);
    film_free(&f);
    scene near = pile_of_spheres(near_count, spheres, &l);
    CHECK(render_film(&render_backend_vulkan, &near, &opts, &f),
          "%s walk: a pile of %d spheres failed", walk, near_count);
    CHECK(render_film(&render_backend_cpu, &near, &opts, &reference), "the C renderer failed");
    CHECK(f.accum && reference.accum && !memcmp(f.accum, reference.accum, 4 * sizeof(float)),
          "%s walk: the pile of %d spheres differs from the C renderer", walk, near_count);
    film_free(&f);
    film_free(&reference);
    unsetenv("TRAZADOR_VK_WALK");
    free(spheres);
}

int main(void) {
    if (vk_context_device_count() == 0) {
        printf("test_vk_loop_limit: no Vulkan device, skipped\n");
        return 77;
    }
    vk_context ctx;
    vk_context_desc desc = {.device = -1, .validate = true};
    CHECK(vk_context_init(&ctx, &desc), "context creation failed");
    if (ctx.device) {
        test_limit(&ctx);
        test_probe(&ctx);
        test_guard(&ctx);
        test_walk_budget(&ctx, "invocation", 6000);
        test_walk_budget(&ctx, "cooperative", 3000);
    }
    CHECK(vk_context_destroy(&ctx), "the validation layer reported errors");
    test_bound();
    return check_summary("test_vk_loop_limit");
}
