/* main.c: the command line: subcommands, flags and exit codes (the only file that exits).
 * Exit codes: 0 success, 1 runtime failure, 2 usage or scene error. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "util/atomic_file.h"
#include "cli/cli.h"
#include "util/clock.h"
#include "default_scene.h"
#include "image/diff.h"
#include "scene/gen.h"
#include "image/image.h"
#include "util/interrupts.h"
#include "util/log.h"
#include "scene/scene.h"
#include "render/vk/vk_context.h"

static const char usage_text[] =
    "usage: trazador render [SCENE] [-o OUT] [--backend auto|vulkan|cpu] [--spp N] [--seed N]\n"
    "                       [--no-jitter] [--no-indirect] [--indirect] [--bounces N]\n"
    "                       [--threads N] [--device N] [--validate] [--quiet] [--verbose]\n"
    "                       [--tonemap srgb|linear] [--width N] [--no-bvh] [--format F]\n"
    "       trazador diff A B [--max-rmse X] [--min-psnr DB] [--max-diff-share FRACTION]\n"
    "       trazador devices\n"
    "       trazador bench [--backend auto|vulkan|cpu|both] [--spp N]\n"
    "       trazador gen sphereflake --depth N [-o FILE] [--seed N]\n"
    "       trazador gen random --count N [-o FILE] [--seed N]\n"
    "       trazador --help | --version\n"
    "SCENE defaults to the embedded scenes/cornell.scene ('-' reads standard input),\n"
    "OUT to render.png;\n"
    "the output format follows the extension: .png, .ppm or .pfm (linear float), or\n"
    "--format png|ppm|pfm for any name (-o - --format ppm writes to standard output).\n";

static int usage_error(const char *fmt, const char *arg) {
    fprintf(stderr, "trazador: ");
    fprintf(stderr, fmt, arg);
    fprintf(stderr, "\n%s", usage_text);
    return 2;
}

typedef struct render_args {
    const char *scene_path, *output, *format; /* format: NULL for the output's extension */
    backend_choice backend;
    tonemap tm;
    bool quiet;
    long long spp, seed, bounces, threads, device, width; /* -1: not given */
    int indirect;                                         /* -1 not given, 0 off, 1 on */
    bool no_jitter, validate, verbose, no_bvh;
} render_args;

/* The names --format takes, each with the default output of that format. */
static const char *const output_formats[3][2] = {
    {"png", "render.png"}, {"ppm", "render.ppm"}, {"pfm", "render.pfm"}};

/* Parses `render` arguments; returns 0 to go on, 2 on a usage error, -1 for --help (exit 0). */
static int parse_render_args(int argc, char **argv, render_args *a) {
    *a = (render_args){.output = "render.png",
                       .spp = -1,
                       .seed = -1,
                       .bounces = -1,
                       .threads = -1,
                       .device = -1,
                       .width = -1,
                       .indirect = -1};
    bool output_given = false;
    for (int k = 1; k < argc; k++) {
        const char *arg = argv[k];
        const char *value = k + 1 < argc ? argv[k + 1] : NULL;
        bool takes_value = true;
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            fputs(usage_text, stdout);
            return -1;
        } else if (!strcmp(arg, "-o") || !strcmp(arg, "--output")) {
            if (!value) return usage_error("%s needs a file name", arg);
            a->output = value;
            output_given = true;
        } else if (!strcmp(arg, "--format")) {
            int f = 0;
            while (f < 3 && (!value || strcasecmp(value, output_formats[f][0]))) f++;
            if (f == 3)
                return usage_error("--format takes png, ppm or pfm, got '%s'", value ? value : "");
            a->format = output_formats[f][0];
            if (!output_given) a->output = output_formats[f][1];
        } else if (!strcmp(arg, "--backend")) {
            if (value && !strcmp(value, "vulkan"))
                a->backend = BACKEND_VULKAN;
            else if (value && !strcmp(value, "cpu"))
                a->backend = BACKEND_CPU;
            else if (value && !strcmp(value, "auto"))
                a->backend = BACKEND_AUTO;
            else
                return usage_error("--backend takes auto, vulkan or cpu, got '%s'",
                                   value ? value : "");
        } else if (!strcmp(arg, "--tonemap")) {
            if (value && !strcmp(value, "srgb"))
                a->tm = TONEMAP_SRGB;
            else if (value && !strcmp(value, "linear"))
                a->tm = TONEMAP_LINEAR;
            else
                return usage_error("--tonemap takes srgb or linear, got '%s'", value ? value : "");
        } else if (!strcmp(arg, "--spp")) {
            if (!cli_parse_int(value, 1, SCENE_MAX_SAMPLES, &a->spp))
                return usage_error("--spp takes a whole number from 1 to " CLI_AS_TEXT(
                                       SCENE_MAX_SAMPLES) ", got '%s'",
                                   value ? value : "");
        } else if (!strcmp(arg, "--seed")) {
            if (!cli_parse_int(value, 0, 4294967295LL, &a->seed))
                return usage_error("--seed takes a whole number from 0 to 4294967295, got '%s'",
                                   value ? value : "");
        } else if (!strcmp(arg, "--bounces")) {
            if (!cli_parse_int(value, 0, SCENE_MAX_BOUNCES, &a->bounces))
                return usage_error("--bounces takes a whole number from 0 to " CLI_AS_TEXT(
                                       SCENE_MAX_BOUNCES) ", got '%s'",
                                   value ? value : "");
        } else if (!strcmp(arg, "--threads")) {
            if (!cli_parse_int(value, 1, RENDER_MAX_THREADS, &a->threads))
                return usage_error("--threads takes a whole number from 1 to " CLI_AS_TEXT(
                                       RENDER_MAX_THREADS) ", got '%s'",
                                   value ? value : "");
        } else if (!strcmp(arg, "--width")) {
            if (!cli_parse_int(value, 1, SCENE_MAX_RESOLUTION, &a->width))
                return usage_error("--width takes a whole number of pixels from 1 to " CLI_AS_TEXT(
                                       SCENE_MAX_RESOLUTION) ", got '%s'",
                                   value ? value : "");
        } else if (!strcmp(arg, "--device")) {
            if (!cli_parse_int(value, 0, 255, &a->device))
                return usage_error(
                    "--device takes a device index (see `trazador devices`), got '%s'",
                    value ? value : "");
        } else {
            takes_value = false;
            if (!strcmp(arg, "--no-jitter"))
                a->no_jitter = true;
            else if (!strcmp(arg, "--no-indirect"))
                a->indirect = 0;
            else if (!strcmp(arg, "--indirect"))
                a->indirect = 1;
            else if (!strcmp(arg, "--validate"))
                a->validate = true;
            else if (!strcmp(arg, "--no-bvh"))
                a->no_bvh = true;
            else if (!strcmp(arg, "--quiet") || !strcmp(arg, "-q"))
                a->quiet = true;
            else if (!strcmp(arg, "--verbose") || !strcmp(arg, "-v"))
                a->verbose = true;
            else if (arg[0] == '-' && arg[1])
                return usage_error("unknown option '%s'", arg);
            else if (!a->scene_path)
                a->scene_path = arg;
            else
                return usage_error("more than one scene given ('%s')", arg);
        }
        if (takes_value) k++;
    }
    if (a->scene_path && !strcmp(a->scene_path, "-")) /* the usual name of standard input */
        a->scene_path = "/dev/stdin";
    if (!strcmp(a->output, "-")) { /* the usual name of standard output */
        if (!a->format)
            return usage_error("%s", "-o - (standard output) needs --format png|ppm|pfm");
        a->output = "/dev/stdout";
    }
    const char *named = image_path_format(a->output);
    if (a->format && named && strcmp(named, a->format))
        return usage_error("output '%s' names another format than --format", a->output);
    if (!a->format && !named)
        return usage_error("output '%s' must end in .png, .ppm or .pfm, or take --format",
                           a->output);
    if (a->device >= 0 && a->backend == BACKEND_CPU)
        return usage_error("%s", "--device names a Vulkan device: it cannot go with --backend cpu");
    if (a->validate && a->backend == BACKEND_CPU)
        return usage_error(
            "%s", "--validate turns on Vulkan's validation: it cannot go with --backend cpu");
    return 0;
}

/* --width N: N pixels across the same plane; the height must come out whole too. */
static bool apply_width(long long width, scene *s) {
    if (width < 0) return true;
    double pixel = (double)s->plane_width / (double)width;
    double height = (double)s->plane_height / pixel;
    long long rows = llround(height);
    if (rows < 1 || rows > SCENE_MAX_RESOLUTION) {
        fprintf(stderr,
                "trazador: --width %lld gives a height of %.7g pixels for a %g x %g plane; the "
                "height must be 1 to %d pixels\n",
                width, height, s->plane_width, s->plane_height, SCENE_MAX_RESOLUTION);
        return false;
    }
    if (fabs(height - (double)rows) > 1e-6 * height) {
        fprintf(stderr,
                "trazador: --width %lld gives a height of %.7g pixels for a %g x %g plane; "
                "pick a width that makes it whole\n",
                width, height, s->plane_width, s->plane_height);
        return false;
    }
    s->pixel_size = (float)pixel;
    s->width = (int)width;
    s->height = (int)rows;
    return true;
}

/* Warns about what the film cannot show as rendered: samples dropped as non-finite (and the
 * pixels they left with no sample, black), and finite samples that summed past the float range
 * (radiance near 3.4e38), written as infinity (PFM) or white. One pass over the film. */
static void warn_film_problems(const film *f) {
    size_t pixels = (size_t)f->width * (size_t)f->height, empty = 0, overflowed = 0;
    for (size_t k = 0; k < pixels; k++) {
        const float *px = &f->accum[4 * k];
        empty += !(px[3] > 0.0f);
        overflowed += !isfinite(px[0]) || !isfinite(px[1]) || !isfinite(px[2]);
    }
    if (f->nonfinite) {
        char black[96] = "";
        if (empty)
            snprintf(black, sizeof black, "; %zu pixel%s kept no sample and %s black", empty,
                     empty == 1 ? "" : "s", empty == 1 ? "is" : "are");
        log_warn("%llu samples had non-finite radiance and were not accumulated%s",
                 (unsigned long long)f->nonfinite, black);
    }
    if (overflowed)
        log_warn(
            "%zu pixels summed their samples past the float range (radiance near 3.4e38): "
            "they are infinite in PFM and white in 8-bit images",
            overflowed);
}

/* An interrupted render clears its progress line, so the shell's prompt starts a clean line. */
static void clear_progress(int sig) {
    static const char clear[] = "\r\033[K";
    ssize_t written = write(STDERR_FILENO, clear, sizeof clear - 1); /* async-signal-safe */
    (void)written;
    interrupts_die(sig);
}

static void apply_overrides(const render_args *a, render_opts *o) {
    if (a->spp >= 0) o->samples = (int)a->spp;
    if (a->seed >= 0) o->seed = (uint32_t)a->seed;
    if (a->bounces >= 0) o->bounces = (int)a->bounces;
    if (a->threads >= 0) o->threads = (int)a->threads;
    if (a->device >= 0) o->device = (int)a->device;
    if (a->indirect >= 0) o->indirect = a->indirect;
    o->no_jitter = a->no_jitter;
    o->validate = a->validate;
    o->no_bvh = a->no_bvh;
    o->progress = !a->quiet && isatty(STDERR_FILENO);
}

static int render_command(int argc, char **argv) {
    render_args a;
    int rc = parse_render_args(argc, argv, &a);
    if (rc) return rc < 0 ? 0 : rc;
    if (a.verbose) log_set_level(LOG_DEBUG);
    if (a.quiet) log_set_level(LOG_WARN);
    scene s;
    scene_error err;
    double parse_start = clock_seconds();
    bool parsed = a.scene_path ? scene_parse_file(a.scene_path, &s, &err)
                               : scene_parse_string(default_scene_text, strlen(default_scene_text),
                                                    "scenes/cornell.scene (embedded)", &s, &err);
    if (!parsed) {
        scene_error_print(&err);
        return err.out_of_memory ? 1 : 2;
    }
    log_debug("scene: read and parsed in %.1f ms", (clock_seconds() - parse_start) * 1e3);
    for (int k = 0; k < s.warning_count; k++) {
        const scene_error *w = &s.warnings[k];
        log_warn("%s:%d:%d: %s", w->file, w->line, w->col, w->message);
    }
    if (!apply_width(a.width, &s)) {
        scene_free(&s);
        return 2;
    }
    /* An output that cannot be written is said before the render, not after it. */
    if (!atomic_file_check(a.output)) {
        scene_free(&s);
        return 1;
    }
    /* Naming a device asks for Vulkan: none at all is the usual runtime failure, a number past
     * the devices a mistake on the command line; neither falls back to the CPU. */
    int devices = a.device >= 0 ? vk_context_device_count() : -1;
    if (devices == 0) {
        log_error(VK_CONTEXT_NO_DEVICE_MESSAGE);
        scene_free(&s);
        return 1;
    }
    if (devices > 0 && a.device >= devices) {
        fprintf(stderr,
                "trazador: --device %lld: there %s %d Vulkan device%s (see `trazador devices`)\n",
                a.device, devices == 1 ? "is" : "are", devices, devices == 1 ? "" : "s");
        scene_free(&s);
        return 2;
    }
    render_opts opts;
    render_opts_from_scene(&s, &opts);
    apply_overrides(&a, &opts);
    render_stats stats = {0};
    opts.stats = &stats;
    film f = {0};
    image img = {0};
    const char *used = "";
    double start = clock_seconds();
    interrupts_saved saved;
    if (opts.progress) interrupts_catch(clear_progress, &saved);
    bool ok = cli_render(&s, &opts, a.backend, &f, &used);
    if (opts.progress) interrupts_restore(&saved);
    double elapsed = clock_seconds() - start;
    if (ok) warn_film_problems(&f);
    double write_start = clock_seconds();
    ok = ok && image_from_film(&f, &img) && image_write_as(a.output, a.format, &img, a.tm);
    if (ok) log_debug("image: written in %.1f ms", (clock_seconds() - write_start) * 1e3);
    if (ok && !a.quiet) {
        double samples = (double)s.width * s.height * opts.samples;
        log_info("%s: %dx%d, %d spp, %s back end, %.3f s, %.2f Msamples/s, %.1f Mrays/s", a.output,
                 s.width, s.height, opts.samples, used, elapsed, samples / elapsed * 1e-6,
                 (double)stats.rays / elapsed * 1e-6);
    }
    image_free(&img);
    film_free(&f);
    scene_free(&s);
    return ok ? 0 : 1;
}

/* Runs the subcommand argv[1]; its exit code. */
static int run_command(int argc, char **argv) {
    if (argc < 2) {
        fputs(usage_text, stderr);
        return 2;
    }
    const char *cmd = argv[1];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        fputs(usage_text, stdout);
        return 0;
    }
    if (!strcmp(cmd, "--version")) {
        printf("trazador %s\n", TRAZADOR_VERSION);
        return 0;
    }
    if (!strcmp(cmd, "render")) return render_command(argc - 1, argv + 1);
    if (!strcmp(cmd, "diff")) return diff_command(argc - 1, argv + 1);
    if (!strcmp(cmd, "bench")) return bench_command(argc - 1, argv + 1);
    if (!strcmp(cmd, "gen")) return gen_command(argc - 1, argv + 1);
    if (!strcmp(cmd, "devices")) {
        if (argc == 3 && (!strcmp(argv[2], "--help") || !strcmp(argv[2], "-h"))) {
            printf("usage: trazador devices\nLists the Vulkan devices; * marks the default.\n");
            return 0;
        }
        if (argc > 2) return usage_error("devices takes no arguments, got '%s'", argv[2]);
        return vk_context_print_devices() ? 0 : 1;
    }
    return usage_error("unknown command '%s'", cmd);
}

int main(int argc, char **argv) {
    int rc = run_command(argc, argv);
    /* What went to standard output is data (diff's metrics, a scene, a list): a failed write
     * there (a full disk, /dev/full) fails the run. */
    if ((fflush(stdout) != 0 || ferror(stdout)) && rc == 0) {
        fprintf(stderr, "trazador: cannot write to standard output: %s\n", strerror(errno));
        rc = 1;
    }
    return rc;
}
