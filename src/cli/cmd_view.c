/* cmd_view.c: `trazador view [SCENE]`: a window showing the render converge pass by pass on the
 * chosen back end (view_render.c), tonemapped as `render` writes a PNG; the mouse moves the
 * camera (view_camera.c) and restarts it, keys print the camera line, save the image and its
 * part, switch the mode and change the exposure (view_window.c). */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "cli/view_camera.h"
#include "cli/view_render.h"
#include "cli/view_window.h"
#include "default_scene.h"
#include "image/image.h"
#include "render/part.h"
#include "scene/scene.h"
#include "util/clock.h"
#include "util/log.h"

typedef struct view_args {
    int backend;                                 /* backend_choice */
    long long spp, seed, threads, device, width; /* -1: not given */
    int mode;                                    /* -1 not given, else the word's index */
    int no_jitter, tm, verbose, quiet;
    const char *save_as; /* the saved files' prefix */
} view_args;

/* Exposure keys change it by this many stops. */
#define EXPOSURE_STEP 0.5
/* The event loop's longest wait for an event: how late a published image can be shown. */
#define VIEW_POLL_MS 5

#define ARG(field) offsetof(view_args, field)
static const opt_spec view_specs[] = {
    OPT_ONE_OF("--backend", ARG(backend), "auto|vulkan|cpu",
               "the back end (default auto: Vulkan where it can render the scene, else the CPU)"),
    OPT_WHOLE("--spp", NULL, ARG(spp), 1, SCENE_MAX_SAMPLES,
              "samples per pixel to converge to, then the image stays, 1 to " CLI_AS_TEXT(
                  SCENE_MAX_SAMPLES) " (default: the scene's, else 64)"),
    OPT_WHOLE("--seed", NULL, ARG(seed), 0, 4294967295.0,
              "the random seed (default: the scene's, else 1)"),
    OPT_ONE_OF("--mode", ARG(mode), "report|path|seed",
               "the integrator to start with (default: the scene's); the m key switches it"),
    OPT_SET("--no-jitter", NULL, ARG(no_jitter), 1,
            "every sample through the pixel's centre (default: jittered)"),
    OPT_WHOLE("--width", NULL, ARG(width), 1, SCENE_MAX_RESOLUTION,
              "N pixels across the scene's plane (default: the scene's pixel size)"),
    OPT_WHOLE("--threads", NULL, ARG(threads), 1, RENDER_MAX_THREADS,
              "CPU back end threads (default: one per core)"),
    OPT_WHOLE("--device", NULL, ARG(device), 0, 255,
              "the Vulkan device, no fallback (default: the first)"),
    OPT_ONE_OF("--tonemap", ARG(tm), "srgb|linear",
               "8-bit encoding of the window and the saved PNG (default srgb)"),
    OPT_TEXT("--save-as", NULL, ARG(save_as), "PREFIX", "a file name prefix",
             "the s key writes PREFIX-N.png and PREFIX-N.exr, N the first number free "
             "(default view)"),
    OPT_SET("--quiet", "-q", ARG(quiet), 1, "warnings and errors only"),
    OPT_SET("--verbose", "-v", ARG(verbose), 1,
            "the timings of the window: first image, frame times (default off)"),
};
#undef ARG

static const opt_command view_command = {
    .name = "view",
    .synopsis =
        "usage: trazador view [SCENE] [options]\n"
        "Shows SCENE (default: the embedded scenes/cornell.scene) converging in a window.\n",
    .about =
        "Mouse: left drag orbits about the point under the centre, right or middle drag pans,\n"
        "the wheel moves in and out. Keys: c prints the camera as a scene line, s saves the\n"
        "image (PNG) and its samples so far (an EXR part for merge and --resume), m switches\n"
        "report and path mode, + and - change the exposure, Escape quits.\n",
    .specs = view_specs,
    .spec_count = OPT_COUNT(view_specs),
    .max_positional = 1,
};

/* What the event loop keeps between events. */
typedef struct view_state {
    const scene *s;
    const char *name; /* the scene's, for the title */
    view_window *w;
    view_render *render;
    view_settings settings;
    uint64_t generation; /* of the settings shown */
    bool has_emitters;   /* report mode refuses emitters */
    bool dragging;
    int drag_button, drag_x, drag_y;
    view_drag drag;
    double exposure; /* stops */
    tonemap tm;
    const char *save_as;
    int saved; /* the last N of PREFIX-N */
} view_state;

/* The window's title: the scene, the samples of f (NULL: none yet), the rate, the back end, the
 * mode, the exposure. */
static void set_title(const view_state *st, const view_frame *f) {
    char title[512];
    const char *mode = st->settings.mode == RENDER_MODE_PATH ? "path" : "report";
    if (!f || !f->img.rgb || f->generation != st->generation) {
        snprintf(title, sizeof title, "trazador view %s | rendering | %s mode | exposure %+.1f",
                 st->name, mode, st->exposure);
    } else {
        char samples[64];
        if (f->coarse)
            snprintf(samples, sizeof samples, "preview of %u spp", f->spp);
        else
            snprintf(samples, sizeof samples, "%u of %u spp%s", f->samples, f->spp,
                     f->samples == f->spp ? " (done)" : "");
        snprintf(title, sizeof title,
                 "trazador view %s | %s | %.2f Msamples/s | %s | %s mode | exposure %+.1f",
                 st->name, samples, f->msamples, f->backend, mode, st->exposure);
    }
    view_window_title(st->w, title);
}

/* Asks the render thread for the settings as they are now. The title says so at once, before
 * any later event is handled: a script that sees what a later key prints (the camera line) sees
 * the title of the new settings too. */
static void restart(view_state *st) {
    st->generation = view_render_change(st->render, st->settings);
    set_title(st, NULL);
}

/* img scaled by 2^exposure (exactly, a power of two), as the window shows it and `s` saves it. */
static bool exposed(const image *img, double exposure, image *out) {
    if (!image_init(out, img->width, img->height)) return false;
    float scale = (float)exp2(exposure);
    size_t n = (size_t)img->width * img->height * 3;
    for (size_t i = 0; i < n; i++) out->rgb[i] = img->rgb[i] * scale;
    return true;
}

/* The 8-bit pixels of the frame through the PNG writer's tonemap (image.h's table); at exposure
 * 0 the scale is 1, which changes no float. */
static void encode(const view_state *st, const tonemap_table *t, const image *img, uint8_t *rgb) {
    size_t n = (size_t)img->width * img->height * 3;
    float scale = (float)exp2(st->exposure);
    for (size_t i = 0; i < n; i++) rgb[i] = tonemap_table_channel(t, img->rgb[i] * scale);
}

/* Writes PREFIX-N.png (the image as shown) and PREFIX-N.exr (its part); said on stdout. */
static void save(view_state *st, const view_frame *f) {
    if (!f->img.rgb || f->coarse) {
        log_warn("view: nothing to save yet: the image shown is a coarse preview");
        return;
    }
    char png[4096], exr[4096];
    do {
        st->saved++;
        snprintf(png, sizeof png, "%s-%d.png", st->save_as, st->saved);
        snprintf(exr, sizeof exr, "%s-%d.exr", st->save_as, st->saved);
    } while (access(png, F_OK) == 0 || access(exr, F_OK) == 0);
    image shown = {0};
    bool ok = exposed(&f->img, st->exposure, &shown) && image_write(png, &shown, st->tm) &&
              part_write(exr, &f->part);
    image_free(&shown);
    if (ok) {
        printf("saved %s and %s (samples 0:%u)\n", png, exr, f->samples);
        fflush(stdout);
    }
}

/* Prints the camera as a scene line on stdout, at once (a script may wait for it). */
static void print_camera(const view_state *st) {
    char line[512];
    view_camera_line(st->s, st->settings.camera, line, sizeof line);
    printf("%s\n", line);
    fflush(stdout);
}

/* Acts on one event; false when the view should close. */
static bool handle(view_state *st, view_event e, const view_frame *f, bool *redraw) {
    switch (e.kind) {
        case VIEW_EVENT_QUIT:
            return false;
        case VIEW_EVENT_EXPOSED:
            *redraw = true;
            return true;
        case VIEW_EVENT_PRESS:
            st->dragging = true;
            st->drag_button = e.button;
            st->drag_x = e.x, st->drag_y = e.y;
            st->drag = view_camera_drag(st->s, st->settings.camera);
            return true;
        case VIEW_EVENT_RELEASE:
            st->dragging = false;
            return true;
        case VIEW_EVENT_MOVE: {
            if (!st->dragging) return true;
            int dx = e.x - st->drag_x, dy = e.y - st->drag_y;
            view_camera c = st->drag_button == 0 ? view_camera_orbit(&st->drag, dx, dy)
                                                 : view_camera_pan(st->s, &st->drag, dx, dy);
            if (memcmp(&c, &st->settings.camera, sizeof c)) {
                st->settings.camera = c;
                restart(st);
            }
            return true;
        }
        case VIEW_EVENT_WHEEL: {
            if (e.wheel == 0) return true; /* a sideways scroll */
            view_drag d = view_camera_drag(st->s, st->settings.camera);
            st->settings.camera = view_camera_dolly(&d, e.wheel);
            restart(st);
            return true;
        }
        case VIEW_EVENT_KEY:
            if (e.key == 'c') print_camera(st);
            if (e.key == 's') save(st, f);
            if (e.key == '+' || e.key == '-')
                st->exposure += e.key == '+' ? EXPOSURE_STEP : -EXPOSURE_STEP;
            if (e.key == 'm') {
                render_mode to =
                    st->settings.mode == RENDER_MODE_PATH ? RENDER_MODE_REPORT : RENDER_MODE_PATH;
                if (to == RENDER_MODE_REPORT && st->has_emitters) {
                    log_warn("view: the scene has emitters, which report mode cannot render");
                } else {
                    st->settings.mode = to;
                    restart(st);
                }
            }
            return true;
        default:
            return true;
    }
}

/* What --verbose reports of the window's timings. */
typedef struct view_timing {
    double start, opened, first, closed; /* the command's start, the window's open, the first
                                          * image, the window's close */
    int images;
    double show_total, show_worst; /* tonemap, upload and present of an image */
    double turn_worst;             /* an event loop turn, its wait for events left out */
    int changes;                   /* settings whose image came, and the seconds it took */
    double change_total, change_worst;
} view_timing;

/* The event loop until the view closes: its exit code. */
static int run_window(view_window *w, view_state *st, view_timing *t) {
    view_frame f = {0};
    uint8_t *rgb = malloc((size_t)w->width * w->height * 3);
    if (!rgb) {
        log_error("view: out of memory");
        return 1;
    }
    tonemap_table table;
    tonemap_table_init(&table, st->tm);
    int rc = 0;
    bool running = true;
    uint64_t shown = 0, shown_generation = 0;
    double shown_exposure = st->exposure;
    char title_key[64] = "";
    while (running) {
        view_event e = view_window_next(w, VIEW_POLL_MS);
        double turn = clock_seconds();
        bool redraw = false;
        for (; e.kind != VIEW_EVENT_NONE && running; e = view_window_next(w, 0))
            running = handle(st, e, &f, &redraw);
        if (view_render_failed(st->render)) {
            rc = 1;
            break;
        }
        bool fresh = view_render_take(st->render, &f);
        if (f.img.rgb && (fresh || shown_exposure != st->exposure)) {
            double t0 = clock_seconds();
            encode(st, &table, &f.img, rgb);
            if (!view_window_show(w, rgb)) {
                rc = 1;
                break;
            }
            double took = clock_seconds() - t0;
            if (!t->images) t->first = clock_seconds();
            t->images++;
            t->show_total += took;
            t->show_worst = fmax(t->show_worst, took);
            /* The first image of new settings: how long a move of the camera waits to show. */
            if (f.generation > 1 && f.generation != shown_generation) {
                double wait = clock_seconds() - f.asked_at;
                t->changes++;
                t->change_total += wait;
                t->change_worst = fmax(t->change_worst, wait);
            }
            shown = f.sequence;
            shown_generation = f.generation;
            shown_exposure = st->exposure;
        } else if (redraw && shown) {
            view_window_redraw(w);
        }
        /* The title changes with each image and setting, not each turn: X round trips. */
        char key[64];
        snprintf(key, sizeof key, "%llu %llu %g %d", (unsigned long long)shown,
                 (unsigned long long)st->generation, st->exposure, (int)st->settings.mode);
        if (strcmp(key, title_key)) {
            set_title(st, &f);
            snprintf(title_key, sizeof title_key, "%s", key);
        }
        t->turn_worst = fmax(t->turn_worst, clock_seconds() - turn);
    }
    view_frame_free(&f);
    free(rgb);
    return rc;
}

/* The view of scene s, parsed from `name`: the window and the render; the exit code. */
static int view_scene(const view_args *a, scene *s, const char *name, view_timing *t) {
    render_opts opts;
    render_opts_from_scene(s, &opts);
    if (a->spp >= 0) opts.spp = (int)a->spp;
    if (a->seed >= 0) opts.seed = (uint32_t)a->seed;
    if (a->mode >= 0) {
        opts.mode = scene_mode_of_word(a->mode);
        if (!s->bounces_given) opts.bounces = scene_default_bounces(opts.mode);
    }
    if (a->threads >= 0) opts.threads = (int)a->threads;
    if (a->device >= 0) opts.device = (int)a->device, opts.device_given = true;
    opts.no_jitter = a->no_jitter;
    view_state st = {.s = s,
                     .name = name,
                     .settings = {view_camera_of(s), opts.mode},
                     .generation = 1,
                     .has_emitters = scene_emits(s),
                     .tm = (tonemap)a->tm,
                     .save_as = a->save_as ? a->save_as : "view"};
    view_window w;
    char why[512];
    char title[300];
    snprintf(title, sizeof title, "trazador view %s", name);
    if (!view_window_has_display(why, sizeof why)) {
        fprintf(stderr, "trazador: view: %s\n", why);
        return 2;
    }
    /* The render starts before the window opens: SDL's set-up (100-250 ms here, an OpenGL
     * renderer on llvmpipe) and the first preview overlap. */
    int backend = a->device >= 0 && a->backend == BACKEND_AUTO ? BACKEND_VULKAN : a->backend;
    st.render = view_render_start(s, &opts, (backend_choice)backend, st.settings);
    if (!st.render) return 1;
    if (!view_window_open(&w, s->width, s->height, title, why, sizeof why)) {
        view_render_stop(st.render);
        fprintf(stderr, "trazador: view: %s\n", why);
        return 2;
    }
    t->opened = clock_seconds();
    st.w = &w;
    int rc = run_window(&w, &st, t);
    t->closed = clock_seconds();
    view_render_stop(st.render);
    view_window_close(&w);
    return rc;
}

int cmd_view(int argc, char **argv) {
    view_timing t = {.start = clock_seconds()};
    view_args a = {.spp = -1, .seed = -1, .threads = -1, .device = -1, .width = -1, .mode = -1};
    const char *scene_path = NULL;
    int count;
    opt_result parsed_args = opt_parse(&view_command, argc, argv, &a, &scene_path, &count);
    if (parsed_args != OPT_OK) return parsed_args == OPT_HELP ? 0 : parsed_args;
    if (a.device >= 0 && a.backend == BACKEND_CPU)
        return opt_usage_error(&view_command,
                               "--device names a Vulkan device: it cannot go with --backend cpu");
    if (a.verbose) log_set_level(LOG_DEBUG);
    if (a.quiet) log_set_level(LOG_WARN);
    int mode = a.mode >= 0 ? (int)scene_mode_of_word(a.mode) : -1;
    scene s;
    scene_error err;
    bool parsed =
        scene_path ? scene_parse_file_in_mode(scene_path, mode, &s, &err)
                   : scene_parse_string_in_mode(default_scene_text, strlen(default_scene_text),
                                                "scenes/cornell.scene (embedded)", mode, &s, &err);
    if (!parsed) {
        scene_error_print(&err);
        return err.out_of_memory ? 1 : 2;
    }
    for (int k = 0; k < s.warning_count; k++)
        log_warn("%s:%d:%d: %s", s.warnings[k].file, s.warnings[k].line, s.warnings[k].col,
                 s.warnings[k].message);
    const char *name = scene_path ? scene_path : "cornell.scene";
    int rc = cli_apply_width(a.width, &s) ? view_scene(&a, &s, name, &t) : 2;
    if (rc == 0 && t.images)
        log_debug(
            "view: first image %.3f s after the window opened (%.3f s after the start); %d "
            "images in %.2f s, tonemap and upload %.2f ms on average, %.2f ms at worst; longest "
            "event loop turn %.2f ms",
            t.first - t.opened, t.first - t.start, t.images, t.closed - t.opened,
            t.show_total / t.images * 1e3, t.show_worst * 1e3, t.turn_worst * 1e3);
    if (rc == 0 && t.changes)
        log_debug(
            "view: %d moves of the camera or mode shown, %.1f ms to their first image on "
            "average, %.1f ms at worst",
            t.changes, t.change_total / t.changes * 1e3, t.change_worst * 1e3);
    scene_free(&s);
    return rc;
}
