/* test_vk_rayquery.c: the ray query walk (`--walk rayquery`: the device's acceleration structure,
 * every candidate decided by the shared tests and the tie rule) gives films byte-identical to the
 * compute walk's, with validation on: every scene in scenes/ (spheres, quads, the mesh), 3,000
 * random spheres (report mode with and without the indirect bounce, path mode), sphereflake 3, and
 * an exact tie of two coincident spheres. Where the device does not offer ray queries the test
 * says which driver it ran on, checks that the device really lacks them and that asking for the
 * walk fails, and passes. Exits 77 only when no Vulkan device exists. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "scene/gen.h"
#include "test_scenes.h"
#include "tmp_dir.h"

/* Renders s with `walk`, validation on; false when it failed. */
static bool render_with_walk(const scene *s, render_opts opts, render_walk walk, film *f) {
    opts.validate = true;
    opts.walk = walk;
    return render_film(&render_backend_vulkan, s, &opts, f);
}

/* The films of the two walks, bit for bit. */
static void check_same(const char *name, const scene *s, const render_opts *opts) {
    film compute = {0}, query = {0};
    bool ok = render_with_walk(s, *opts, RENDER_WALK_COMPUTE, &compute);
    ok = render_with_walk(s, *opts, RENDER_WALK_RAY_QUERY, &query) && ok;
    CHECK(ok, "%s: a walk failed", name);
    if (ok) {
        size_t n = (size_t)s->width * (size_t)s->height, differ = 0;
        for (size_t k = 0; k < 4 * n; k++)
            differ += memcmp(&compute.accum[k], &query.accum[k], sizeof(float)) != 0;
        CHECK(differ == 0 && compute.nonfinite == query.nonfinite,
              "%s: the ray query walk changed %zu of %zu film values", name, differ, 4 * n);
    }
    film_free(&compute);
    film_free(&query);
}

/* Every scene in scenes/, 64 pixels across, 4 samples. */
static void test_example_scenes(void) { each_example_scene(64, 4, check_same); }

/* The scene `trazador gen` writes for desc, `width` pixels across; false (checked) on failure. */
static bool generated_scene(const gen_desc *desc, const char *name, int width, scene *s) {
    const char *path = tmp_path(name);
    FILE *fp = fopen(path, "w");
    bool written = fp && gen_write(desc, fp);
    if (fp) written = fclose(fp) == 0 && written;
    scene_error err;
    bool parsed = written && scene_parse_file(path, s, &err);
    if (written && !parsed) scene_error_print(&err);
    remove(path);
    CHECK(parsed, "%s: the generated scene did not load", name);
    if (parsed) set_width(s, width);
    return parsed;
}

/* Scenes of thousands of spheres, where the compute walk walks trazador's BVH. */
static void test_generated_scenes(void) {
    if (!tmp_dir_make("test_vk_rayquery")) {
        CHECK(0, "no temporary folder");
        return;
    }
    const gen_desc random = {.kind = GEN_RANDOM, .count = 3000, .seed = 7};
    const gen_desc flake = {.kind = GEN_SPHEREFLAKE, .depth = 3, .seed = 1};
    scene s;
    render_opts opts;
    if (generated_scene(&random, "random.scene", 64, &s)) {
        render_opts_from_scene(&s, &opts);
        opts.spp = 2;
        check_same("random 3000, indirect", &s, &opts);
        opts.indirect = false;
        check_same("random 3000, direct", &s, &opts);
        opts.mode = RENDER_MODE_PATH;
        opts.bounces = 4;
        check_same("random 3000, path", &s, &opts);
        scene_free(&s);
    }
    if (generated_scene(&flake, "flake.scene", 64, &s)) {
        render_opts_from_scene(&s, &opts);
        opts.spp = 2;
        check_same("sphereflake 3", &s, &opts);
        scene_free(&s);
    }
    remove(tmpdir);
}

/* Two coincident spheres among others: every ray to them ties, and the device reports the two
 * boxes in any order; the tie rule gives the sphere stored first, as the compute walk does. */
static void test_tie(void) {
    sphere spheres[20];
    for (int k = 0; k < 20; k++)
        spheres[k] = ball((float)(k < 5 ? k : k - 2) - 9.0f, 3.0f, 5.0f, 0.3f,
                          TZ_MATERIAL_LAMBERTIAN, 0.5f, 0.5f, 0.5f);
    spheres[5] = ball(0.0f, 0.0f, 3.0f, 1.0f, TZ_MATERIAL_LAMBERTIAN, 0.8f, 0.1f, 0.1f);
    spheres[6] = ball(0.0f, 0.0f, 3.0f, 1.0f, TZ_MATERIAL_LAMBERTIAN, 0.1f, 0.8f, 0.1f);
    light lamp = {.position = {1.0f, 2.0f, -1.0f}, .power = 20.0f, .color = {1, 1, 1}};
    scene s = view(-2.0f, 2.0f, 2.0f, 16, 2, 5, spheres, 20, &lamp, 1);
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    check_same("coincident spheres", &s, &opts);
}

/* Without ray queries: the device must really lack them, and --walk rayquery must fail. */
static void test_not_offered(const vk_context *ctx) {
    printf(
        "test_vk_rayquery: %s (driver %s %s) does not offer ray queries; checking that "
        "--walk rayquery is refused\n",
        ctx->properties.deviceName, ctx->driver_name, ctx->driver_info);
    CHECK(!vk_device_has_ray_query(ctx->physical) || ctx->loop_limit,
          "the device has ray queries, but the context did not enable them");
    sphere one = ball(0.0f, 0.0f, 3.0f, 1.0f, TZ_MATERIAL_LAMBERTIAN, 0.5f, 0.5f, 0.5f);
    light lamp = {.position = {1.0f, 2.0f, -1.0f}, .power = 20.0f, .color = {1, 1, 1}};
    scene s = view(-2.0f, 2.0f, 2.0f, 4, 1, 5, &one, 1, &lamp, 1);
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    film f = {0};
    CHECK(!render_with_walk(&s, opts, RENDER_WALK_RAY_QUERY, &f),
          "--walk rayquery rendered on a device without ray queries");
    film_free(&f);
}

int main(void) {
    if (vk_context_device_count() == 0) {
        printf("test_vk_rayquery: no Vulkan device, skipped\n");
        return 77;
    }
    vk_context ctx;
    vk_context_desc desc = {.device = -1, .validate = true, .ray_query = true};
    CHECK(vk_context_init(&ctx, &desc), "context creation failed");
    bool offered = ctx.ray_query && ctx.loop_limit == 0u;
    if (ctx.device && !offered) test_not_offered(&ctx);
    if (ctx.device && offered) {
        printf("test_vk_rayquery: ray queries on %s (driver %s %s)\n", ctx.properties.deviceName,
               ctx.driver_name, ctx.driver_info);
        vk_context_destroy(&ctx);
        test_tie();
        test_example_scenes();
        test_generated_scenes();
    } else {
        vk_context_destroy(&ctx);
    }
    return check_summary("test_vk_rayquery");
}
