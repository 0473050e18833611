/* render_args.h: the flags of `trazador render` (render_args.c: their table, defaults and the
 * checks that need several of them), which cmd_render.c acts on. */
#ifndef TRAZADOR_CLI_RENDER_ARGS_H
#define TRAZADOR_CLI_RENDER_ARGS_H

#include <stdint.h>

#include "cli/options.h"

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

/* Parses `render` arguments; OPT_OK to go on, OPT_HELP, or OPT_USAGE (printed). */
opt_result parse_render_args(int argc, char **argv, render_args *a, const char **scene_path);
/* The --format given ("png", ...), NULL when the output's extension decides. */
const char *render_args_format(const render_args *a);

#endif
