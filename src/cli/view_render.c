/* view_render.c: the render thread of `trazador view` (view_render.h), driven through
 * render_choose_part and a render_control whose passes are one chunk each. */
#define _GNU_SOURCE /* gettid */
#include "cli/view_render.h"

#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

#include "render/part.h"
#include "util/clock.h"
#include "util/log.h"

struct view_render {
    const scene *base;
    render_opts opts;
    backend_choice backend;
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake;
    /* Under lock: what the main thread asks. */
    view_settings settings;
    double asked_at;               /* when the settings were asked for */
    uint64_t generation, rendered; /* asked for, and the last the thread finished */
    bool quit, failed;
    bool chunks_running; /* the passes that a change abandons are in flight (not the coarse) */
    volatile sig_atomic_t stop;
    /* Under lock: what the thread published. */
    view_frame latest;
};

/* One render of the thread: the settings' generation it renders and its rate's clock. */
typedef struct view_pass {
    view_render *v;
    uint64_t generation;
    double asked_at;         /* when its settings were asked for */
    uint32_t spp;            /* the samples the view goes to (the previews' parts have 1) */
    int width, height;       /* the view's image */
    bool preview;            /* the render in flight is a preview: shown even when superseded */
    bool coarse;             /* ... the coarse one, of every other pixel */
    uint32_t samples_before; /* published before the pass in flight */
    double since;            /* when the pass in flight began (the render, for the first) */
    const char *backend;
} view_pass;

/* img of the coarse preview, each pixel made 2 x 2, cut to width x height; false on out of
 * memory. */
static bool enlarge(image *img, int width, int height) {
    image big;
    if (!image_init(&big, width, height)) return false;
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++)
            memcpy(&big.rgb[3 * ((size_t)y * width + x)],
                   &img->rgb[3 * ((size_t)(y / 2) * img->width + x / 2)], 3 * sizeof(float));
    image_free(img);
    *img = big;
    return true;
}

/* Publishes part p (samples 0 to its sample_end) as the latest image, unless the settings
 * changed since it began (a preview is shown all the same: during a drag the settings change
 * faster than a preview of lavapipe's renders); false (logged) on out of memory. */
static bool publish(view_pass *r, const part *p) {
    view_render *v = r->v;
    film f = {0};
    image img = {0};
    part copy = {0};
    bool ok = part_film_so_far(p, &f) && image_from_film(&f, &img) &&
              (r->coarse ? enlarge(&img, r->width, r->height) : part_copy(p, &copy));
    film_free(&f);
    if (!ok) {
        log_error("view: out of memory for the image of a pass");
        image_free(&img);
        return false;
    }
    double now = clock_seconds();
    double pixels = (double)(p->meta.x1 - p->meta.x0) * (p->meta.y1 - p->meta.y0);
    uint32_t samples = p->meta.sample_end;
    pthread_mutex_lock(&v->lock);
    if (v->generation == r->generation || r->preview) {
        image old = v->latest.img;
        part old_part = v->latest.part;
        v->latest = (view_frame){
            .img = img,
            .part = copy,
            .samples = samples,
            .coarse = r->coarse,
            .spp = r->spp,
            .msamples = pixels * (samples - r->samples_before) / (now - r->since) * 1e-6,
            .backend = r->backend,
            .generation = r->generation,
            .asked_at = r->asked_at,
            .sequence = v->latest.sequence + 1};
        img = old;
        copy = old_part;
    }
    pthread_mutex_unlock(&v->lock);
    image_free(&img);
    part_free(&copy);
    r->samples_before = samples;
    r->since = now;
    return true;
}

/* Whether the settings of this render are still the ones asked for. */
static bool current(view_pass *r) {
    pthread_mutex_lock(&r->v->lock);
    bool same = !r->v->quit && r->v->generation == r->generation;
    pthread_mutex_unlock(&r->v->lock);
    return same;
}

/* render_control.next_pass: one chunk a pass while the settings stand (a preview's always),
 * the part handed over after each. */
static uint32_t next_pass(void *user, uint32_t done, bool *sync) {
    view_pass *r = user;
    bool go = current(r);
    if (r->preview) {
        pthread_mutex_lock(&r->v->lock);
        go = !r->v->quit;
        pthread_mutex_unlock(&r->v->lock);
    }
    *sync = go && done > r->samples_before;
    return go ? 1u : 0u;
}

/* render_control.synced: the pass just done, shown. */
static bool synced(void *user, const struct part *p) { return publish(user, p); }

/* Renders samples 0 to spp - 1 of scene s with opts into a fresh part, publishing each pass;
 * false on failure (logged). */
static bool render_samples(view_pass *r, const scene *s, render_opts opts, uint32_t spp,
                           backend_choice backend, bool stoppable) {
    view_render *v = r->v;
    opts.spp = (int)spp;
    render_control control = {
        .next_pass = next_pass, .synced = synced, .user = r, .stop = stoppable ? &v->stop : NULL};
    opts.control = &control;
    part_meta meta;
    render_part_meta(s, &opts, &meta);
    part p = {0};
    if (!part_init(&p, &meta)) return false;
    r->samples_before = 0;
    r->since = clock_seconds();
    const char *used = "";
    bool ok = render_choose_part(s, &opts, backend, &p, spp, &used);
    r->backend = used;
    /* auto chose once: later renders go to the same back end without its notices again. */
    if (ok && backend == v->backend)
        v->backend = strcmp(used, "cpu") ? BACKEND_VULKAN : BACKEND_CPU;
    /* The last pass is handed to no synced: it is published here. */
    if (ok && p.meta.sample_end > r->samples_before) ok = publish(r, &p);
    part_free(&p);
    return ok;
}

/* The scene and options of settings set; never fails. */
static void apply(const view_render *v, view_settings set, scene *s, render_opts *o) {
    *s = *v->base; /* the arrays shared, read only */
    s->camera_position = set.camera.position;
    s->camera_direction = set.camera.direction;
    s->camera_up = set.camera.up;
    *o = v->opts;
    if (o->mode != set.mode)
        o->bounces = v->base->bounces_given ? v->base->bounces : scene_default_bounces(set.mode);
    o->mode = set.mode;
}

/* Seconds the settings must stand before a Vulkan render: no move can abandon its set-up
 * (0.4-2.7 s of device and pipeline on lavapipe here), which would hold a drag's previews up. */
#define VIEW_VULKAN_SETTLE 0.25

/* Waits up to VIEW_VULKAN_SETTLE for other settings; whether none came (nor a quit). */
static bool settled(view_pass *r) {
    view_render *v = r->v;
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until); /* the condition variable's clock */
    long nanoseconds = until.tv_nsec + (long)(VIEW_VULKAN_SETTLE * 1e9);
    until.tv_sec += nanoseconds / 1000000000L;
    until.tv_nsec = nanoseconds % 1000000000L;
    pthread_mutex_lock(&v->lock);
    while (!v->quit && v->generation == r->generation &&
           pthread_cond_timedwait(&v->wake, &v->lock, &until) == 0) {
    }
    bool same = !v->quit && v->generation == r->generation;
    pthread_mutex_unlock(&v->lock);
    return same;
}

/* Renders one generation: the previews, then the chunks; false on failure (logged). */
static bool render_generation(view_render *v, view_settings set, uint64_t generation,
                              double asked_at) {
    scene s;
    render_opts o;
    apply(v, set, &s, &o);
    view_pass r = {.v = v,
                   .generation = generation,
                   .asked_at = asked_at,
                   .spp = (uint32_t)o.spp,
                   .width = s.width,
                   .height = s.height,
                   .backend = ""};
    /* A chunk of 16 samples takes about 0.7 s at 400 x 400 on two cores, its first sample a
     * twentieth of that, and that sample of every other pixel a quarter of it: the coarse
     * preview, rendered by the CPU back end whatever the view's: on Vulkan each render sets its
     * device and pipeline up again (0.4-2.7 s on lavapipe here), which a drag would wait for at
     * every move. A preview is never abandoned, so that a drag always shows some. */
    bool vulkan = v->backend == BACKEND_VULKAN;
    r.preview = true;
    if (s.width >= 2 && s.height >= 2) {
        scene coarse = s;
        coarse.pixel_size = 2.0f * s.pixel_size;
        coarse.width = (s.width + 1) / 2;
        coarse.height = (s.height + 1) / 2;
        r.coarse = true;
        if (!render_samples(&r, &coarse, o, 1, BACKEND_CPU, false)) return false;
        r.coarse = false;
    } else if (o.spp > 1 && !render_samples(&r, &s, o, 1, v->backend, false)) {
        return false;
    }
    r.preview = false;
    if (vulkan && !settled(&r)) return true;
    pthread_mutex_lock(&v->lock);
    v->chunks_running = true;
    v->stop = 0;
    pthread_mutex_unlock(&v->lock);
    bool ok = true;
    /* One sample of every pixel next, but not on Vulkan, where it would cost a set-up more. */
    if (!vulkan && o.spp > 1 && current(&r)) ok = render_samples(&r, &s, o, 1, v->backend, true);
    if (ok && current(&r)) ok = render_samples(&r, &s, o, (uint32_t)o.spp, v->backend, true);
    pthread_mutex_lock(&v->lock);
    v->chunks_running = false;
    pthread_mutex_unlock(&v->lock);
    return ok;
}

/* The render thread's niceness, which the back end's threads inherit: the window's thread
 * must not wait for a core behind them (on two cores it did, up to 80 ms an image). */
#define VIEW_RENDER_NICE 5

/* The thread: renders each generation asked for until told to quit. */
static void *render_thread(void *user) {
    view_render *v = user;
    /* Linux gives each thread its own niceness; failing to lower it only costs smoothness. */
    if (setpriority(PRIO_PROCESS, (id_t)gettid(), VIEW_RENDER_NICE) != 0)
        log_debug("view: the render thread keeps its priority");
    pthread_mutex_lock(&v->lock);
    while (!v->quit && !v->failed) {
        if (v->rendered == v->generation) {
            pthread_cond_wait(&v->wake, &v->lock);
            continue;
        }
        uint64_t generation = v->generation;
        view_settings set = v->settings;
        double asked_at = v->asked_at;
        pthread_mutex_unlock(&v->lock);
        bool ok = render_generation(v, set, generation, asked_at);
        pthread_mutex_lock(&v->lock);
        v->rendered = generation;
        if (!ok) v->failed = true;
    }
    pthread_mutex_unlock(&v->lock);
    return NULL;
}

view_render *view_render_start(const scene *s, const render_opts *opts, backend_choice backend,
                               view_settings first) {
    view_render *v = calloc(1, sizeof *v);
    if (!v) {
        log_error("view: out of memory");
        return NULL;
    }
    v->base = s;
    v->opts = *opts;
    v->backend = backend;
    v->settings = first;
    v->asked_at = clock_seconds();
    v->generation = 1;
    pthread_mutex_init(&v->lock, NULL);
    pthread_cond_init(&v->wake, NULL);
    if (pthread_create(&v->thread, NULL, render_thread, v) != 0) {
        log_error("view: cannot start the render thread");
        pthread_mutex_destroy(&v->lock);
        pthread_cond_destroy(&v->wake);
        free(v);
        return NULL;
    }
    return v;
}

uint64_t view_render_change(view_render *v, view_settings set) {
    pthread_mutex_lock(&v->lock);
    v->settings = set;
    v->asked_at = clock_seconds();
    uint64_t generation = ++v->generation;
    if (v->chunks_running) v->stop = 1;
    pthread_cond_signal(&v->wake);
    pthread_mutex_unlock(&v->lock);
    return generation;
}

bool view_render_take(view_render *v, view_frame *f) {
    pthread_mutex_lock(&v->lock);
    bool newer = v->latest.sequence > f->sequence;
    if (newer) {
        view_frame_free(f);
        *f = v->latest;
        v->latest.img = (image){0};
        v->latest.part = (part){0};
        /* the image and part moved out; the sequence stays, so that it is not taken twice */
    }
    pthread_mutex_unlock(&v->lock);
    return newer;
}

bool view_render_failed(view_render *v) {
    pthread_mutex_lock(&v->lock);
    bool failed = v->failed;
    pthread_mutex_unlock(&v->lock);
    return failed;
}

void view_frame_free(view_frame *f) {
    image_free(&f->img);
    part_free(&f->part);
}

void view_render_stop(view_render *v) {
    if (!v) return;
    pthread_mutex_lock(&v->lock);
    v->quit = true;
    v->stop = 1;
    pthread_cond_signal(&v->wake);
    pthread_mutex_unlock(&v->lock);
    pthread_join(v->thread, NULL);
    view_frame_free(&v->latest);
    pthread_mutex_destroy(&v->lock);
    pthread_cond_destroy(&v->wake);
    free(v);
}
