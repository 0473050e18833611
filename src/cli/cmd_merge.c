/* cmd_merge.c: `trazador merge PARTS... -o OUT`: reads render parts (EXR part files), checks that
 * they are of one render and cover it exactly once (render/part.h), and writes the whole
 * render's image, byte-identical to a single render's, or the merged part. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "image/image.h"
#include "render/part.h"
#include "util/atomic_file.h"
#include "util/clock.h"
#include "util/log.h"

typedef struct merge_args {
    const char *output;
    int format;   /* index in format_names, -1: from the extension */
    int tm;       /* tonemap */
    int exr_type; /* 0 half, 1 float */
    int part, force, quiet, verbose;
    int aov_files; /* the parts' feature images as files of their own */
} merge_args;

static const char *const format_names[] = {"png", "ppm", "pfm", "exr"};

#define ARG(field) offsetof(merge_args, field)
static const opt_spec merge_specs[] = {
    OPT_TEXT("--output", "-o", ARG(output), "FILE", "a file name",
             "the image to write, its format from the extension (required); - is standard "
             "output, with --format"),
    OPT_ONE_OF("--format", ARG(format), "png|ppm|pfm|exr",
               "the output's format, for any name (default: from the extension)"),
    OPT_ONE_OF("--exr-type", ARG(exr_type), "half|float",
               "an EXR image's channels (default half; a part is always float)"),
    OPT_SET("--part", NULL, ARG(part), 1,
            "write the merged parts as an EXR part file, which merges and resumes again; it may "
            "be partial: the parts must fill the smallest region and sample range holding them "
            "(default: the whole render's image)"),
    OPT_ONE_OF("--tonemap", ARG(tm), "srgb|linear",
               "8-bit encoding: sRGB or a plain clamp (default srgb; .pfm and .exr are linear)"),
    OPT_SET("--aov-files", NULL, ARG(aov_files), 1,
            "write the parts' feature images (render --aov) as files beside the image, "
            "NAME.albedo.pfm (.exr for an EXR output) and so on (default: layers of an EXR "
            "output only)"),
    OPT_SET("--force", NULL, ARG(force), 1,
            "replace a write-protected output (default: refuse it, as the shell's > does)"),
    OPT_SET("--quiet", "-q", ARG(quiet), 1, "warnings and errors only (default: a summary line)"),
    OPT_SET("--verbose", "-v", ARG(verbose), 1, "the timings of each stage (default off)"),
};
#undef ARG

static const opt_command merge_command = {
    .name = "merge",
    .synopsis =
        "usage: trazador merge PARTS... -o OUT [options]\n"
        "Merges the EXR parts of one render (`trazador render --region / --samples`) "
        "into its image,\nbyte-identical to the single render's.\n",
    .about =
        "The parts must be of one scene, seed, mode, settings and trazador version, and "
        "hold every\nsample of every pixel exactly once; the merge refuses, naming the "
        "files, otherwise.\n",
    .specs = merge_specs,
    .spec_count = OPT_COUNT(merge_specs),
    .max_positional = 1 << 20,
};

/* True (said) when the output is one of the parts (through any name or link): writing it would
 * replace a part with the image. */
static bool output_is_part(const char *output, const char *const *paths, int n) {
    for (int k = 0; k < n; k++) {
        if (atomic_file_same(output, paths[k])) {
            fprintf(stderr,
                    "trazador: merge: output '%s' is the part '%s' being merged: give another\n",
                    output, paths[k]);
            return true;
        }
    }
    return false;
}

int cmd_merge(int argc, char **argv) {
    merge_args a = {.format = -1, .tm = -1, .exr_type = -1};
    const char **paths = calloc((size_t)argc + 1, sizeof *paths);
    if (!paths) {
        log_error("merge: out of memory");
        return 1;
    }
    int n = 0;
    opt_result rc = opt_parse(&merge_command, argc, argv, &a, paths, &n);
    int status = rc == OPT_HELP ? 0 : rc;
    /* - is standard output, as for render; it needs --format, there being no extension. */
    bool to_stdout = rc == OPT_OK && a.output && !strcmp(a.output, "-");
    if (to_stdout) a.output = "/dev/stdout";
    if (rc == OPT_OK) {
        const char *format = a.format >= 0 ? format_names[a.format]
                             : a.output    ? image_path_format(a.output)
                                           : NULL;
        status = 0;
        if (n == 0)
            status = opt_usage_error(&merge_command, "no parts given");
        else if (!a.output)
            status = opt_usage_error(&merge_command, "-o OUT is required");
        else if (to_stdout && a.format < 0)
            status = opt_usage_error(&merge_command,
                                     "-o - (standard output) needs --format png|ppm|pfm|exr");
        else if (!format)
            status = opt_usage_error(&merge_command,
                                     "output '%s' must end in .png, .ppm, .pfm or .exr, or take "
                                     "--format",
                                     a.output);
        else if (a.part && strcmp(format, "exr"))
            status = opt_usage_error(&merge_command, "--part writes an EXR: give -o NAME.exr");
        else if (a.part && a.aov_files)
            status = opt_usage_error(&merge_command,
                                     "--aov-files writes beside an image: a part keeps its "
                                     "feature images as layers");
        if (a.verbose) log_set_level(LOG_DEBUG);
        if (a.quiet) log_set_level(LOG_WARN);
        if (status == 0) cli_warn_unused(format, a.part, &a.tm, &a.exr_type);
        if (status == 0 && output_is_part(a.output, paths, n)) status = 2;
        if (status == 0 && !atomic_file_check_force(a.output, a.force)) status = 1;
        if (status == 0) {
            double t0 = clock_seconds();
            part merged;
            film f = {0};
            bool merged_ok = part_merge_files(paths, n, !a.part, &merged);
            double t1 = clock_seconds();
            bool ok = merged_ok &&
                      (a.part ? part_write(a.output, &merged)
                              : part_film(&merged, &f) &&
                                    image_write_film(a.output, format, &f, a.tm, a.exr_type == 0) &&
                                    (!a.aov_files ||
                                     image_write_aov_files(a.output, format, &f, a.exr_type == 0)));
            if (ok && !a.quiet)
                log_info("%s: %d part%s of %dx%d, %u spp merged in %.3f s, written in %.3f s",
                         a.output, n, n == 1 ? "" : "s", merged.meta.width, merged.meta.height,
                         merged.meta.spp, t1 - t0, clock_seconds() - t1);
            if (merged_ok) part_free(&merged);
            film_free(&f);
            status = ok ? 0 : 1;
        }
    }
    free(paths);
    return status;
}
