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
#include "cli/render_args.h"
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

/* Seconds between checkpoints unless --checkpoint-every says. */
#define CHECKPOINT_EVERY 60.0

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
    const char *format = render_args_format(a);
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
