/* test_packet.c: every build of the packet integrator this machine runs (the CPU back end renders
 * with the fastest) returns bit for bit what the one-sample reference integrator_report_sample
 * returns, and traces the same rays, on every scene of scenes/, generated scenes on both of its
 * intersection paths (every sphere, the BVH), a scene of nested and overlapping spheres with the
 * camera inside glass and a cloud of overlapping spheres with exact duplicates; under every option
 * that changes the integrator's path. So does every path-mode build against integrator_path_sample,
 * on the path scenes, point lights with emitters, the scenes above in path mode and a BVH scene
 * with an emitter, under every path-mode option. */
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "render/cpu/integrator.h"
#include "render/render.h"
#include "render/scene_pack.h"
#include "scene/gen.h"

#define SIDE 64 /* pixels of the square test image */

/* Nested, overlapping and touching spheres of every material; the camera sits in a glass ball. */
static const char tangle[] =
    "camera position 0 0 0 direction 0.1 0 1 up 0 1 0\n"
    "plane width 4 height 4 pixel 0.1\n"
    "light position 0 3 2 power 20\n"
    "light position -2 -1 6 power 5 color 1 0.5 0.2\n"
    "sphere refractive center 0 0 0 radius 1.5 ior 1.33\n"
    "sphere mirror center 0.6 0 5 radius 1 color 0.9 0.8 0.7\n"
    "sphere refractive center -0.4 0.2 4.5 radius 0.8 ior 1.7\n"
    "sphere refractive center -0.4 0.2 4.5 radius 0.4 ior 1.2\n"
    "sphere phong center 1.5 -0.5 4 radius 0.7 ks 0.6 alpha 12\n"
    "sphere lambertian center 0 -1001.5 0 radius 1000 color 0.7 0.7 0.7\n"
    "sphere lambertian center 0 0 1010 radius 1000 color 0.2 0.4 0.8\n"
    "background 0.1 0.2 0.3\n";

/* Few enough primitives to be tested whole: triangles of every material beside spheres, a
 * smooth triangle whose normals lean, an emitting quad and a point light (in path mode; seed
 * mode's test drops the emission). */
static const char facets[] =
    "camera position 0 1 -4 direction 0 -0.2 1 up 0 1 0\n"
    "plane width 4 height 4 pixel 0.1\n"
    "light position 1 3 -1 power 8\n"
    "quad lambertian v0 -3 -1 -3 v1 -3 -1 3 v2 3 -1 3 v3 3 -1 -3 color 0.7 0.7 0.7\n"
    "quad lambertian v0 -1 2.5 -1 v1 1 2.5 -1 v2 1 2.5 1 v3 -1 2.5 1 color 0 0 0 "
    "emission 6 6 5\n"
    "triangle mirror v0 -2 -1 2 v1 0 2 2.5 v2 2 -1 2 color 0.9 0.9 0.9\n"
    "triangle phong v0 -2 -1 0 v1 -1 1 0.5 v2 -0.5 -1 0 ks 0.5 alpha 20 "
    "n0 0 0.3 -1 n1 0.4 0 -1 n2 -0.3 0.2 -1\n"
    "sphere refractive center 1 -0.4 0 radius 0.6 ior 1.5\n"
    "sphere lambertian center -1 -0.6 1 radius 0.4 color 0.2 0.5 0.8 emission 2 2 2\n"
    "background 0.1 0.1 0.2\n"
    "render mode path\n";

/* The microfacet kinds: rough mirrors, rough glass and pbr spheres and faces (one smooth, so that
 * its lobes fold), under a point light and emitters, beside a Phong sphere; path mode (seed mode's
 * test drops the emission). */
static const char rough[] =
    "camera position 0 1 -5 direction 0 -0.15 1 up 0 1 0\n"
    "plane width 4 height 4 pixel 0.1\n"
    "light position 2 3 -2 power 20\n"
    "quad pbr v0 -3 -1 -3 v1 -3 -1 3 v2 3 -1 3 v3 3 -1 -3 color 0.7 0.6 0.5 roughness 0.6\n"
    "triangle pbr v0 -2 -1 2 v1 -1 1.5 2.5 v2 0.5 -1 2 metallic 1 roughness 0.2 "
    "color 0.9 0.7 0.3 n0 0 0.3 -1 n1 0.4 0 -1 n2 -0.3 0.2 -1\n"
    "sphere mirror center -1.2 -0.4 0.5 radius 0.6 roughness 0.3 color 0.9 0.9 0.9\n"
    "sphere mirror center 1.2 -0.4 0.5 radius 0.6 roughness 0.05\n"
    "sphere pbr center 0 -0.5 -0.5 radius 0.5 color 0.8 0.1 0.1 roughness 0.4 metallic 0.3\n"
    "sphere pbr center 0.3 0.6 1 radius 0.4 color 0.2 0.8 0.2 roughness 1\n"
    "sphere phong center -0.4 0.5 -1 radius 0.3 ks 0.4 alpha 20\n"
    "sphere refractive center 0.9 0.2 -1.2 radius 0.35 roughness 0.3\n"
    "sphere refractive center -1 -0.7 -1.5 radius 0.3 roughness 0.8 ior 1.3 color 0.9 1 0.9\n"
    "sphere lambertian center 0 3 0 radius 0.5 color 0 0 0 emission 6 6 5\n"
    "background 0.1 0.1 0.2\n"
    "render mode path\n";

static int bits_equal(vec3 a, vec3 b) { return memcmp(&a, &b, sizeof a) == 0; }

/* The builds under test (seed or path mode) and the one-sample reference they must match. */
static packet_integrator builds[PACKET_BUILDS_MAX];
static int build_count;
static vec3 (*reference)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index);
static bool path_mode;
static bool check_runs; /* path mode: the runs of samples too (the scene's own settings only) */

/* Every pixel of a SIDE x SIDE render by build b, packets of every width from 1 to its own; with
 * want_light, a quarter of the pixels at least must not be black. */
static void compare_build(const char *name, const packed_scene *p, const packet_integrator *b,
                          bool want_light) {
    int differing = 0, lit = 0;
    uint64_t rays_one = 0, rays_packet = 0;
    for (uint32_t j = 0; j < SIDE; j++) {
        uint32_t lanes = 1 + j % b->width;
        for (uint32_t i = 0; i < SIDE; i += lanes) {
            uint32_t n = SIDE - i < lanes ? SIDE - i : lanes;
            uint32_t sample = (i + j) % 3;
            vec3 out[PACKET_LANES_MAX];
            uint64_t before = integrator_rays_traced();
            b->sample(p, i, j, n, sample, out);
            rays_packet += integrator_rays_traced() - before;
            for (uint32_t k = 0; k < n; k++) {
                before = integrator_rays_traced();
                vec3 one = reference(p, i + k, j, sample);
                rays_one += integrator_rays_traced() - before;
                if (!bits_equal(one, out[k]) && differing++ < 3)
                    fprintf(stderr, "%s, %s: pixel %u,%u: %.9g %.9g %.9g (one) vs %.9g %.9g %.9g\n",
                            name, b->name, i + k, j, one.x, one.y, one.z, out[k].x, out[k].y,
                            out[k].z);
                lit += one.x + one.y + one.z > 0.0f;
            }
        }
    }
    CHECK(differing == 0, "%s, %s: %d pixels differ", name, b->name, differing);
    CHECK(rays_one == rays_packet, "%s, %s: %llu rays one at a time, %llu in packets", name,
          b->name, (unsigned long long)rays_one, (unsigned long long)rays_packet);
    CHECK(!want_light || lit > SIDE * SIDE / 4, "%s: only %d pixels have light", name, lit);
}

/* Path builds' runs of samples: every pixel of a SIDE x SIDE render by build b, 1 to 4 samples
 * a run, packets of every width from 1 to its own, against integrator_path_sample. */
static void compare_samples(const char *name, const packed_scene *p, const packet_integrator *b) {
    int differing = 0;
    uint64_t rays_one = 0, rays_packet = 0;
    for (uint32_t j = 0; j < SIDE; j++) {
        uint32_t lanes = 1 + (j * 7) % b->width, count = 1 + j % 4, first = j % 3;
        for (uint32_t i = 0; i < SIDE; i += lanes) {
            uint32_t n = SIDE - i < lanes ? SIDE - i : lanes;
            vec3 out[PACKET_LANES_MAX * 4];
            uint64_t before = integrator_rays_traced();
            b->samples(p, i, j, n, first, count, out);
            rays_packet += integrator_rays_traced() - before;
            for (uint32_t s = 0; s < count; s++)
                for (uint32_t k = 0; k < n; k++) {
                    before = integrator_rays_traced();
                    vec3 one = integrator_path_sample(p, i + k, j, first + s);
                    rays_one += integrator_rays_traced() - before;
                    if (!bits_equal(one, out[s * n + k]) && differing++ < 3)
                        fprintf(stderr, "%s, %s runs: pixel %u,%u sample %u differs\n", name,
                                b->name, i + k, j, first + s);
                }
        }
    }
    CHECK(differing == 0, "%s, %s runs: %d samples differ", name, b->name, differing);
    CHECK(rays_one == rays_packet, "%s, %s runs: %llu rays one at a time, %llu in runs", name,
          b->name, (unsigned long long)rays_one, (unsigned long long)rays_packet);
}

/* The scene with these options through every build. */
static void compare(const char *name, const scene *s, const render_opts *o, bool want_light) {
    packed_scene p;
    CHECK(scene_pack(s, o, &p), "%s: pack failed", name);
    for (int b = 0; b < build_count; b++) {
        compare_build(name, &p, &builds[b], want_light);
        CHECK(!path_mode == !builds[b].samples, "%s: runs of samples in path builds only",
              builds[b].name);
        if (path_mode && check_runs && builds[b].samples) compare_samples(name, &p, &builds[b]);
    }
    scene_pack_free(&p);
}

/* The scene's own settings, then each option that changes the path a sample takes. */
static void compare_variants(const char *name, scene *s) {
    s->pixel_size = s->plane_width / (float)SIDE;
    s->plane_height = s->plane_width;
    s->width = s->height = SIDE;
    render_opts o;
    render_opts_from_scene(s, &o);
    compare(name, s, &o, true);
    render_opts v = o;
    v.indirect = !o.indirect;
    compare(name, s, &v, false);
    v = o;
    v.no_jitter = true;
    v.bounces = 1;
    compare(name, s, &v, true);
    v = o;
    v.bounces = 0;
    v.seed = 7;
    compare(name, s, &v, false);
    v = o;
    v.no_bvh = true;
    compare(name, s, &v, true);
    v = o;
    v.sampler = RENDER_SAMPLER_SOBOL;
    compare(name, s, &v, true);
}

/* In path mode: the scene's own settings, then each option that changes a path. */
static void compare_path_variants(const char *name, scene *s) {
    s->pixel_size = s->plane_width / (float)SIDE;
    s->plane_height = s->plane_width;
    s->width = s->height = SIDE;
    render_opts o;
    render_opts_from_scene(s, &o);
    o.mode = RENDER_MODE_PATH;
    check_runs = true;
    compare(name, s, &o, true);
    check_runs = false;
    render_opts v = o;
    v.roulette = !o.roulette;
    compare(name, s, &v, false);
    v = o;
    v.strategy = PATH_LIGHTS_ONLY;
    compare(name, s, &v, false);
    v = o;
    v.strategy = PATH_BSDF_ONLY;
    v.seed = 7;
    compare(name, s, &v, false);
    v = o;
    v.no_jitter = true;
    v.bounces = 1;
    compare(name, s, &v, false);
    v = o;
    v.bounces = 0;
    compare(name, s, &v, false);
    v = o;
    v.no_bvh = true;
    compare(name, s, &v, false);
    v = o;
    v.sampler = scene_sampler_of(o.sampler, o.mode) == RENDER_SAMPLER_SOBOL ? RENDER_SAMPLER_RANDOM
                                                                            : RENDER_SAMPLER_SOBOL;
    check_runs = true;
    compare(name, s, &v, false);
    v = o;
    v.light_samples = 3;
    compare(name, s, &v, false);
    check_runs = false;
}

/* Report mode's variants, or path mode's when the tests are on the path builds. */
static void compare_scene(const char *name, scene *s) {
    if (path_mode)
        compare_path_variants(name, s);
    else
        compare_variants(name, s);
}

static void compare_file(const char *file) {
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/%s", TRAZADOR_SOURCE_DIR, file);
    scene s;
    scene_error err;
    if (!scene_parse_file(path, &s, &err)) {
        scene_error_print(&err);
        CHECK(0, "%s does not parse", path);
        return;
    }
    compare_scene(file, &s);
    scene_free(&s);
}

/* Parses the scene text and compares its variants. */
static void compare_text(const char *name, const char *text, size_t length) {
    scene s;
    scene_error err;
    if (text && scene_parse_string(text, length, name, &s, &err)) {
        compare_scene(name, &s);
        scene_free(&s);
    } else {
        if (text) scene_error_print(&err);
        CHECK(0, "%s does not parse", name);
    }
}

/* Writes a scene with write(fp, arg) into memory, then compares its variants. */
static void compare_written(const char *name, bool (*write)(FILE *fp, const void *arg),
                            const void *arg) {
    char *text = NULL;
    size_t length = 0;
    FILE *fp = open_memstream(&text, &length);
    CHECK(fp != NULL, "%s: open_memstream failed", name);
    if (!fp) return;
    bool written = write(fp, arg);
    fclose(fp);
    CHECK(written, "%s: writing the scene failed", name);
    if (written) compare_text(name, text, length);
    free(text);
}

/* A `trazador gen` scene; arg is its gen_desc. */
static bool write_generated(FILE *fp, const void *arg) { return gen_write(arg, fp); }

/* 150 overlapping and nested spheres of all four materials in a 4-unit cube, every tenth one
 * given twice (exact ties), seen from outside: enough to need the BVH. */
static bool write_cloud(FILE *fp, const void *unused) {
    (void)unused;
    fprintf(fp,
            "camera position 0.3 0.2 -7 direction 0 0 1 up 0 1 0\n"
            "plane width 4 height 4 pixel 0.1\n"
            "light position 3 4 -5 power 60\nlight position -4 1 -3 power 30\n"
            "background 0.2 0.3 0.4\n");
    const char *materials[] = {"lambertian", "phong ks 0.4 alpha 20", "mirror",
                               "refractive ior 1.4"};
    uint32_t state = 12345;
    for (int k = 0; k < 150; k++) {
        float v[4];
        for (int c = 0; c < 4; c++) {
            state = state * 1664525u + 1013904223u;
            v[c] = (float)(state >> 8) / 16777216.0f;
        }
        char line[200];
        snprintf(line, sizeof line, "sphere %s center %.3f %.3f %.3f radius %.3f\n",
                 materials[k % 4], 4.0f * v[0] - 2.0f, 4.0f * v[1] - 2.0f, 4.0f * v[2] - 2.0f,
                 0.1f + 0.6f * v[3]);
        fputs(line, fp);
        if (k % 10 == 0) fputs(line, fp);
    }
    return true;
}

/* 24 coincident spheres of different colours (more than a leaf holds, so the BVH splits them over
 * leaves): every hit is an exact tie, which the lowest index must win whatever leaf the walk
 * enters first. */
static bool write_coincident(FILE *fp, const void *unused) {
    (void)unused;
    fprintf(fp,
            "camera position 0 0 -5 direction 0 0 1 up 0 1 0\n"
            "plane width 4 height 4 pixel 0.1\n"
            "light position 2 3 -4 power 40\n"
            "sphere lambertian center 0 -1001.5 0 radius 1000 color 0.5 0.5 0.5\n");
    for (int k = 0; k < 24; k++)
        fprintf(fp, "sphere lambertian center 0 0 0 radius 1.2 color %.3f %.3f 0.5\n",
                0.1f + 0.035f * (float)k, 0.9f - 0.03f * (float)k);
    return true;
}

/* Phong and Lambertian spheres under point lights and two emitters (one of them seen through
 * glass, one tiny), a mirror; path mode. */
static const char lit[] =
    "camera position 0 1 -6 direction 0 -0.1 1 up 0 1 0\n"
    "plane width 4 height 4 pixel 0.1\n"
    "light position 2 4 -3 power 30\n"
    "light position -3 2 1 power 10 color 0.4 0.6 1\n"
    "sphere lambertian center 0 -1000 0 radius 1000 color 0.6 0.6 0.6\n"
    "sphere phong center -1 0.7 1 radius 0.7 color 0.5 0.2 0.1 ks 0.4 alpha 25\n"
    "sphere phong center 1.2 0.5 0 radius 0.5 color 0.1 0.1 0.1 ks 0.8 alpha 200\n"
    "sphere mirror center 0 1 3 radius 1 color 0.9 0.9 0.9\n"
    "sphere refractive center 0.3 0.4 -1.5 radius 0.4 ior 1.5\n"
    "sphere lambertian center 0 3.5 1 radius 0.6 color 0 0 0 emission 8 7 6\n"
    "sphere lambertian center 1.5 0.1 -1 radius 0.1 color 0.5 0.5 0.5 emission 50 20 10\n"
    "background 0.05 0.05 0.1\n"
    "render mode path bounces 10\n";

/* `trazador gen random` (200 spheres: the BVH) lit by an emitter above it, its render line made
 * path mode's; arg its gen_desc. */
static bool write_generated_lit(FILE *fp, const void *arg) {
    char *text = NULL;
    size_t length = 0;
    FILE *gen = open_memstream(&text, &length);
    if (!gen) return false;
    bool written = gen_write(arg, gen);
    fclose(gen);
    for (char *line = strtok(text, "\n"); written && line; line = strtok(NULL, "\n"))
        if (strncmp(line, "render", 6)) fprintf(fp, "%s\n", line);
    free(text);
    fputs(
        "sphere lambertian center 0 30 0 radius 8 color 0 0 0 emission 6 6 6\n"
        "render mode path\n",
        fp);
    return written;
}

/* The example scene named file into text (size bytes), then the line `extra`; false when it
 * does not fit. */
static bool read_scene(const char *file, char *text, size_t size, const char *extra) {
    char path[512];
    snprintf(path, sizeof path, "%s/scenes/%s", TRAZADOR_SOURCE_DIR, file);
    FILE *fp = fopen(path, "r");
    size_t n = fp ? fread(text, 1, size - 1, fp) : 0;
    if (fp) fclose(fp);
    text[n] = 0;
    bool ok = fp && n + strlen(extra) + 2 < size;
    CHECK(ok, "%s: cannot read it whole", path);
    if (ok) strcat(strcat(text, "\n"), extra);
    return ok;
}

/* The scene text arg in report mode: without its render lines and emission. */
static bool write_seed_mode(FILE *fp, const void *arg) {
    char text[4096];
    snprintf(text, sizeof text, "%s", (const char *)arg);
    for (char *line = strtok(text, "\n"); line; line = strtok(NULL, "\n")) {
        if (!strncmp(line, "render", 6)) continue;
        char *emission = strstr(line, "emission");
        if (emission) *emission = 0;
        if (fprintf(fp, "%s\n", line) < 0) return false;
    }
    return true;
}

/* Every test scene through the path-mode builds. */
static void compare_path_builds(void) {
    path_mode = true;
    reference = integrator_path_sample;
    build_count = integrator_path_list(builds);
    for (int b = 0; b < build_count; b++)
        printf("path integrator build %s, %u lanes\n", builds[b].name, builds[b].width);
    CHECK(build_count >= 2 && !strcmp(builds[build_count - 1].name, RENDER_CPU_REFERENCE) &&
              !strcmp(integrator_path_choose(RENDER_CPU_REFERENCE, false).name,
                      RENDER_CPU_REFERENCE) &&
              !strcmp(integrator_path_choose(NULL, false).name, builds[0].name),
          "the path builds: the reference last and by name only, the fastest first");
    const char *files[] = {"cornell_path.scene", "caustic.scene",     "all.scene",
                           "refraction.scene",   "cornell_box.scene", "mesh.scene"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) compare_file(files[k]);
    compare_text("facets", facets, sizeof facets - 1);
    compare_text("lit", lit, sizeof lit - 1);
    compare_text("tangle", tangle, sizeof tangle - 1);
    compare_text("rough", rough, sizeof rough - 1);
    const gen_desc random200 = {.kind = GEN_RANDOM, .count = 200, .seed = 3};
    compare_written("random 200 with an emitter", write_generated_lit, &random200);
    compare_written("cloud", write_cloud, NULL);
}

int main(void) {
    reference = integrator_report_sample;
    unsetenv("TRAZADOR_PACKET_BUILD"); /* the checks of the default choice below */
    build_count = integrator_packet_list(builds);
    for (int b = 0; b < build_count; b++)
        printf("packet integrator build %s, %u lanes\n", builds[b].name, builds[b].width);
    CHECK(build_count >= 2 && !strcmp(builds[build_count - 2].name, "baseline") &&
              !strcmp(builds[build_count - 1].name, RENDER_CPU_REFERENCE),
          "the baseline and reference builds are not listed last");
    CHECK(
        !strcmp(integrator_packet_choose(RENDER_CPU_REFERENCE, true).name, RENDER_CPU_REFERENCE) &&
            strcmp(integrator_packet_choose(NULL, false).name, RENDER_CPU_REFERENCE) &&
            strcmp(integrator_packet_choose(NULL, true).name, RENDER_CPU_REFERENCE),
        "the reference build is chosen by name only");
    CHECK(!strcmp(integrator_packet_choose(NULL, false).name, builds[0].name) &&
              integrator_packet_choose(NULL, true).width <= PACKET_WALK_LANES_MAX,
          "the fastest build for scenes with and without BVH walks");
    const char *files[] = {"cornell.scene", "shadows.scene",    "phong.scene",
                           "mirror.scene",  "refraction.scene", "all.scene"};
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) compare_file(files[k]);
    compare_written("facets", write_seed_mode, facets);
    compare_written("rough", write_seed_mode, rough);
    /* Triangle scenes through the BVH, lit by a point light (the name keeps the models' folder) */
    char box[4096], mesh[4096];
    if (read_scene("cornell_box.scene", box, sizeof box, "light position -278 500 279 power 4e5"))
        compare_written(TRAZADOR_SOURCE_DIR "/scenes/cornell_box lit", write_seed_mode, box);
    if (read_scene("mesh.scene", mesh, sizeof mesh, "light position 1 3 -2 power 40"))
        compare_written(TRAZADOR_SOURCE_DIR "/scenes/mesh lit", write_seed_mode, mesh);
    /* A flake of 11 spheres: every sphere per packet; 92 and 304 spheres: the BVH. */
    const gen_desc flake1 = {.kind = GEN_SPHEREFLAKE, .depth = 1};
    const gen_desc flake2 = {.kind = GEN_SPHEREFLAKE, .depth = 2};
    const gen_desc random300 = {.kind = GEN_RANDOM, .count = 300, .seed = 5};
    compare_written("sphereflake depth 1", write_generated, &flake1);
    compare_written("sphereflake depth 2", write_generated, &flake2);
    compare_written("random 300", write_generated, &random300);
    compare_text("tangle", tangle, sizeof tangle - 1);
    compare_written("cloud", write_cloud, NULL);
    compare_written("coincident", write_coincident, NULL);
    compare_path_builds();
    return check_summary("test_packet");
}
