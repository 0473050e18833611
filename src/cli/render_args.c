/* render_args.c: the flags of `trazador render` (render_args.h). */
#include "cli/render_args.h"

#include <stddef.h>
#include <string.h>

#include "cli/cli.h"
#include "image/aov.h"
#include "image/image.h"
#include "render/render.h"
#include "scene/scene.h"

#define FORMATS "png|ppm|pfm|exr"
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

opt_result parse_render_args(int argc, char **argv, render_args *a, const char **scene_path) {
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

const char *render_args_format(const render_args *a) {
    return a->format >= 0 ? format_names[a->format] : NULL;
}
