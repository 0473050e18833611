/* test_vk_agree.c: the Vulkan back end against the CPU back end, sample for sample (DESIGN
 * section 8). The contract: both run the same operations in the same order (the shared steps of
 * shaders/common/, precise in GLSL, no contraction in C), so +, -, *, / and sqrt round alike, and
 * cos, sin and pow are shaders/common/transcendental.h's, made of those: every film must be
 * bit-identical, pixel for pixel. Scenes built here and every scene in scenes/ are rendered small
 * (96 pixels wide, 16 samples, the same seed) by both back ends with validation on, in their own
 * mode and, for those of report mode, in path mode too. Also: an image of several tiles renders
 * every pixel once a sample; staging copies (the discrete-GPU path) give the very film mapped
 * memory gives; non-finite samples are dropped and counted alike. Exits 77 only when no Vulkan
 * device exists. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "image/diff.h"
#include "image/image.h"
#include "render/render.h"
#include "render/scene_pack.h"
#include "render/vk/vk_context.h"
#include "scene/gen.h"
#include "test_scenes.h"
#include "tmp_dir.h"

/* Renders with both back ends, validation on; false when either fails. */
static bool render_both(const scene *s, const render_opts *opts, film *cpu, film *vk) {
    render_opts o = *opts;
    o.validate = true;
    bool ok_cpu = render_film(&render_backend_cpu, s, &o, cpu),
         ok_vk = render_film(&render_backend_vulkan, s, &o, vk);
    return ok_cpu && ok_vk;
}

/* Share of pixels whose four floats are bit-identical: how exact the twin is, for the log. */
static double exact_share(const film *a, const film *b) {
    size_t n = (size_t)a->width * (size_t)a->height, same = 0;
    for (size_t k = 0; k < n; k++) same += !memcmp(&a->accum[4 * k], &b->accum[4 * k], 16);
    return (double)same / (double)n;
}

static void check_agreement(const char *name, const scene *s, const render_opts *opts) {
    film cpu = {0}, vk = {0};
    image a = {0}, b = {0};
    diff_stats st;
    bool rendered = render_both(s, opts, &cpu, &vk);
    CHECK(rendered, "%s: a back end failed", name);
    if (rendered && image_from_film(&cpu, &a) && image_from_film(&vk, &b) &&
        diff_images(&a, &b, &st)) {
        double exact = exact_share(&cpu, &vk);
        printf("%-30s %4s %3dx%-3d %2d spp: %.4f%% of pixels bit-exact, psnr %6.2f dB\n", name,
               opts->mode == RENDER_MODE_PATH ? "path" : "report", s->width, s->height, opts->spp,
               100.0 * exact, st.psnr);
        CHECK(exact == 1.0, "%s: only %.4f%% of pixels bit-exact (psnr %.2f dB, %ld differ)", name,
              100.0 * exact, st.psnr, st.differ_count);
        CHECK(cpu.nonfinite == vk.nonfinite,
              "%s: %llu non-finite samples on the CPU, %llu on Vulkan", name,
              (unsigned long long)cpu.nonfinite, (unsigned long long)vk.nonfinite);
    }
    image_free(&a);
    image_free(&b);
    film_free(&cpu);
    film_free(&vk);
}

/* check_agreement in the scene's mode and, for a scene of report mode, in path mode with path
 * mode's bounces (as --mode path) unless the scene sets them. */
static void check_both_modes(const char *name, const scene *s, const render_opts *opts) {
    check_agreement(name, s, opts);
    if (opts->mode == RENDER_MODE_PATH) return;
    render_opts path = *opts;
    path.mode = RENDER_MODE_PATH;
    if (!s->bounces_given) path.bounces = scene_default_bounces(RENDER_MODE_PATH);
    check_agreement(name, s, &path);
}

/* Every material, two coloured lights, a visible background, a huge floor; seen at an angle. */
static sphere materials_spheres[5];
static light materials_lights[] = {
    {.position = {-3.0f, 4.0f, -1.0f}, .power = 40.0f, .color = {1.0f, 0.9f, 0.8f}},
    {.position = {3.0f, 2.0f, 1.0f}, .power = 15.0f, .color = {0.6f, 0.7f, 1.0f}},
};

static scene materials_scene(void) {
    sphere *b = materials_spheres;
    b[0] = ball(0.0f, -1000.0f, 0.0f, 999.0f, TZ_MATERIAL_LAMBERTIAN, 0.7f, 0.7f, 0.6f);
    b[1] = ball(-1.6f, 0.0f, 3.0f, 1.0f, TZ_MATERIAL_LAMBERTIAN, 0.8f, 0.2f, 0.2f);
    b[2] = ball(0.6f, -0.3f, 2.0f, 0.7f, TZ_MATERIAL_PHONG, 0.2f, 0.3f, 0.8f);
    ball_material(&b[2])->ks = 0.4f, ball_material(&b[2])->alpha = 30.0f;
    b[3] = ball(1.2f, 0.4f, 5.0f, 1.4f, TZ_MATERIAL_MIRROR, 0.9f, 0.9f, 0.8f);
    b[4] = ball(-0.4f, -0.5f, 0.8f, 0.5f, TZ_MATERIAL_REFRACTIVE, 1.0f, 1.0f, 1.0f);
    scene s = view(-4.0f, 4.0f, 3.0f, 96, 16, 7, b, 5, materials_lights, 2);
    s.camera_position = (vec3){0.5f, 1.2f, -4.0f};
    s.camera_direction = (vec3){-0.1f, -0.2f, 1.0f};
    s.background = (vec3){0.3f, 0.5f, 0.8f};
    return s;
}

/* A closed room of radius-1e5 walls (float32 cancellation would show), glass and Phong inside. */
static sphere room_spheres[8];
static light room_light = {.position = {0.0f, 1.6f, 0.6f}, .power = 9.0f, .color = {1, 1, 1}};

static scene room_scene(void) {
    sphere *b = room_spheres;
    const float wall = 1e5f;
    b[0] = ball(-wall - 2.0f, 0.0f, 0.0f, wall, TZ_MATERIAL_LAMBERTIAN, 0.75f, 0.12f, 0.10f);
    b[1] = ball(wall + 2.0f, 0.0f, 0.0f, wall, TZ_MATERIAL_LAMBERTIAN, 0.12f, 0.70f, 0.15f);
    b[2] = ball(0.0f, -wall - 2.0f, 0.0f, wall, TZ_MATERIAL_LAMBERTIAN, 0.75f, 0.75f, 0.75f);
    b[3] = ball(0.0f, wall + 2.0f, 0.0f, wall, TZ_MATERIAL_LAMBERTIAN, 0.75f, 0.75f, 0.75f);
    b[4] = ball(0.0f, 0.0f, wall + 3.0f, wall, TZ_MATERIAL_LAMBERTIAN, 0.75f, 0.75f, 0.75f);
    b[5] = ball(0.0f, 0.0f, -wall - 8.0f, wall, TZ_MATERIAL_LAMBERTIAN, 0.75f, 0.75f, 0.75f);
    b[6] = ball(-0.85f, -1.3f, 1.4f, 0.7f, TZ_MATERIAL_PHONG, 0.85f, 0.85f, 0.85f);
    ball_material(&b[6])->ks = 0.25f, ball_material(&b[6])->alpha = 40.0f;
    b[7] = ball(0.85f, -1.4f, 0.3f, 0.6f, TZ_MATERIAL_REFRACTIVE, 1.0f, 1.0f, 1.0f);
    return view(-6.9f, 4.0f, 4.0f, 96, 16, 3, b, 8, &room_light, 1);
}

/* A grid of n spheres of every material in front of a wall, lit by m lights, `width` pixels
 * across, `samples` spp: past TZ_UNROLL_MAX_SPHERES spheres the shader walks the BVH (and, with
 * few lights, is also checked with --no-bvh, its sphere loop), past TZ_UNROLL_MAX_LIGHTS it
 * loops over the lights instead of unrolling them; in path mode too where path_too. */
static void check_crowd(const char *name, int n, int m, int width, int samples, bool path_too) {
    sphere *spheres = calloc((size_t)n + 1, sizeof *spheres);
    light *lights = calloc((size_t)m, sizeof *lights);
    if (!spheres || !lights) {
        CHECK(0, "%s: out of memory", name);
        free(spheres);
        free(lights);
        return;
    }
    spheres[0] = ball(0.0f, 0.0f, 1006.0f, 1000.0f, TZ_MATERIAL_LAMBERTIAN, 0.6f, 0.6f, 0.6f);
    for (int k = 1; k <= n; k++) {
        material_kind kind = (material_kind)(k % 4);
        spheres[k] =
            ball((float)(k % 8) - 3.5f, (float)(k / 8) - 2.0f, 3.0f, 0.35f + 0.02f * (float)(k % 5),
                 kind, 0.3f + 0.08f * (float)(k % 7), 0.5f, 0.9f - 0.1f * (float)(k % 6));
        material *mk = ball_material(&spheres[k]);
        if (kind == TZ_MATERIAL_PHONG) mk->ks = 0.3f, mk->alpha = 25.0f;
        if (kind == TZ_MATERIAL_REFRACTIVE) mk->ior = 1.45f;
    }
    for (int k = 0; k < m; k++)
        lights[k] = (light){.position = {2.0f * (float)k - (float)m, 3.0f, -1.0f + 0.5f * (float)k},
                            .power = 30.0f / (float)m,
                            .color = {1.0f, 0.9f, 0.8f}};
    scene s = view(-5.0f, 4.0f, 3.0f, width, samples, 11, spheres, n + 1, lights, m);
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    if (path_too)
        check_both_modes(name, &s, &opts);
    else
        check_agreement(name, &s, &opts);
    if (n + 1 > TZ_UNROLL_MAX_SPHERES && m <= 6) { /* the shader's sphere loop, without a BVH */
        char no_bvh[96];
        snprintf(no_bvh, sizeof no_bvh, "%s, --no-bvh", name);
        opts.no_bvh = true;
        check_agreement(no_bvh, &s, &opts);
    }
    free(spheres);
    free(lights);
}

static void test_built_scenes(void) {
    scene s = materials_scene();
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    check_both_modes("materials", &s, &opts);
    render_opts other = opts; /* each mode with the sampler it does not default to */
    other.sampler = RENDER_SAMPLER_SOBOL;
    check_agreement("materials, sobol in report mode", &s, &other);
    other.sampler = RENDER_SAMPLER_RANDOM;
    other.mode = RENDER_MODE_PATH;
    other.bounces = scene_default_bounces(RENDER_MODE_PATH);
    check_agreement("materials, random in path mode", &s, &other);
    opts.indirect = false;
    opts.no_jitter = true;
    check_agreement("materials direct", &s, &opts);
    ball_material(&s.spheres[2])->ks = 0.0f; /* no Phong lobe: Lambertian, mirror and glass */
    check_agreement("materials direct, ks 0", &s, &opts);
    s = room_scene();
    render_opts_from_scene(&s, &opts);
    check_both_modes("room of 1e5 walls", &s, &opts);
    opts.bounces = 1; /* the glass sphere's inside goes black: the limit, on both */
    check_agreement("room, bounces 1", &s, &opts);
    /* the BVH walk, and with --no-bvh the sphere loop; lights looped, then unrolled */
    check_crowd("crowd 40 spheres 6 lights", 39, 6, 96, 16, true);
    check_crowd("crowd 24 spheres 2 lights", 23, 2, 96, 16, true);
    check_crowd("crowd 6 spheres 5 lights", 5, 5, 96, 16, true); /* spheres unrolled, light loop */
    /* So many lights leave a BVH walk too few of lavapipe's loop passes: every sphere is tested
     * instead (it was refused). */
    check_crowd("crowd 20 spheres 120 lights", 19, 120, 96, 16, true);
    /* Unrolled sphere tests cost no loop passes: 4,096 lights fit lavapipe's limit (they were
     * refused; looping over the 16 spheres, a sample would take about 148,000 passes and the
     * image would come out wrong). Path mode's sample needs more passes than the limit: refused. */
    check_crowd("crowd 16 spheres 4096 lights", 15, 4096, 16, 1, false);
}

/* Every scene in scenes/, 96 pixels across its own plane, 16 samples. */
static void test_example_scenes(void) { each_example_scene(96, 16, check_both_modes); }

/* Two coincident spheres, red and green, written after five small ones: an exact tie on every
 * ray to them, which goes to the sphere stored first (in BVH order) on both back ends, with and
 * without the BVH walk, whichever of the two is written first. */
static void test_ties(void) {
    for (int red_first = 0; red_first <= 1; red_first++) {
        sphere spheres[20];
        for (int k = 0; k < 20; k++)
            spheres[k] = ball((float)(k < 5 ? k : k - 2) - 9.0f, 3.0f, 5.0f, 0.3f,
                              TZ_MATERIAL_LAMBERTIAN, 0.5f, 0.5f, 0.5f);
        for (int k = 5; k < 7; k++) {
            bool red = (k == 5) == (red_first == 1);
            spheres[k] = ball(0.0f, 0.0f, 3.0f, 1.0f, TZ_MATERIAL_LAMBERTIAN, red ? 0.8f : 0.1f,
                              red ? 0.1f : 0.8f, 0.1f);
        }
        light lamp = {.position = {1.0f, 2.0f, -1.0f}, .power = 20.0f, .color = {1, 1, 1}};
        scene s = view(-2.0f, 2.0f, 2.0f, 16, 2, 5, spheres, 20, &lamp, 1);
        render_opts opts;
        render_opts_from_scene(&s, &opts);
        packed_scene packed;
        bool red_stored_first = false;
        if (scene_pack(&s, &opts, &packed)) {
            int first = -1; /* the pair's first stored sphere */
            for (int k = 0; k < 20 && first < 0; k++)
                if (packed.spheres[k].center_radius.w == 1.0f) first = k;
            red_stored_first =
                first >= 0 &&
                packed.materials[(int)packed.spheres[first].material].color_ks.x > 0.5f;
            scene_pack_free(&packed);
        }
        film cpu = {0}, vk = {0}, brute = {0};
        render_opts no_bvh = opts;
        no_bvh.no_bvh = true;
        if (render_both(&s, &opts, &cpu, &vk) &&
            render_film(&render_backend_cpu, &s, &no_bvh, &brute)) {
            size_t centre = (8u * 16u + 8u) * 4u; /* a pixel on the pair */
            bool red_seen = cpu.accum[centre] > cpu.accum[centre + 1];
            CHECK(red_seen == red_stored_first,
                  "ties: the C back end saw the sphere stored second");
            CHECK(!memcmp(cpu.accum, vk.accum, 16 * 16 * 4 * sizeof(float)),
                  "ties (%s written first): the films differ", red_first ? "red" : "green");
            CHECK(!memcmp(cpu.accum, brute.accum, 16 * 16 * 4 * sizeof(float)),
                  "ties (%s written first): the BVH walk changed the film",
                  red_first ? "red" : "green");
        } else {
            CHECK(0, "ties: a back end failed");
        }
        film_free(&brute);
        film_free(&cpu);
        film_free(&vk);
    }
}

/* An image of several tiles, partial ones at the right and bottom edges: every pixel is
 * rendered once a sample (the workgroups of a dispatch take the tile's blocks in a strided
 * order), and the image agrees with the C one. */
static void test_tiles(void) {
    scene s = materials_scene();
    set_width(&s, 525); /* 256 + 256 + 13 by 256 + 138: partial workgroups on both axes */
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.spp = 2;
    opts.indirect = false;
    film vk = {0};
    opts.validate = true;
    if (render_film(&render_backend_vulkan, &s, &opts, &vk)) {
        size_t n = (size_t)vk.width * (size_t)vk.height, wrong = 0;
        for (size_t k = 0; k < n; k++) wrong += vk.accum[4 * k + 3] != 2.0f;
        CHECK(s.height > 256 && wrong == 0, "%dx%d: %zu pixels not rendered exactly twice", s.width,
              s.height, wrong);
    } else {
        CHECK(0, "tiles: the Vulkan render failed");
    }
    film_free(&vk);
    check_agreement("materials 525 wide", &s, &opts);
}

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

/* Renders s on Vulkan with `walk` (render_opts.walk, as `render --walk` sets it); false when it
 * failed. */
static bool render_with_walk(const scene *s, const render_opts *opts, render_walk walk, film *f) {
    render_opts o = *opts;
    o.walk = walk;
    return render_film(&render_backend_vulkan, s, &o, f);
}

/* The subgroup's cooperative BVH walk and the walk per invocation over the binary and the wide
 * BVH (TRAZADOR_VK_BVH) give bit-identical films (the tie rule) on generated scenes, report mode
 * and path mode, with and without the indirect bounce. */
static void check_walks(const char *name, const scene *s, render_opts opts) {
    opts.validate = true;
    const char *layouts[] = {"binary", "wide"};
    film coop = {0}, alone[2] = {{0}, {0}};
    bool ok = render_with_walk(s, &opts, RENDER_WALK_COOPERATIVE, &coop);
    for (int k = 0; k < 2; k++) {
        setenv("TRAZADOR_VK_BVH", layouts[k], 1);
        ok = render_with_walk(s, &opts, RENDER_WALK_COMPUTE, &alone[k]) && ok;
    }
    unsetenv("TRAZADOR_VK_BVH");
    CHECK(ok, "%s: a walk failed", name);
    size_t bytes = (size_t)s->width * s->height * 4 * sizeof(float);
    if (ok) {
        CHECK(!memcmp(coop.accum, alone[0].accum, bytes),
              "%s: the cooperative walk changed the film", name);
        CHECK(!memcmp(alone[1].accum, alone[0].accum, bytes), "%s: the wide BVH changed the film",
              name);
    }
    film_free(&coop);
    film_free(&alone[0]);
    film_free(&alone[1]);
}

static void test_walks(void) {
    if (!tmp_dir_make("test_vk_agree")) {
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
        check_walks("random 3000, indirect", &s, opts);
        opts.indirect = false;
        check_walks("random 3000, direct", &s, opts);
        opts.mode = RENDER_MODE_PATH;
        opts.bounces = 4;
        check_walks("random 3000, path", &s, opts);
        scene_free(&s);
    }
    if (generated_scene(&flake, "flake.scene", 64, &s)) {
        render_opts_from_scene(&s, &opts);
        opts.spp = 2;
        check_walks("sphereflake 3", &s, opts);
        opts.mode = RENDER_MODE_PATH;
        check_walks("sphereflake 3, path", &s, opts);
        scene_free(&s);
    }
    /* Triangles, smooth and flat, and their leaves in the wide nodes. */
    scene_error err;
    if (scene_parse_file(TRAZADOR_SOURCE_DIR "/scenes/mesh.scene", &s, &err)) {
        set_width(&s, 48);
        render_opts_from_scene(&s, &opts);
        opts.spp = 2;
        check_walks("mesh.scene", &s, opts);
        scene_free(&s);
    } else {
        CHECK(0, "%s:%d:%d: %s", err.file, err.line, err.col, err.message);
    }
    remove(tmpdir);
}

/* TRAZADOR_VK_STAGING=1 sends every buffer through staging copies, as on a discrete GPU, and
 * TRAZADOR_VK_NO_IMPORT=1 keeps the driver's own device memory, as where the process's cannot be
 * imported (lavapipe imports it by default): the same film all three ways. */
static void test_staging(void) {
    scene s = materials_scene();
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.validate = true;
    film imported = {0}, mapped = {0}, staged = {0};
    bool ok = render_film(&render_backend_vulkan, &s, &opts, &imported);
    setenv("TRAZADOR_VK_NO_IMPORT", "1", 1);
    ok = render_film(&render_backend_vulkan, &s, &opts, &mapped) && ok;
    unsetenv("TRAZADOR_VK_NO_IMPORT");
    setenv("TRAZADOR_VK_STAGING", "1", 1);
    ok = render_film(&render_backend_vulkan, &s, &opts, &staged) && ok;
    unsetenv("TRAZADOR_VK_STAGING");
    CHECK(ok, "staging: a render failed");
    size_t bytes = (size_t)s.width * s.height * 4 * sizeof(float);
    if (ok) {
        CHECK(!memcmp(imported.accum, mapped.accum, bytes), "device memory changed the film");
        CHECK(!memcmp(imported.accum, staged.accum, bytes), "staging copies changed the film");
    }
    film_free(&imported);
    film_free(&mapped);
    film_free(&staged);
}

/* The centre ray of a 3 x 3 image hits the sphere exactly at (0, 0, -1), where the light is:
 * zero distance, NaN radiance. Both back ends drop those samples and count them. */
static void test_nonfinite(void) {
    sphere lit = ball(0.0f, 0.0f, 0.0f, 1.0f, TZ_MATERIAL_LAMBERTIAN, 0.5f, 0.5f, 0.5f);
    light lamp = {.position = {0.0f, 0.0f, -1.0f}, .power = 10.0f, .color = {1, 1, 1}};
    scene s = view(-4.0f, 0.75f, 0.75f, 3, 4, 1, &lit, 1, &lamp, 1);
    s.indirect = false;
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.no_jitter = true;
    film cpu = {0}, vk = {0};
    if (render_both(&s, &opts, &cpu, &vk)) {
        CHECK(cpu.nonfinite == 4 && vk.nonfinite == 4, "non-finite samples: cpu %llu, vulkan %llu",
              (unsigned long long)cpu.nonfinite, (unsigned long long)vk.nonfinite);
        CHECK(cpu.accum[4 * 4 + 3] == 0.0f && vk.accum[4 * 4 + 3] == 0.0f,
              "the centre pixel counted a non-finite sample");
        CHECK(!memcmp(cpu.accum, vk.accum, 9 * 4 * sizeof(float)), "the films differ");
    } else {
        CHECK(0, "non-finite: a back end failed");
    }
    film_free(&cpu);
    film_free(&vk);
}

int main(void) {
    if (vk_context_device_count() == 0) {
        printf("test_vk_agree: no Vulkan device, skipped\n");
        return 77;
    }
    test_built_scenes();
    test_example_scenes();
    test_ties();
    test_tiles();
    test_staging();
    test_nonfinite();
    test_walks();
    return check_summary("test_vk_agree");
}
