/* render.h: render options, the progress line, the table of the two back ends and the choice
 * between them. */
#ifndef TRAZADOR_RENDER_H
#define TRAZADOR_RENDER_H

#include <signal.h>
#include <stdbool.h>
#include <stdint.h>

#include "image/film.h"
#include "scene/scene.h"

/* What a render measured, for --verbose and bench. */
typedef struct render_stats {
    double pack_seconds;   /* struct scene -> GPU layout, BVH build included */
    double bvh_seconds;    /* BVH build alone */
    double render_seconds; /* the sample passes alone */
    uint64_t rays;         /* nearest-hit and shadow rays traced */
    uint32_t bvh_nodes, bvh_depth;
    uint64_t scene_bytes; /* spheres, lights and BVH nodes as the shaders read them */
} render_stats;

/* How path mode samples emitters: both strategies weighted by MIS, or one alone. */
typedef enum path_strategy { PATH_MIS = 0, PATH_LIGHTS_ONLY, PATH_BSDF_ONLY } path_strategy;

struct part; /* render/part.h */

/* What a render asks between its passes (a pass: whole chunks of samples of every pixel, see
 * render/chunk_tree.h): checkpoints, time limits, signals. */
typedef struct render_control {
    /* Called before the first pass and after each, the part then holding samples up to `done`
     * (or, when the back end keeps its sums elsewhere, as of the last sync); returns the chunks
     * of the next pass, 0 to stop, and sets *sync to have the part brought up to date and handed
     * to `synced` (then called at once). */
    uint32_t (*next_pass)(void *user, uint32_t done, bool *sync);
    /* The part, up to date; false fails the render (logged by it). */
    bool (*synced)(void *user, const struct part *p);
    void *user;
    /* Non-zero (a signal handler sets it): the back end abandons the pass in flight (the CPU
     * one at its next tile, the Vulkan one at its next submission), its samples lost and the
     * part as before it, and asks next_pass at once, so that a stop need not wait for a whole
     * pass. NULL: passes always finish. */
    volatile sig_atomic_t *stop;
} render_control;

/* The most threads the CPU back end runs. */
#define RENDER_MAX_THREADS 256

/* How the Vulkan back end walks rays through the scene (`render --walk`): auto (the measured
 * faster one for the device type), the compute BVH walk per invocation, the subgroup's
 * cooperative walk, or ray queries through the device's acceleration structure. */
typedef enum render_walk {
    RENDER_WALK_AUTO,
    RENDER_WALK_COMPUTE,
    RENDER_WALK_COOPERATIVE,
    RENDER_WALK_RAY_QUERY
} render_walk;

typedef struct render_opts {
    int spp; /* samples per pixel */
    uint32_t seed;
    bool no_jitter;         /* zero is default: jitter on */
    bool indirect;          /* report mode: the one bounce of indirect light */
    render_mode mode;       /* report (the course report's model) or path (DESIGN section 3.2) */
    bool roulette;          /* path mode: Russian roulette from the fourth vertex */
    int light_samples;      /* path mode: emitter samples a diffuse vertex (0 as 1) */
    render_sampler sampler; /* auto: scene_sampler_of the mode */
    path_strategy strategy; /* path mode: MIS (the default), or one strategy alone (tests) */
    int bounces;            /* report: longest chain of specular events; path: scattering events */
    int threads;            /* CPU back end; 0 = all cores */
    bool device_given;      /* Vulkan back end: `device` was asked for (--device) */
    int device;             /* the Vulkan device asked for; without device_given the first */
    bool validate;          /* Vulkan validation layer, errors fail the run */
    render_walk walk;       /* Vulkan back end; auto (0) also reads TRAZADOR_VK_WALK */
    bool no_bvh;            /* test every sphere for every ray (debugging, comparisons) */
    bool progress;          /* progress line on stderr */
    const char *cpu_build;  /* CPU back end: the packet build by name; NULL: the fastest */
    render_stats *stats;    /* filled by the back end when not NULL */
    const render_control *control; /* NULL: every pass at once */
    double deadline; /* clock_seconds() when a time limit ends, for the progress line; 0: none */
    uint32_t aov;    /* the feature images (image/aov.h) a part of chunk 0 gets, a bit a kind */
    /* Adaptive sampling (common/adaptive.h): a pixel whose estimated error is at most this
     * renders no further chunk; 0: off, every pixel renders spp samples. */
    float noise_threshold;
} render_opts;

/* Fills opts from the scene's `render` settings (flags override afterwards); never fails. */
void render_opts_from_scene(const scene *s, render_opts *opts);

/* The emitter samples a diffuse vertex of path mode takes: opts' light_samples, 1 for 0, and 1 in
 * report mode. */
static inline int render_light_samples(const render_opts *o) {
    return o->mode == RENDER_MODE_PATH && o->light_samples > 1 ? o->light_samples : 1;
}

/* Prints the progress line on stderr: share done, time so far, samples per second and the time
 * left (samples: of the whole render), at most what is left until `deadline` (clock_seconds(),
 * 0 for none); never fails. */
void render_progress_print(double share, double seconds, double samples, double deadline);
/* Clears the progress line, so that messages start a clean line; never fails. */
void render_progress_clear(void);

/* How a back end's render ended: done; refused, because it cannot render this scene right here
 * (the reason is given, nothing is logged: the caller may render it elsewhere); failed (logged);
 * or invalid: the Vulkan validation layer reported errors (logged), which no fallback may hide. */
typedef enum render_status {
    RENDER_DONE,
    RENDER_REFUSED,
    RENDER_FAILED,
    RENDER_INVALID
} render_status;
/* Bytes of a refusal's reason, its terminating NUL included. */
#define RENDER_REASON_SIZE 512
/* The end of every refusal of a scene or device by the Vulkan back end, which the CPU back end
 * renders; --backend auto drops it from its notice, since it falls back by itself. */
#define RENDER_USE_CPU ": use --backend cpu"
/* What to tell a user who asked for Vulkan and has no Vulkan device. */
#define RENDER_NO_VULKAN_DEVICE                                                          \
    "no Vulkan device found (VK_LOADER_DEBUG=all shows why): install lavapipe (Debian: " \
    "apt-get install mesa-vulkan-drivers) or use --backend cpu"
/* The CPU back end's one-sample build (render_opts.cpu_build): the reference of every other. */
#define RENDER_CPU_REFERENCE "reference"

/* A back end: the CPU one (src/render/cpu/) or the Vulkan one (src/render/vk/). */
typedef struct render_backend {
    const char *name; /* "cpu" or "vulkan": what --backend and a part's metadata call it */
    /* The devices it can render on here, 0 where it has none (no Vulkan loader, driver or
     * device); logs nothing. */
    int (*device_count)(void);
    /* Whether every one of those devices is a CPU (lavapipe). */
    bool (*cpu_only)(void);
    /* Prints on stdout what it renders with here (its builds, or its devices and what they
     * offer); false on failure (logged). */
    bool (*describe)(void);
    /* Adds to part p (its region, from its sample_end on) the samples up to sample_end
     * (chunk-aligned or the render's total) in passes that opts->control sets; on a refusal
     * `reason` (RENDER_REASON_SIZE bytes) says why, otherwise it is "". After a failure or a
     * refusal the part holds what was last synced, from which another back end can go on. */
    render_status (*render_part)(const scene *s, const render_opts *opts, struct part *p,
                                 uint32_t sample_end, char *reason);
} render_backend;

extern const render_backend render_backend_cpu;    /* render/cpu/render_cpu.c */
extern const render_backend render_backend_vulkan; /* render/vk/render_vk.c */

/* Renders the whole image with back end b into f (allocated by the call), a refusal logged as
 * an error; true only when done. */
bool render_film(const render_backend *b, const scene *s, const render_opts *opts, film *f);

/* The back end a render asks for: auto (Vulkan when it can render the scene, else the CPU). */
typedef enum backend_choice { BACKEND_AUTO = 0, BACKEND_VULKAN, BACKEND_CPU } backend_choice;
/* Renders with the back end chosen; *used names the one that rendered ("vulkan" or "cpu").
 * auto falls back to the CPU, with one line saying why, where Vulkan has no device, refuses the
 * scene or fails; a device or validation asked for (opts) makes Vulkan's verdict final. False
 * on failure (logged). */
bool render_choose(const scene *s, const render_opts *opts, backend_choice backend, film *f,
                   const char **used);
/* The samples of a pixel whose first hits make its feature images: enough to smooth edges, few
 * enough to cost a few percent of a render (docs/PERF.md, "Feature images"). */
#define RENDER_AOV_SAMPLES 4
/* Fills part p's feature images of opts->aov (p->aov, zeroed before): the mean over samples 0 to
 * min(RENDER_AOV_SAMPLES, spp) - 1 of each pixel of its region of the first hit's features
 * (shaders/common/aov.h), computed by the C text for either back end (render/cpu/render_aov.c);
 * false (logged) on failure. */
bool render_aov(const scene *s, const render_opts *opts, struct part *p);
/* render_choose for a part (render_backend.render_part), with the feature images opts->aov asks
 * for when the part begins at sample 0; false on failure (logged). */
bool render_choose_part(const scene *s, const render_opts *opts, backend_choice backend,
                        struct part *p, uint32_t sample_end, const char **used);

/* Fills the metadata of a part of scene s rendered with opts: digest (render_digest), mode,
 * version, seed, samples, chunk and size; the whole image and samples 0:0. Never fails. */
struct part_meta;
void render_part_meta(const scene *s, const render_opts *opts, struct part_meta *m);

#endif
