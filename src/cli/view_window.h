/* view_window.h: the window of `trazador view` (SDL2, opened at run time): an image shown one
 * pixel per pixel, its title, and the mouse and keys as the few events the view needs. */
#ifndef TRAZADOR_VIEW_WINDOW_H
#define TRAZADOR_VIEW_WINDOW_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

typedef enum view_event_kind {
    VIEW_EVENT_NONE,
    VIEW_EVENT_QUIT,    /* Escape or the window closed */
    VIEW_EVENT_KEY,     /* key: a printable character ('c', 's', 'm', '+', '-') */
    VIEW_EVENT_PRESS,   /* a drag begins at x, y: button 0 orbits, 1 pans */
    VIEW_EVENT_MOVE,    /* the mouse at x, y (a drag goes on) */
    VIEW_EVENT_RELEASE, /* the drag ends */
    VIEW_EVENT_WHEEL,   /* wheel: steps away from the user (positive: zoom in) */
    VIEW_EVENT_EXPOSED  /* the window must be drawn again */
} view_event_kind;

typedef struct view_event {
    view_event_kind kind;
    int x, y, button, wheel;
    char key;
} view_event;

typedef struct view_window {
    void *window, *renderer, *texture; /* SDL's */
    int width, height;
} view_window;

/* Whether the environment names a display (DISPLAY, WAYLAND_DISPLAY or SDL_VIDEODRIVER), which
 * view_window_open needs; false with why. It may still fail to open there. */
bool view_window_has_display(char *why, size_t why_size);
/* Opens a window of width x height pixels titled `title`; false with why (one line: no
 * display, no SDL2) when it cannot. */
bool view_window_open(view_window *w, int width, int height, const char *title, char *why,
                      size_t why_size);
/* Shows rgb (3 bytes a pixel, rows top to bottom) one pixel per pixel; false (logged) on
 * failure. */
bool view_window_show(view_window *w, const uint8_t *rgb);
/* Shows the last image again (after an expose); never fails. */
void view_window_redraw(view_window *w);
/* Sets the title; never fails. */
void view_window_title(view_window *w, const char *title);
/* The next event, waiting up to `timeout_ms` for one; VIEW_EVENT_NONE when none came. */
view_event view_window_next(view_window *w, int timeout_ms);
/* Closes the window (SDL stays open until the process ends); safe on a zeroed one. */
void view_window_close(view_window *w);

#endif
