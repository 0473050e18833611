/* cmd_render.c: `trazador render`: its options, the checks made before rendering (the output can
 * be written and is not the scene), the render (a whole image or a part: a region, a range of
 * samples, resumed from a checkpoint: render_part_args.c) and its summary line. */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "cli/render_pacer.h"
#include "cli/render_part_args.h"
#include "default_scene.h"
#include "image/image.h"
#include "render/part.h"
#include "scene/model_formats.h"
#include "scene/model_scene.h"
#include "scene/scene.h"
#include "util/atomic_file.h"
#include "util/clock.h"
#include "util/interrupts.h"
#include "util/log.h"

typedef struct render_args {
    const char *output; /* NULL: render.png, or render.<format> */
    int format;         /* index in FORMATS, -1: the output's extension */
    int backend;        /* backend_choice */
    int tm;             /* tonemap */
    long long spp, seed, bounces, threads, device, width; /* -1: not given */
    long long light_samples;                              /* -1: not given */
    int indirect;                                         /* -1 not given, 0 off, 1 on */
    int mode;                                             /* -1 not given, else render_mode */
    int no_jitter, validate, verbose, quiet, no_bvh, force;
    int walk;                        /* render_walk */
    int sampler;                     /* render_sampler */
    const char *region, *samples;    /* "x0,x1,y0,y1", "A:B"; NULL: all */
    const char *checkpoint, *resume; /* part files; NULL: none */
    const char *camera;              /* a model file's camera, index or name; NULL: its first */
    const char *environment;         /* a model file's environment map; NULL: the default */
    double checkpoint_every;         /* seconds; -1: not given (CHECKPOINT_EVERY) */
    double time_limit;               /* seconds; -1: none */
    int exr_type;                    /* 0 half, 1 float */
    int part;                        /* an EXR output is a part file */
    int keep_checkpoint;             /* keep the checkpoint of a finished render */
    double noise_threshold;          /* -1: not given */
    const char *aov;                 /* --aov's list; NULL: none */
    uint32_t aov_mask;               /* its kinds (image/aov.h) */
    int aov_files;                   /* the feature images as files of their own */
} render_args;

#define FORMATS "png|ppm|pfm|exr"
/* Seconds between checkpoints unless --checkpoint-every says. */
#define CHECKPOINT_EVERY 60.0
static const char *const format_names[] = {"png", "ppm", "pfm", "exr"};
static const char *const default_outputs[] = {"render.png", "render.ppm", "render.pfm",
                                              "render.exr"};

#define ARG(field) offsetof(render_args, field)
static const opt_spec render_specs[] = {
    OPT_TEXT("--output", "-o", ARG(output), "FILE", "a file name",
             "the image to write, its format from the extension (default render.png); - is "
             "standard output"),
    OPT_ONE_OF("--format", ARG(format), FORMATS,
               "the output's format, for any name (default: from the extension)"),
    OPT_ONE_OF("--backend", ARG(backend), "auto|vulkan|cpu",
               "the back end (default auto: Vulkan where it can render the scene, else the CPU)"),
    OPT_WHOLE("--spp", NULL, ARG(spp), 1, SCENE_MAX_SAMPLES,
              "samples per pixel, 1 to " CLI_AS_TEXT(
                  SCENE_MAX_SAMPLES) " (default: the scene's, else 64)"),
    OPT_WHOLE("--seed", NULL, ARG(seed), 0, 4294967295.0,
              "the random seed, 0 to 4294967295 (default: the scene's, else 1)"),
    OPT_ONE_OF("--mode", ARG(mode), "report|path|seed",
               "the integrator: report, the course report's model, or path, physically based "
               "path tracing (default: the scene's, else report; seed is report's old name)"),
    OPT_ONE_OF("--sampler", ARG(sampler), "auto|random|sobol",
               "where a sample's numbers come from: random (a hashed stream) or sobol "
               "(Owen-scrambled Sobol points, lower error at equal samples) (default: the "
               "scene's, else sobol in path mode and random in report mode)"),
    OPT_WHOLE("--bounces", NULL, ARG(bounces), 0, SCENE_MAX_BOUNCES,
              "report mode: the longest chain of specular events; path mode: the most scattering "
              "events of a path; 0 to " CLI_AS_TEXT(
                  SCENE_MAX_BOUNCES) " (default: the scene's, else 5 in report mode, 16 in path)"),
    OPT_WHOLE("--light-samples", NULL, ARG(light_samples), 1, SCENE_MAX_LIGHT_SAMPLES,
              "path mode: emitter samples at each diffuse vertex, 1 to " CLI_AS_TEXT(
                  SCENE_MAX_LIGHT_SAMPLES) ", each with its shadow ray (default: the scene's, else "
                                           "1)"),
    OPT_SET("--indirect", NULL, ARG(indirect), 1,
            "one diffuse bounce of indirect light (default: the scene's, else on)"),
    OPT_SET("--no-indirect", NULL, ARG(indirect), 0,
            "direct light only (default: the scene's, else indirect on)"),
    OPT_SET("--no-jitter", NULL, ARG(no_jitter), 1,
            "every sample through the pixel's centre (default: jittered)"),
    OPT_WHOLE("--width", NULL, ARG(width), 1, SCENE_MAX_RESOLUTION,
              "N pixels across the scene's plane, 1 to " CLI_AS_TEXT(
                  SCENE_MAX_RESOLUTION) " (default: the scene's pixel size)"),
    OPT_TEXT("--camera", NULL, ARG(camera), "N|NAME", "a camera's index or name",
             "a model file given as the scene: its camera N (from 0) or NAME (default: its "
             "first, or without one a camera that frames the model; `trazador info` lists them)"),
    OPT_TEXT("--environment", NULL, ARG(environment), "PATH", "an environment map",
             "a model file given as the scene: lit by the HDR map at PATH (EXR or Radiance HDR) "
             "beside its own lights (default: its lights, or a white background without any)"),
    OPT_WHOLE(
        "--threads", NULL, ARG(threads), 1, RENDER_MAX_THREADS,
        "CPU back end threads, 1 to " CLI_AS_TEXT(RENDER_MAX_THREADS) " (default: one per core)"),
    {.name = "--device",
     .type = OPT_INT,
     .offset = ARG(device),
     .min = 0,
     .max = 255,
     .choices = "N",
     .takes = "a device index (see `trazador devices`)",
     .help = "the Vulkan device, 0 to 255, no fallback (default: the one * marks in `trazador "
             "devices`)"},
    OPT_SET("--validate", NULL, ARG(validate), 1,
            "Vulkan's validation layer on; any error fails the run (default off)"),
    OPT_ONE_OF("--walk", ARG(walk), "auto|compute|cooperative|rayquery",
               "how Vulkan rays find their hits: compute (each invocation walks trazador's BVH), "
               "cooperative (the subgroup walks it together), rayquery (the device's "
               "acceleration structure, VK_KHR_ray_query); one the device lacks is an error "
               "(default auto: rayquery on GPUs that have it, else compute; TRAZADOR_VK_WALK "
               "names one too)"),
    OPT_SET("--no-bvh", NULL, ARG(no_bvh), 1,
            "test every sphere for every ray (default: walk the BVH)"),
    OPT_TEXT("--region", NULL, ARG(region), "X0,X1,Y0,Y1", "four whole numbers",
             "render pixels X0 <= x < X1, Y0 <= y < Y1 of the image only, as an EXR part "
             "(default: every pixel)"),
    OPT_TEXT("--samples", NULL, ARG(samples), "A:B", "a sample range",
             "render sample indices A to B - 1 of every pixel only, as an EXR part; A and B "
             "multiples of 16, or B the samples per pixel (default: all)"),
    OPT_TEXT("--checkpoint", NULL, ARG(checkpoint), "FILE", "a file name",
             "write the part so far to FILE (an EXR part, atomically) every --checkpoint-every "
             "seconds and on SIGUSR1, SIGINT or SIGTERM (the last two then stop the render); "
             "checked as the output is, before the render, and named .exr (default: none)"),
    OPT_SET("--keep-checkpoint", NULL, ARG(keep_checkpoint), 1,
            "keep the checkpoint once the render is complete and its output written (default: "
            "it is removed then; a render stopped or cut short by --time-limit keeps it)"),
    OPT_DECIMAL("--checkpoint-every", ARG(checkpoint_every), 0.001, 1e9, "SECONDS",
                "seconds between checkpoints (default 60)"),
    OPT_TEXT("--resume", NULL, ARG(resume), "FILE", "a file name",
             "go on from the checkpoint FILE of this very render (default: from the start)"),
    OPT_DECIMAL("--time-limit", ARG(time_limit), 0.001, 1e9, "SECONDS",
                "render whole chunks of 16 samples until SECONDS have passed, then write the "
                "image of the samples so far (default: no limit)"),
    OPT_DECIMAL("--noise-threshold", ARG(noise_threshold), 0.0, 1e6, "T",
                "adaptive sampling: from sample 64 on, a pixel whose estimated error (its mean "
                "against the mean of its odd chunks of 16 samples) is at most T takes no further "
                "sample; --spp is the cap; 0 is off (default: the scene's, else off)"),
    OPT_TEXT("--aov", NULL, ARG(aov), "LIST", "feature images, comma-separated",
             "feature images for a denoiser, any of albedo,normal,depth,position,emission: of "
             "each pixel's first 4 samples' first hit, albedo and normal through mirrors and "
             "glass; layers of an EXR output or part (default: none)"),
    OPT_SET("--aov-files", NULL, ARG(aov_files), 1,
            "write the --aov images as files beside the image too, NAME.albedo.pfm (.exr for an "
            "EXR output) and so on (default: layers only)"),
    OPT_ONE_OF("--exr-type", ARG(exr_type), "half|float",
               "an EXR image's channels (default half; parts are always float)"),
    OPT_SET("--part", NULL, ARG(part), 1,
            "write an EXR output as a part file, for `trazador merge` or --resume (default: "
            "with --region or --samples)"),
    OPT_ONE_OF("--tonemap", ARG(tm), "srgb|linear",
               "8-bit encoding: sRGB or a plain clamp (default srgb; .pfm is linear)"),
    OPT_SET("--force", NULL, ARG(force), 1,
            "replace a write-protected output (default: refuse it, as the shell's > does)"),
    OPT_SET("--quiet", "-q", ARG(quiet), 1,
            "warnings and errors only (default: progress on a terminal, a summary line)"),
    OPT_SET("--verbose", "-v", ARG(verbose), 1, "the timings of each stage (default off)"),
};
#undef ARG

static const opt_command render_command = {
    .name = "render",
    .synopsis =
        "usage: trazador render [SCENE] [options]\n"
        "Renders SCENE (default: the embedded scenes/cornell.scene; - reads standard "
        "input) into an image.\n",
    .about =
        "Values are given as --flag value or --flag=value; -- ends the options. Choices\n"
        "(auto, png, srgb, ...) are matched without regard to case.\n",
    .specs = render_specs,
    .spec_count = OPT_COUNT(render_specs),
    .max_positional = 1,
};

/* Parses `render` arguments; OPT_OK to go on, OPT_HELP, or OPT_USAGE (printed). */
static opt_result parse_render_args(int argc, char **argv, render_args *a,
                                    const char **scene_path) {
    *a = (render_args){.format = -1,
                       .tm = -1,
                       .exr_type = -1,
                       .spp = -1,
                       .seed = -1,
                       .bounces = -1,
                       .light_samples = -1,
                       .threads = -1,
                       .device = -1,
                       .width = -1,
                       .indirect = -1,
                       .mode = -1,
                       .checkpoint_every = -1.0,
                       .noise_threshold = -1.0,
                       .time_limit = -1.0};
    int count;
    *scene_path = NULL;
    opt_result rc = opt_parse(&render_command, argc, argv, a, scene_path, &count);
    if (rc != OPT_OK) return rc;
    const char *format = a->format >= 0 ? format_names[a->format] : NULL;
    if (!a->output) a->output = a->format >= 0 ? default_outputs[a->format] : "render.png";
    if (!strcmp(a->output, "-")) { /* the usual name of standard output */
        if (!format)
            return opt_usage_error(&render_command,
                                   "-o - (standard output) needs --format " FORMATS);
        a->output = "/dev/stdout";
    }
    const char *named = image_path_format(a->output);
    if (format && named && strcmp(named, format))
        return opt_usage_error(&render_command, "output '%s' names another format than --format",
                               a->output);
    if (!format && !named)
        return opt_usage_error(&render_command,
                               "output '%s' must end in .png, .ppm, .pfm or .exr, or take --format",
                               a->output);
    bool exr = !strcmp(format ? format : named, "exr");
    cli_warn_unused(format ? format : named, a->region || a->samples || a->part, &a->tm,
                    &a->exr_type);
    if ((a->region || a->samples || a->part) && !exr)
        return opt_usage_error(&render_command,
                               "--region, --samples and --part write an EXR part: give -o "
                               "NAME.exr (and `trazador merge` the parts)");
    size_t bad = 0;
    if (a->aov && !aov_parse_list(a->aov, &a->aov_mask, &bad))
        return opt_usage_error(&render_command,
                               "--aov takes a list of albedo, normal, depth, position, emission, "
                               "got '%s' (at character %zu)",
                               a->aov, bad + 1);
    if (a->aov_files && !a->aov)
        return opt_usage_error(&render_command, "--aov-files writes the --aov images: give --aov");
    if (a->aov && !exr && !a->aov_files)
        return opt_usage_error(&render_command,
                               "--aov writes layers of an EXR output: give -o NAME.exr, or "
                               "--aov-files for files of their own");
    if (a->aov_files && (a->region || a->samples || a->part))
        return opt_usage_error(&render_command,
                               "--aov-files writes beside an image: a part keeps its feature "
                               "images as layers, which `trazador merge --aov-files` writes");
    /* A checkpoint is an EXR part whatever its name says: a name of another format would hide
     * it (and a later render could read it as that format). */
    const char *ck_format = a->checkpoint ? image_path_format(a->checkpoint) : NULL;
    if (a->checkpoint && (!ck_format || strcmp(ck_format, "exr")))
        return opt_usage_error(&render_command,
                               "--checkpoint '%s' must end in .exr: a checkpoint is an EXR part",
                               a->checkpoint);
    if (a->device >= 0 && a->backend == BACKEND_CPU)
        return opt_usage_error(&render_command,
                               "--device names a Vulkan device: it cannot go with --backend cpu");
    if (a->validate && a->backend == BACKEND_CPU)
        return opt_usage_error(
            &render_command,
            "--validate turns on Vulkan's validation: it cannot go with --backend cpu");
    if (a->walk != RENDER_WALK_AUTO && a->backend == BACKEND_CPU)
        return opt_usage_error(&render_command,
                               "--walk chooses how Vulkan walks rays: it cannot go with "
                               "--backend cpu");
    return OPT_OK;
}

bool cli_apply_width(long long width, scene *s) {
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

/* True (logged) when the file `what` names (the output, the checkpoint) is one the render reads,
 * the same file on the same device (through another name or a link): the scene file itself or a
 * file of its meshes (s->inputs). Writing it would replace it. */
static bool is_input(const char *what, const char *path, const char *scene_path, const scene *s) {
    struct stat out, in;
    if (stat(path, &out) != 0 || !S_ISREG(out.st_mode)) return false;
    for (int k = 0; k < s->input_count; k++) {
        const scene_input *mesh_file = &s->inputs[k];
        if (!scene_input_is(mesh_file, (uint64_t)out.st_dev, (uint64_t)out.st_ino)) continue;
        fprintf(stderr,
                "trazador: render: %s '%s' is a file the scene's meshes read (%s): give another\n",
                what, path, mesh_file->path);
        return true;
    }
    if (!scene_path) return false;
    bool is_stdin = !strcmp(scene_path, "-");
    if ((is_stdin ? fstat(STDIN_FILENO, &in) : stat(scene_path, &in)) != 0) return false;
    if (in.st_dev != out.st_dev || in.st_ino != out.st_ino) return false;
    fprintf(stderr, "trazador: render: %s '%s' is the scene being rendered (%s): give another\n",
            what, path, is_stdin ? "<stdin>" : scene_path);
    return true;
}

/* The checks the output gets, for the checkpoint, before rendering (a checkpoint that cannot be
 * written would otherwise fail the run only at the first checkpoint, its work lost): 0 to go
 * on, else the exit code (said). The checkpoint may be the file resumed, not the output. */
static int check_checkpoint(const render_args *a, const char *scene_path, const scene *s) {
    if (!a->checkpoint) return 0;
    if (is_input("--checkpoint", a->checkpoint, scene_path, s)) return 2;
    if (atomic_file_same(a->checkpoint, a->output)) {
        fprintf(stderr,
                "trazador: render: --checkpoint '%s' is the output '%s': give another (the "
                "output would replace the checkpoint)\n",
                a->checkpoint, a->output);
        return 2;
    }
    return atomic_file_check_force(a->checkpoint, a->force) ? 0 : 1;
}

/* An interrupted render clears its progress line, so the shell's prompt starts a clean line. */
static void clear_progress(int sig) {
    static const char clear[] = "\r\033[K";
    ssize_t written = write(STDERR_FILENO, clear, sizeof clear - 1); /* async-signal-safe */
    (void)written;
    interrupts_die(sig);
}

/* The flags over the scene's settings; a mode named without bounces takes that mode's default. */
static void apply_overrides(const render_args *a, const scene *s, render_opts *o) {
    if (a->spp >= 0) o->spp = (int)a->spp;
    if (a->seed >= 0) o->seed = (uint32_t)a->seed;
    if (a->mode >= 0) o->mode = (render_mode)a->mode;
    if (a->mode >= 0 && !s->bounces_given) o->bounces = scene_default_bounces(o->mode);
    if (a->bounces >= 0) o->bounces = (int)a->bounces;
    if (a->sampler != RENDER_SAMPLER_AUTO) o->sampler = (render_sampler)a->sampler;
    if (a->light_samples >= 0) o->light_samples = (int)a->light_samples;
    if (a->threads >= 0) o->threads = (int)a->threads;
    if (a->device >= 0) o->device = (int)a->device, o->device_given = true;
    if (a->indirect >= 0) o->indirect = a->indirect;
    o->no_jitter = a->no_jitter;
    o->validate = a->validate;
    o->walk = (render_walk)a->walk;
    o->no_bvh = a->no_bvh;
    o->progress = !a->quiet && isatty(STDERR_FILENO);
    o->aov = a->aov_mask;
    if (a->noise_threshold >= 0.0) o->noise_threshold = (float)a->noise_threshold;
}

/* Naming a device asks for Vulkan: none at all is the usual runtime failure (1), a number past
 * the devices a mistake on the command line (2); neither falls back to the CPU. 0 to go on. */
static int check_device(long long device) {
    int devices = device >= 0 ? render_backend_vulkan.device_count() : -1;
    if (devices == 0) {
        log_error(RENDER_NO_VULKAN_DEVICE);
        return 1;
    }
    if (devices > 0 && device >= devices) {
        fprintf(stderr,
                "trazador: --device %lld: there %s %d Vulkan device%s (see `trazador devices`)\n",
                device, devices == 1 ? "is" : "are", devices, devices == 1 ? "" : "s");
        return 2;
    }
    return 0;
}

/* Writes a whole-image film as the output image; false (logged) on failure. */
static bool write_image(const render_args *a, const film *f) {
    const char *format = a->format >= 0 ? format_names[a->format] : NULL;
    return image_write_film(a->output, format, f, a->tm, a->exr_type == 0) &&
           (!a->aov_files || image_write_aov_files(a->output, format, f, a->exr_type == 0));
}

/* Says what a noise threshold saved: the samples drawn and the pixels that stopped early. */
static void report_adaptive(const part *p, float threshold) {
    size_t n = (size_t)(p->meta.x1 - p->meta.x0) * (size_t)(p->meta.y1 - p->meta.y0), early = 0;
    double drawn = 0.0;
    for (size_t i = 0; i < n; i++) {
        drawn += p->count[i];
        early += p->adaptive[4 * i + 3] > 0.0f;
    }
    double cap = (double)n * (p->meta.sample_end - p->meta.sample_begin);
    log_info("noise threshold %g: %.1f%% of the samples drawn, %zu of %zu pixels stopped early",
             threshold, cap > 0.0 ? 100.0 * drawn / cap : 0.0, early, n);
}

/* Renders and writes the image or the part; the exit code. started: when the command began, so
 * that the summary's set-up counts the scene's parse and its models' import too. */
static int render_and_write(const render_args *a, const scene *s, double started) {
    render_opts opts;
    render_opts_from_scene(s, &opts);
    apply_overrides(a, s, &opts);
    bool path = opts.mode == RENDER_MODE_PATH;
    char light_samples[48] = "";
    if (path)
        snprintf(light_samples, sizeof light_samples, ", light samples a vertex %d",
                 render_light_samples(&opts));
    log_debug(
        "render: %s mode, %d samples a pixel, %d bounces, %s sampler%s", path ? "path" : "report",
        opts.spp, opts.bounces,
        scene_sampler_of(opts.sampler, opts.mode) == RENDER_SAMPLER_SOBOL ? "sobol" : "random",
        light_samples);
    /* flags the render's mode has no use for are said once, as the scene's keys are */
    if (a->light_samples > 1 && !path)
        log_warn(
            "--light-samples does nothing in report mode: it is path mode's emitter samples "
            "a vertex");
    if (a->indirect >= 0 && path)
        log_warn("--%sindirect does nothing in path mode: paths bounce until --bounces",
                 a->indirect ? "" : "no-");
    if (!a->checkpoint && a->checkpoint_every > 0.0)
        log_warn("--checkpoint-every does nothing without --checkpoint");
    render_stats stats = {0};
    opts.stats = &stats;
    part_meta meta;
    render_part_meta(s, &opts, &meta);
    uint32_t end;
    if (!render_parse_region(a->region, &meta) || !render_parse_samples(a->samples, &meta, &end))
        return 2;
    if (meta.adaptive && meta.sample_begin > 0) {
        fprintf(stderr,
                "trazador: render: --samples %s with a noise threshold: whether a pixel takes a "
                "chunk depends on its samples before, so a part must begin at sample 0 (split "
                "by --region, or render 0:B and go on with --resume)\n",
                a->samples);
        return 2;
    }
    part p = {0};
    /* --device, --validate and --walk ask for Vulkan as --backend vulkan does. */
    int backend = a->backend == BACKEND_AUTO && (a->device >= 0 || a->validate || a->walk)
                      ? BACKEND_VULKAN
                      : a->backend;
    if (a->resume ? !render_load_resume(a->resume, &meta, end, backend, &p) : !part_init(&p, &meta))
        return 1;
    uint32_t begin = p.meta.sample_end;
    render_pacer pacer = {
        .checkpoint = a->checkpoint,
        .every = a->checkpoint_every > 0.0 ? a->checkpoint_every : CHECKPOINT_EVERY,
        .time_limit = a->time_limit};
    render_control control;
    bool paced = a->checkpoint || a->time_limit > 0.0;
    if (paced) {
        render_pacer_start(&pacer, &control);
        opts.control = &control;
        opts.deadline = render_pacer_deadline(&pacer);
    }
    const char *used = "";
    double start = clock_seconds();
    interrupts_saved saved;
    bool clear_on_signal = opts.progress && !a->checkpoint;
    if (clear_on_signal) interrupts_catch(clear_progress, &saved);
    /* SIGUSR1 asks for a checkpoint (tools/slurm sends it before a time limit); without one its
     * default action would kill the render. */
    struct sigaction ignore = {.sa_handler = SIG_IGN}, usr1_before;
    if (!a->checkpoint) {
        sigemptyset(&ignore.sa_mask);
        sigaction(SIGUSR1, &ignore, &usr1_before);
        log_debug("SIGUSR1: ignored, as it asks for a checkpoint and there is no --checkpoint");
    }
    bool ok = render_choose_part(s, &opts, (backend_choice)a->backend, &p, end, &used);
    if (!a->checkpoint) sigaction(SIGUSR1, &usr1_before, NULL);
    if (clear_on_signal) interrupts_restore(&saved);
    /* a checkpoint could not be written */
    if (!render_pacer_stop(&pacer, ok ? &p : NULL)) ok = false;
    double finished = clock_seconds(), elapsed = finished - start;
    if (ok && pacer.checkpoints)
        log_debug("checkpoints: %d written in %.3f s in all", pacer.checkpoints,
                  pacer.checkpoint_seconds);
    if (ok && pacer.stopped_by) {
        log_info("stopped by %s at sample %u of %u: checkpointed to %s; go on with --resume %s",
                 pacer.stopped_by == SIGINT ? "SIGINT" : "SIGTERM", p.meta.sample_end, end,
                 a->checkpoint, a->checkpoint);
        part_free(&p);
        return 128 + pacer.stopped_by;
    }
    bool as_part = a->region || a->samples || a->part;
    film f = {0};
    double write_start = clock_seconds();
    if (ok && as_part) {
        ok = part_write(a->output, &p);
    } else if (ok) {
        ok = part_film_so_far(&p, &f);
        if (ok) film_warn_problems(&f);
        ok = ok && write_image(a, &f);
    }
    if (ok) log_debug("output: written in %.1f ms", (clock_seconds() - write_start) * 1e3);
    if (ok && a->checkpoint && p.meta.sample_end == end)
        ok = render_finish_checkpoint(a->checkpoint, a->keep_checkpoint, &p);
    if (ok && meta.adaptive) report_adaptive(&p, opts.noise_threshold);
    if (ok && pacer.time_up)
        log_info("time limit: every pixel got samples %u:%u (%u of %u)", p.meta.sample_begin,
                 p.meta.sample_end, p.meta.sample_end - p.meta.sample_begin, end);
    if (ok && !a->quiet) {
        /* The rates are the sample passes' own; set-up is everything else since the command
         * began (the scene's parse, its models' import, the BVH, device and pipeline): a model's
         * import, part of the parse, once took as long as the rest and showed nowhere. */
        double render = stats.render_seconds > 0.0 ? stats.render_seconds : elapsed;
        double samples =
            (double)(p.meta.x1 - p.meta.x0) * (p.meta.y1 - p.meta.y0) * (p.meta.sample_end - begin);
        log_info(
            "%s: %dx%d, %u spp, %s back end, %.3f s rendering + %.3f s set-up, %.2f "
            "Msamples/s, %.1f Mrays/s",
            a->output, p.meta.x1 - p.meta.x0, p.meta.y1 - p.meta.y0,
            p.meta.sample_end - p.meta.sample_begin, used, render, finished - started - render,
            samples / render * 1e-6, (double)stats.rays / render * 1e-6);
    }
    film_free(&f);
    part_free(&p);
    return ok ? 0 : 1;
}

/* Parses the scene, or the model file given as one (model_scene.c): a file that fails to parse
 * on its first line and whose bytes or extension are a model format's (model_file_kind). False
 * with *err filled; *model: whether it was a model. */
static bool parse_scene_or_model(const render_args *a, const char *scene_path, scene *s,
                                 scene_error *err, bool *model) {
    *model = false;
    if (scene_parse_file_in_mode(scene_path, a->mode, s, err)) return true;
    char kind[64];
    if (err->out_of_memory || !strcmp(scene_path, "-") ||
        !model_file_kind(scene_path, err->line, kind, sizeof kind))
        return false;
    *model = true;
    log_debug("%s: a model file (%s), rendered as the scene", scene_path, kind);
    model_scene_opts o = {
        .camera = a->camera, .width = a->width, .mode = a->mode, .environment = a->environment};
    return model_scene_parse(scene_path, &o, s, err);
}

int cmd_render(int argc, char **argv) {
    render_args a;
    const char *scene_path;
    double started = clock_seconds();
    opt_result parsed_args = parse_render_args(argc, argv, &a, &scene_path);
    if (parsed_args != OPT_OK) return parsed_args == OPT_HELP ? 0 : parsed_args;
    if (a.mode >= 0) a.mode = (int)scene_mode_of_word(a.mode); /* seed is report */
    if (a.verbose) log_set_level(LOG_DEBUG);
    if (a.quiet) log_set_level(LOG_WARN);
    scene s;
    scene_error err;
    /* what messages call the scene */
    const char *scene_name = !scene_path               ? "scenes/cornell.scene (embedded)"
                             : strcmp(scene_path, "-") ? scene_path
                                                       : "<stdin>";
    double parse_start = clock_seconds();
    /* --mode decides whether emission is allowed, so the parser is told it. */
    bool model = false;
    bool parsed = scene_path
                      ? parse_scene_or_model(&a, scene_path, &s, &err, &model)
                      : scene_parse_string_in_mode(default_scene_text, strlen(default_scene_text),
                                                   scene_name, a.mode, &s, &err);
    if (!parsed) {
        scene_error_print(&err);
        return err.out_of_memory ? 1 : 2;
    }
    if ((a.camera || a.environment) && !model) {
        fprintf(stderr,
                a.camera ? "trazador: render: --camera picks a camera of a model file given as "
                           "the scene (render model.glb --camera 1): '%s' is a scene\n"
                         : "trazador: render: --environment lights a model file given as the "
                           "scene; '%s' is a scene (its environment line says what lights it)\n",
                scene_name);
        scene_free(&s);
        return 2;
    }
    log_debug("scene: read and parsed in %.1f ms", (clock_seconds() - parse_start) * 1e3);
    for (int k = 0; k < s.warning_count; k++) {
        const scene_error *w = &s.warnings[k];
        if (w->line > 0)
            log_warn("%s:%d:%d: %s", w->file, w->line, w->col, w->message);
        else /* a model file's, given as the scene: no line of the user's */
            log_warn("%s: %s", w->file, w->message);
    }
    /* A black image with exit 0 and no word looked like a broken renderer. */
    if (!scene_has_light(&s))
        log_warn(
            "%s: nothing lights this scene (no light of some power and colour, no emitting "
            "sphere or face, a black background): the image will be black",
            scene_name);
    /* An output that cannot be written is said before the render, not after it. */
    int rc = !cli_apply_width(a.width, &s)                  ? 2
             : is_input("output", a.output, scene_path, &s) ? 2
             : !atomic_file_check_force(a.output, a.force)  ? 1
                                                            : check_checkpoint(&a, scene_path, &s);
    if (rc == 0) rc = check_device(a.device);
    if (rc == 0) rc = render_and_write(&a, &s, started);
    scene_free(&s);
    return rc;
}
