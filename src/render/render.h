/* render.h: render options, the film, the progress line, the two back ends and the choice between
 * them. */
#ifndef TRAZADOR_RENDER_H
#define TRAZADOR_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "scene/scene.h"

/* What a render measured, for --verbose and bench. */
typedef struct render_stats {
    double pack_seconds;   /* struct scene -> GPU layout, BVH build included */
    double bvh_seconds;    /* BVH build alone */
    double render_seconds; /* the sample passes alone */
    uint64_t rays;         /* nearest-hit and shadow rays traced */
    uint32_t bvh_nodes, bvh_depth;
    uint64_t scene_bytes;       /* spheres, lights and BVH nodes as the shaders read them */
    unsigned validation_errors; /* Vulkan: what the validation layer reported (it fails the run) */
} render_stats;

/* How path mode samples emitters: both strategies weighted by MIS, or one alone. */
typedef enum path_strategy { PATH_MIS = 0, PATH_LIGHTS_ONLY, PATH_BSDF_ONLY } path_strategy;

/* The most threads the CPU back end runs. */
#define RENDER_MAX_THREADS 256

typedef struct render_opts {
    int samples; /* samples per pixel */
    uint32_t seed;
    bool no_jitter; /* zero is default: jitter on */
    bool indirect;         /* seed mode: the one bounce of indirect light */
    render_mode mode;      /* seed (the course report's model) or path (DESIGN section 3.2) */
    bool roulette;         /* path mode: Russian roulette from the fourth vertex */
    path_strategy strategy; /* path mode: MIS (the default), or one strategy alone (tests) */
    int bounces;           /* seed: longest chain of specular events; path: scattering events */
    int threads;           /* CPU back end; 0 = all cores */
    int device;            /* Vulkan back end; -1 = first */
    bool validate;         /* Vulkan validation layer, errors fail the run */
    bool no_bvh;           /* test every sphere for every ray (debugging, comparisons) */
    bool progress;         /* progress line on stderr */
    const char *cpu_build; /* CPU back end: the packet build by name; NULL: the fastest */
    render_stats *stats;   /* filled by the back end when not NULL */
} render_opts;

/* Per-pixel accumulation: 4 floats a pixel, RGB sums and the count of finite samples. */
typedef struct film {
    int width, height;
    float *accum;
    uint64_t nonfinite; /* samples dropped because their radiance was NaN or infinite */
} film;

/* Fills opts from the scene's `render` settings (flags override afterwards); never fails. */
void render_opts_from_scene(const scene *s, render_opts *opts);
/* Allocates a zeroed film; false on out-of-memory. */
bool film_init(film *f, int width, int height);
/* Frees the film; safe on a zeroed film. */
void film_free(film *f);

/* Prints the progress line on stderr: share done, time so far, samples per second and the time
 * left (samples: of the whole render); never fails. */
void render_progress_print(double share, double seconds, double samples);
/* Clears the progress line, so that messages start a clean line; never fails. */
void render_progress_clear(void);

/* Renders with the CPU back end (the packet integrator) into f (allocated by the call); false
 * on failure (logged). */
bool render_cpu(const scene *s, const render_opts *opts, film *f);

/* How a Vulkan render ended: done; refused, because this device cannot render this scene right
 * (the reason is given, nothing is logged: the caller may render it elsewhere); or failed
 * (logged). */
typedef enum render_status { RENDER_DONE, RENDER_REFUSED, RENDER_FAILED } render_status;
/* Bytes of a refusal's reason, its terminating NUL included. */
#define RENDER_REASON_SIZE 512
/* Renders with the Vulkan compute back end into f (allocated by the call); on RENDER_REFUSED
 * `reason` (RENDER_REASON_SIZE bytes) says why, on the other results it is "". */
render_status render_vk_try(const scene *s, const render_opts *opts, film *f, char *reason);
/* render_vk_try with a refusal logged as an error; true only when done. */
bool render_vk(const scene *s, const render_opts *opts, film *f);

/* The back end a render asks for: auto (Vulkan when it can render the scene, else the CPU). */
typedef enum backend_choice { BACKEND_AUTO = 0, BACKEND_VULKAN, BACKEND_CPU } backend_choice;
/* Renders with the back end chosen; *used names the one that rendered ("vulkan" or "cpu").
 * auto falls back to the CPU, with one line saying why, where Vulkan has no device, refuses the
 * scene or fails; a device or validation asked for (opts) makes Vulkan's verdict final. False
 * on failure (logged). */
bool render_choose(const scene *s, const render_opts *opts, backend_choice backend, film *f,
                   const char **used);

#endif
