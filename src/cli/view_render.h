/* view_render.h: the render thread of `trazador view`. It renders the scene as the view's
 * camera and mode say: a coarse preview (one sample of every other pixel, each shown as 2 x 2,
 * by the CPU back end whatever the view's), one sample of every pixel (not on Vulkan, where each
 * render sets the device up again), then whole chunks of 16 samples up to the samples asked for,
 * publishing the image after every pass. A change of camera or mode abandons the pass in flight
 * and starts over; previews are never abandoned, and shown even once superseded, so that a drag
 * shows its moves. Each image but the coarse preview is the very film `render --spp N` makes for
 * its N samples, so the window can show it byte for byte. */
#ifndef TRAZADOR_VIEW_RENDER_H
#define TRAZADOR_VIEW_RENDER_H

#include <stdbool.h>
#include <stdint.h>

#include "cli/view_camera.h"
#include "image/image.h"
#include "render/part.h"
#include "render/render.h"

/* What the view changes between renders. */
typedef struct view_settings {
    view_camera camera;
    render_mode mode;
} view_settings;

/* The image last published and what it is. */
typedef struct view_frame {
    image img;           /* the mean of the samples so far, linear RGB */
    part part;           /* their part (`render --part`'s file); none for the coarse preview */
    uint32_t samples;    /* samples a pixel in img */
    bool coarse;         /* img is the coarse preview: no part to save */
    uint32_t spp;        /* the samples the render goes to */
    double msamples;     /* the last pass's rate, Msamples/s (set-up included) */
    const char *backend; /* "cpu" or "vulkan" */
    uint64_t generation; /* the settings it shows: view_render_change's count */
    double asked_at;     /* when they were asked for (clock_seconds) */
    uint64_t sequence;   /* images published before it and it */
} view_frame;

typedef struct view_render view_render;

/* Starts rendering scene s (kept, not copied: it must outlive the render) with opts through
 * backend, as `first` says; NULL (logged) on failure. */
view_render *view_render_start(const scene *s, const render_opts *opts, backend_choice backend,
                               view_settings first);
/* Starts over with new settings; the generation their images will carry. Never fails. */
uint64_t view_render_change(view_render *v, view_settings set);
/* When an image newer than f's (by sequence) was published, moves it and its part into f
 * (freeing f's) and returns true; false when there is none. */
bool view_render_take(view_render *v, view_frame *f);
/* Whether a render failed (logged): the view cannot go on. */
bool view_render_failed(view_render *v);
/* Frees a frame's image and part; safe on a zeroed frame. */
void view_frame_free(view_frame *f);
/* Stops the render (abandoning its pass) and frees v; safe on NULL. */
void view_render_stop(view_render *v);

#endif
