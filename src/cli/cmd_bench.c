/* cmd_bench.c: `trazador bench`, fixed workloads timed on each back end (a benchmark, not a
 * test). */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "default_scene.h"
#include "path_scene.h"
#include "render/render.h"
#include "scene/gen.h"
#include "util/clock.h"
#include "util/log.h"

typedef struct workload {
    const char *name;
    int size; /* square image side in pixels */
    int samples;
    bool indirect;
    bool path; /* path mode on scenes/cornell_path.scene, else report mode on the default scene */
    bool lens; /* a thin lens (LENS_APERTURE, focused LENS_FOCUS away) instead of the pinhole */
} workload;

static const workload workloads[] = {
    {"cornell 512x512 indirect", 512, 16, true, false, false},
    {"cornell 512x512 direct", 512, 16, false, false, false},
    {"cornell 512x512 direct lens", 512, 16, false, false, true},
    {"cornell_path 256x256 path", 256, 16, false, true, false},
    {"cornell_path 256x256 path lens", 256, 16, false, true, true},
};
/* The lens workloads' camera: focused on the box's spheres, 10.5 away, a depth of field that
 * blurs the back wall. */
#define LENS_APERTURE 0.2f
#define LENS_FOCUS 10.5f

/* Scene sizes of the scaling table: the same camera and image, more and more spheres. */
static const long scaling_counts[] = {10, 1000, 100000, 1000000};
#define SCALING_SIZE 256
/* Each row is rendered first at SCALING_WARMUP_SAMPLES (lavapipe compiles its shader into Mesa's
 * disk cache, caches and pages warm up), then timed at the power of two of samples, at most
 * SCALING_MAX_SAMPLES, that makes its passes last SCALING_SECONDS or a little more: a small row at
 * the warm-up's samples is over too fast to time (docs/PERF.md, "Command line"). */
#define SCALING_WARMUP_SAMPLES 4
#define SCALING_MAX_SAMPLES 256
#define SCALING_SECONDS 0.5
/* A timed render shorter than this is timed again at the samples its speed asks for (the
 * warm-up's speed can be off: lavapipe compiles its shader in it). */
#define SCALING_MIN_SECONDS (0.7 * SCALING_SECONDS)
/* Timed renders of a row, the fastest kept: on a shared host single runs of the same row vary
 * widely (docs/PERF.md, "Command line"). */
#define SCALING_REPEATS 3

/* Prints a measured figure in a column of `width`, or "-" when that back end was not timed. */
static void print_figure(int width, double value, bool measured, const char *suffix) {
    if (measured)
        printf(" %*.2f%s", width - (int)strlen(suffix), value, suffix);
    else
        printf(" %*s", width, "-");
}

/* Renders the workload once, end to end (cpu_build: the CPU build by name, NULL the fastest);
 * returns Msamples/s (and *mrays Mrays/s), or a negative number on failure. */
static double run_workload(const scene *seed_scene, const scene *path_scene, const workload *w,
                           backend_choice backend, const char *cpu_build, int spp, double *mrays) {
    scene s = w->path ? *path_scene : *seed_scene;
    s.plane_height = s.plane_width;
    s.pixel_size = s.plane_width / (float)w->size;
    s.width = s.height = w->size;
    if (w->lens) s.camera_aperture = LENS_APERTURE, s.camera_focus = LENS_FOCUS;
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    opts.spp = spp > 0 ? spp : w->samples;
    opts.indirect = w->indirect;
    opts.cpu_build = cpu_build;
    render_stats stats = {0};
    opts.stats = &stats;
    film f = {0};
    const char *used;
    double start = clock_seconds();
    bool ok = render_choose(&s, &opts, backend, &f, &used);
    double elapsed = clock_seconds() - start;
    film_free(&f);
    *mrays = (double)stats.rays / elapsed * 1e-6;
    return ok ? (double)w->size * w->size * opts.spp / elapsed * 1e-6 : -1.0;
}

/* A random-spheres scene (trazador gen random) of `count` spheres in all, ground included; false
 * on failure. */
static bool scaling_scene(long count, scene *out) {
    gen_desc desc = {.kind = GEN_RANDOM, .count = 1, .seed = 1};
    desc.count = count - (gen_sphere_count(&desc) - 1); /* the fixed spheres come on top */
    char *text = NULL;
    size_t length = 0;
    FILE *fp = open_memstream(&text, &length);
    bool ok = fp && gen_write(&desc, fp);
    if (fp) fclose(fp);
    scene_error err;
    ok = ok && scene_parse_string(text, length, "gen random", out, &err);
    free(text);
    return ok;
}

/* The corners of an icosahedron about the origin, of unit radius, and its 20 faces wound
 * outward (counter-clockwise seen from outside). */
static const float ico_corner[12][3] = {
    {-0.525731f, 0.850651f, 0.0f},  {0.525731f, 0.850651f, 0.0f},   {-0.525731f, -0.850651f, 0.0f},
    {0.525731f, -0.850651f, 0.0f},  {0.0f, -0.525731f, 0.850651f},  {0.0f, 0.525731f, 0.850651f},
    {0.0f, -0.525731f, -0.850651f}, {0.0f, 0.525731f, -0.850651f},  {0.850651f, 0.0f, -0.525731f},
    {0.850651f, 0.0f, 0.525731f},   {-0.850651f, 0.0f, -0.525731f}, {-0.850651f, 0.0f, 0.525731f},
};
static const int ico_face[20][3] = {
    {0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1},
};
#define ICO_FACES 20

/* The random-spheres scene of the scaling table with its small spheres as icosahedra: `count`
 * triangles (rounded to whole icosahedra) of the spheres' materials, the ground and the three
 * big spheres kept; false on failure. */
static bool triangle_scene(long count, scene *out) {
    gen_desc desc = {
        .kind = GEN_RANDOM, .count = count / ICO_FACES > 0 ? count / ICO_FACES : 1, .seed = 1};
    if (!scaling_scene(gen_sphere_count(&desc), out)) return false;
    int kept = 4, balls = out->sphere_count - kept; /* the ground and three big spheres first */
    triangle *t = calloc((size_t)balls * ICO_FACES, sizeof *t);
    if (!t) {
        scene_free(out);
        return false;
    }
    for (int b = 0; b < balls; b++) {
        const sphere *sp = &out->spheres[kept + b];
        for (int f = 0; f < ICO_FACES; f++) {
            triangle *face = &t[b * ICO_FACES + f];
            for (int c = 0; c < 3; c++) {
                const float *v = ico_corner[ico_face[f][c]];
                face->v[c] = v3_add(sp->center, v3_scale(v3(v[0], v[1], v[2]), sp->radius));
            }
            face->material = sp->material; /* the ball's */
            face->normals = TRIANGLE_FLAT;
        }
    }
    out->triangles = t;
    out->triangle_count = balls * ICO_FACES;
    out->sphere_count = kept;
    return true;
}

/* Renders s with the back end at the scaling table's size and `samples` spp; Msamples/s of the
 * sample passes alone (BVH build and, for Vulkan, device and pipeline set-up excluded), or -1 on
 * failure. */
static double run_scaling(const scene *s, backend_choice backend, const char *cpu_build,
                          int samples, render_stats *stats) {
    render_opts opts;
    render_opts_from_scene(s, &opts);
    opts.cpu_build = cpu_build;
    opts.spp = samples;
    opts.indirect = true;
    opts.stats = stats;
    film f = {0};
    const char *used;
    bool ok = render_choose(s, &opts, backend, &f, &used);
    film_free(&f);
    return ok && stats->render_seconds > 0.0
               ? (double)s->width * s->height * opts.spp / stats->render_seconds * 1e-6
               : -1.0;
}

/* Msamples/s of s on the back end: a warm-up render, then renders at the power of two of samples
 * that the last one's speed says lasts SCALING_SECONDS, until one lasts SCALING_MIN_SECONDS, and
 * the fastest of SCALING_REPEATS renders at that count; *samples the spp timed, *stats the
 * fastest render's. -1 on failure. */
static double time_scaling(const scene *s, backend_choice backend, const char *cpu_build,
                           int *samples, render_stats *stats) {
    *samples = SCALING_WARMUP_SAMPLES;
    double speed = run_scaling(s, backend, cpu_build, *samples, stats);
    for (int run = 0; speed >= 0.0 && run < 3; run++) {
        double wanted = SCALING_SECONDS * speed * 1e6 / ((double)s->width * s->height);
        *samples = SCALING_WARMUP_SAMPLES;
        while (*samples < SCALING_MAX_SAMPLES && *samples < wanted) *samples *= 2;
        *stats = (render_stats){0};
        speed = run_scaling(s, backend, cpu_build, *samples, stats);
        if (stats->render_seconds >= SCALING_MIN_SECONDS || *samples == SCALING_MAX_SAMPLES) break;
    }
    for (int run = 1; speed >= 0.0 && run < SCALING_REPEATS; run++) {
        render_stats again = {0};
        double faster = run_scaling(s, backend, cpu_build, *samples, &again);
        if (faster < 0.0) return faster;
        if (faster > speed) speed = faster, *stats = again;
    }
    return speed;
}

/* Prints Msamples/s with the spp timed, "12.34 (256)", in a column of `width`, or "-" when that
 * back end was not timed. */
static void print_speed(int width, double value, int spp, bool measured) {
    char text[32] = "-";
    if (measured) snprintf(text, sizeof text, "%.2f (%d)", value, spp);
    printf(" %*s", width, text);
}

/* One engine of the scaling table: a back end, and for the CPU which build. */
typedef struct engine {
    backend_choice backend;
    const char *cpu_build; /* NULL: the fastest */
    bool wanted;
} engine;

/* Mrays/s of a timed render (its passes alone); 0 when not timed. */
static double mrays_of(const render_stats *st) {
    return st->render_seconds > 0.0 ? (double)st->rays / st->render_seconds * 1e-6 : 0.0;
}

/* The triangle table: the scaling table's field with its small spheres as icosahedra, against
 * the same field of as many spheres, in Mrays/s (the rays differ: a sample of a tessellated
 * field traces more or fewer). */
static int bench_triangles(const engine *engines, vec3 position, vec3 direction, vec3 up) {
    static const long counts[] = {1000, 100000, 1000000};
    printf(
        "\ntriangles: the field's small spheres as icosahedra of 20 faces, %dx%d, indirect "
        "on; Mrays/s of the passes alone, triangles against as many spheres\n",
        SCALING_SIZE, SCALING_SIZE);
    printf("%10s %9s %7s %13s %13s %13s %13s %13s %13s\n", "triangles", "build s", "B/tri",
           "cpu tri", "cpu sph", "ref tri", "ref sph", "vk tri", "vk sph");
    int failures = 0;
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        scene tri, sph;
        if (!triangle_scene(counts[k], &tri)) {
            printf("%10ld  could not generate the scene\n", counts[k]);
            failures++;
            continue;
        }
        if (!scaling_scene(tri.triangle_count + tri.sphere_count, &sph)) {
            scene_free(&tri);
            failures++;
            continue;
        }
        scene *both[2] = {&tri, &sph};
        for (int v = 0; v < 2; v++) {
            scene *s = both[v];
            s->camera_position = position, s->camera_direction = direction, s->camera_up = up;
            s->plane_height = s->plane_width;
            s->pixel_size = s->plane_width / (float)SCALING_SIZE;
            s->width = s->height = SCALING_SIZE;
        }
        double rays[3][2] = {{0}};
        render_stats first = {0};
        for (int e = 0; e < 3; e++) {
            if (!engines[e].wanted) continue;
            for (int v = 0; v < 2; v++) {
                render_stats st = {0};
                int spp = 0;
                double speed =
                    time_scaling(both[v], engines[e].backend, engines[e].cpu_build, &spp, &st);
                failures += speed < 0.0;
                rays[e][v] = speed > 0.0 ? mrays_of(&st) : 0.0;
                if (v == 0 && first.bvh_seconds == 0.0) first = st;
            }
        }
        printf("%10d %9.3f %7.1f", tri.triangle_count, first.bvh_seconds,
               (double)first.scene_bytes / (tri.triangle_count + tri.sphere_count));
        for (int e = 0; e < 3; e++)
            for (int v = 0; v < 2; v++)
                print_figure(13, rays[e][v], engines[e].wanted && rays[e][v] > 0.0, "");
        printf("\n");
        fflush(stdout);
        scene_free(&tri);
        scene_free(&sph);
    }
    return failures;
}

/* The scaling table: cost per sample against the sphere count, for the CPU back end, the
 * one-sample C reference integrator and the Vulkan back end. */
static int bench_scaling(bool want_cpu, bool want_vk) {
    printf(
        "\nscaling: random spheres, %dx%d, indirect on; Msamples/s of the passes alone (spp "
        "timed), the fastest of %d runs at a count sized to last %.2f s or more, after a %d-spp "
        "warm-up; ref: the one-sample C reference integrator (src/render/cpu/integrator_sample.c) "
        "on "
        "the CPU back end's threads\n",
        SCALING_SIZE, SCALING_SIZE, SCALING_REPEATS, SCALING_MIN_SECONDS, SCALING_WARMUP_SAMPLES);
    printf("%10s %9s %7s %6s %14s %14s %14s %10s %10s %10s %7s %7s\n", "spheres", "build s",
           "B/sph", "depth", "cpu Msamples/s", "ref Msamples/s", "vk Msamples/s", "cpu vs 10",
           "ref vs 10", "vk vs 10", "vk/cpu", "vk/ref");
    enum { CPU, REF, VK, ENGINES };
    const engine engines[ENGINES] = {{BACKEND_CPU, NULL, want_cpu},
                                     {BACKEND_CPU, RENDER_CPU_REFERENCE, want_cpu},
                                     {BACKEND_VULKAN, NULL, want_vk}};
    int failures = 0;
    double base[ENGINES] = {0};
    vec3 position = {0}, direction = {0}, up = {0};
    for (size_t k = 0; k < sizeof scaling_counts / sizeof scaling_counts[0]; k++) {
        scene s;
        if (!scaling_scene(scaling_counts[k], &s)) {
            printf("%10ld  could not generate the scene\n", scaling_counts[k]);
            failures++;
            continue;
        }
        if (k == 0) { /* every row keeps the first row's camera */
            position = s.camera_position, direction = s.camera_direction, up = s.camera_up;
        }
        s.camera_position = position, s.camera_direction = direction, s.camera_up = up;
        s.plane_height = s.plane_width;
        s.pixel_size = s.plane_width / (float)SCALING_SIZE;
        s.width = s.height = SCALING_SIZE;
        render_stats stats[ENGINES] = {0};
        int spp[ENGINES] = {0};
        double speed[ENGINES] = {0};
        bool ok[ENGINES];
        for (int e = 0; e < ENGINES; e++) {
            const engine *en = &engines[e];
            speed[e] =
                en->wanted ? time_scaling(&s, en->backend, en->cpu_build, &spp[e], &stats[e]) : 0.0;
            failures += speed[e] < 0.0;
            ok[e] = en->wanted && speed[e] > 0.0;
            if (k == 0) base[e] = speed[e];
        }
        const render_stats *st = want_cpu ? &stats[CPU] : &stats[VK];
        printf("%10d %9.3f %7.1f %6u", s.sphere_count, st->bvh_seconds,
               (double)st->scene_bytes / s.sphere_count, st->bvh_depth);
        for (int e = 0; e < ENGINES; e++) print_speed(14, speed[e], spp[e], ok[e]);
        /* Cost per sample relative to the 10-sphere scene: how much slower each sample is. */
        for (int e = 0; e < ENGINES; e++)
            print_figure(10, base[e] / speed[e], ok[e] && base[e] > 0.0, "x");
        print_figure(7, speed[VK] / speed[CPU], ok[VK] && ok[CPU], "");
        print_figure(7, speed[VK] / speed[REF], ok[VK] && ok[REF], "");
        printf("\n");
        fflush(stdout);
        scene_free(&s);
    }
    failures += bench_triangles(engines, position, direction, up);
    return failures;
}

typedef struct bench_args {
    int backend;   /* BENCH_BACKENDS order */
    long long spp; /* 0: each workload's own */
} bench_args;

#define BENCH_BACKENDS "auto|vulkan|cpu|both"
enum { BENCH_AUTO, BENCH_VULKAN, BENCH_CPU, BENCH_BOTH };

static const opt_spec bench_specs[] = {
    OPT_ONE_OF("--backend", offsetof(bench_args, backend), BENCH_BACKENDS,
               "the back ends timed (default auto: the CPU, and Vulkan where a device exists)"),
    OPT_WHOLE("--spp", NULL, offsetof(bench_args, spp), 1, 65536,
              "samples per pixel of the default-scene workloads, 1 to 65536 (default 16; the "
              "scaling table sizes its own)"),
};

static const opt_command bench_command = {
    .name = "bench",
    .synopsis = "usage: trazador bench [--backend auto|vulkan|cpu|both] [--spp N]\n",
    .about =
        "Times fixed workloads, then a scaling table from 10 to 1,000,000 spheres and one of "
        "1,000 to\n1,000,000 triangles against as many spheres, whose rows are each timed for "
        "about " CLI_AS_TEXT(SCALING_SECONDS) " s.\n",
    .specs = bench_specs,
    .spec_count = OPT_COUNT(bench_specs),
};

int cmd_bench(int argc, char **argv) {
    bench_args a = {0};
    const char *none[1];
    int count;
    opt_result rc = opt_parse(&bench_command, argc, argv, &a, none, &count);
    if (rc != OPT_OK) return rc == OPT_HELP ? 0 : rc;
    bool have_vk = render_backend_vulkan.device_count() > 0;
    bool want_cpu = a.backend != BENCH_VULKAN;
    /* --backend vulkan or both: no device is an error, not a skip */
    bool vk_named = a.backend == BENCH_VULKAN || a.backend == BENCH_BOTH;
    bool want_vk = vk_named || (a.backend == BENCH_AUTO && have_vk);
    long long spp = a.spp;
    if (vk_named && !have_vk) {
        log_error(RENDER_NO_VULKAN_DEVICE);
        return 1;
    }

    scene s, path;
    scene_error err;
    if (!scene_parse_string(default_scene_text, strlen(default_scene_text), "cornell.scene", &s,
                            &err)) {
        scene_error_print(&err);
        return 1;
    }
    if (!scene_parse_string(path_scene_text, strlen(path_scene_text), "cornell_path.scene", &path,
                            &err)) {
        scene_error_print(&err);
        scene_free(&s);
        return 1;
    }
    int failures = 0;
    if (want_cpu) {
        printf("cpu: ");
        render_backend_cpu.describe();
    } else {
        printf("cpu: not timed (--backend vulkan)\n");
    }
    if (!want_vk) {
        printf("vulkan: not timed (%s)\n", have_vk ? "--backend cpu" : "no device");
    } else { /* which driver was timed: figures of two lavapipe releases differ twofold */
        printf("vulkan: each workload timed after an untimed 1-spp render; the devices:\n");
        render_backend_vulkan.describe();
    }
    printf("%-34s %15s %12s %15s %15s %12s %7s %7s\n", "workload (end to end)", "cpu Msamples/s",
           "cpu Mrays/s", "ref Msamples/s", "vk Msamples/s", "vk Mrays/s", "vk/cpu", "vk/ref");
    for (size_t k = 0; k < sizeof workloads / sizeof workloads[0]; k++) {
        const workload *w = &workloads[k];
        double cpu_rays = 0.0, ref_rays = 0.0, vk_rays = 0.0;
        double cpu =
            want_cpu ? run_workload(&s, &path, w, BACKEND_CPU, NULL, (int)spp, &cpu_rays) : 0.0;
        double ref = want_cpu ? run_workload(&s, &path, w, BACKEND_CPU, RENDER_CPU_REFERENCE,
                                             (int)spp, &ref_rays)
                              : 0.0;
        /* An untimed 1-spp render first: lavapipe compiles the workload's shader to machine code
         * at its first dispatch (22.3 at the first of every submission) and keeps it in Mesa's
         * disk cache; timed cold, the compilation is most of a workload's time (docs/PERF.md,
         * "First dispatch"). */
        double vk = 0.0;
        if (want_vk && run_workload(&s, &path, w, BACKEND_VULKAN, NULL, 1, &vk_rays) >= 0.0)
            vk = run_workload(&s, &path, w, BACKEND_VULKAN, NULL, (int)spp, &vk_rays);
        else if (want_vk)
            vk = -1.0;
        failures += cpu < 0.0 || ref < 0.0 || vk < 0.0;
        char name[64];
        snprintf(name, sizeof name, "%s, %d spp", w->name, spp > 0 ? (int)spp : w->samples);
        printf("%-34s", name);
        print_figure(15, cpu, want_cpu && cpu > 0.0, "");
        print_figure(12, cpu_rays, want_cpu && cpu > 0.0, "");
        print_figure(15, ref, want_cpu && ref > 0.0, "");
        print_figure(15, vk, want_vk && vk > 0.0, "");
        print_figure(12, vk_rays, want_vk && vk > 0.0, "");
        print_figure(7, vk / cpu, want_cpu && want_vk && cpu > 0.0 && vk > 0.0, "");
        print_figure(7, vk / ref, want_cpu && want_vk && ref > 0.0 && vk > 0.0, "");
        printf("\n");
        fflush(stdout);
    }
    scene_free(&s);
    scene_free(&path);
    failures += bench_scaling(want_cpu, want_vk);
    return failures ? 1 : 0;
}
