/* view_window.c: the window of `trazador view` through SDL2 (sdl_lib.h): a streaming RGB24
 * texture the size of the image, copied one pixel per pixel, so the screen holds the very bytes
 * the PNG writer would. */
#include "cli/view_window.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/sdl_lib.h"
#include "util/log.h"

static const sdl_lib *sdl;

bool view_window_has_display(char *why, size_t why_size) {
    /* Without either variable SDL finds no screen (and its Wayland attempt prints a warning of
     * its own). */
    if (getenv("DISPLAY") || getenv("WAYLAND_DISPLAY") || getenv("SDL_VIDEODRIVER")) return true;
    snprintf(why, why_size, "no display to open a window on (DISPLAY is not set)");
    return false;
}

bool view_window_open(view_window *w, int width, int height, const char *title, char *why,
                      size_t why_size) {
    *w = (view_window){.width = width, .height = height};
    if (!view_window_has_display(why, why_size)) return false;
    sdl = sdl_lib_open(why, why_size);
    if (!sdl) return false;
    /* No scaling filter may blend a pixel with its neighbours, and the view must not stop
     * a compositor's effects or keep the screen saver away. */
    sdl->set_hint(SDL_HINT_RENDER_SCALE_QUALITY, "nearest");
    sdl->set_hint(SDL_HINT_VIDEO_X11_NET_WM_BYPASS_COMPOSITOR, "0");
    sdl->set_hint(SDL_HINT_VIDEO_ALLOW_SCREENSAVER, "1");
    /* Only the drivers of a screen, Wayland where it is named: SDL would fall back to an
     * offscreen one, and its Wayland attempt prints a warning of its own. SDL_VIDEODRIVER in the
     * environment still overrides this. */
    sdl->set_hint(SDL_HINT_VIDEODRIVER, getenv("WAYLAND_DISPLAY") ? "x11,wayland" : "x11");
    if (sdl->init(SDL_INIT_VIDEO) != 0) {
        const char *display = getenv("DISPLAY");
        if (!display) display = getenv("WAYLAND_DISPLAY");
        snprintf(why, why_size, "cannot open the display '%s' (SDL: %s)", display ? display : "",
                 sdl->get_error());
        return false;
    }
    /* SDL falls back to drivers that show nothing where it finds no display. */
    const char *driver = sdl->get_current_video_driver();
    if (!driver || !strcmp(driver, "offscreen") || !strcmp(driver, "dummy") ||
        !strcmp(driver, "evdev")) {
        snprintf(why, why_size, "no display to open a window on (SDL found only its '%s' driver)",
                 driver ? driver : "none");
        sdl->quit();
        return false;
    }
    /* Hidden until its renderer exists: an OpenGL renderer makes SDL destroy the window and
     * create another, and a script (tests/view_test.sh) could find the first one gone. */
    w->window = sdl->create_window(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, width,
                                   height, SDL_WINDOW_HIDDEN);
    if (w->window) w->renderer = sdl->create_renderer(w->window, -1, 0);
    if (w->renderer)
        w->texture = sdl->create_texture(w->renderer, SDL_PIXELFORMAT_RGB24,
                                         SDL_TEXTUREACCESS_STREAMING, width, height);
    if (!w->texture) {
        snprintf(why, why_size, "cannot open a %d x %d window (SDL: %s)", width, height,
                 sdl->get_error());
        view_window_close(w);
        sdl->quit();
        return false;
    }
    /* A black window at once, rather than what the screen held: the first present also sets
     * the renderer up (73 ms of OpenGL on llvmpipe), which the first image need not wait for. */
    sdl->show_window(w->window);
    sdl->render_clear(w->renderer);
    sdl->render_present(w->renderer);
    return true;
}

bool view_window_show(view_window *w, const uint8_t *rgb) {
    if (sdl->update_texture(w->texture, NULL, rgb, 3 * w->width) != 0) {
        log_error("view: cannot update the window's texture (SDL: %s)", sdl->get_error());
        return false;
    }
    view_window_redraw(w);
    return true;
}

void view_window_redraw(view_window *w) {
    sdl->render_copy(w->renderer, w->texture, NULL, NULL);
    sdl->render_present(w->renderer);
}

void view_window_title(view_window *w, const char *title) {
    sdl->set_window_title(w->window, title);
}

/* The event of a key, NONE for keys the view has no use for. */
static view_event key_event(const SDL_KeyboardEvent *k) {
    SDL_Keycode code = k->keysym.sym;
    if (code == SDLK_ESCAPE) return (view_event){.kind = VIEW_EVENT_QUIT};
    /* The keypad's and the shifted '=' count as '+' too: '+' needs Shift on most layouts. */
    if (code == SDLK_KP_PLUS || code == SDLK_EQUALS) code = '+';
    if (code == SDLK_KP_MINUS) code = '-';
    if (code == 'c' || code == 's' || code == 'm' || code == '+' || code == '-')
        return (view_event){.kind = VIEW_EVENT_KEY, .key = (char)code};
    return (view_event){.kind = VIEW_EVENT_NONE};
}

view_event view_window_next(view_window *w, int timeout_ms) {
    (void)w;
    SDL_Event e;
    if (!sdl->wait_event_timeout(&e, timeout_ms)) return (view_event){.kind = VIEW_EVENT_NONE};
    switch (e.type) {
        case SDL_QUIT:
            return (view_event){.kind = VIEW_EVENT_QUIT};
        case SDL_KEYDOWN:
            return key_event(&e.key);
        case SDL_MOUSEBUTTONDOWN:
            return (view_event){.kind = VIEW_EVENT_PRESS,
                                .x = e.button.x,
                                .y = e.button.y,
                                .button = e.button.button == SDL_BUTTON_LEFT ? 0 : 1};
        case SDL_MOUSEMOTION:
            return (view_event){.kind = VIEW_EVENT_MOVE, .x = e.motion.x, .y = e.motion.y};
        case SDL_MOUSEBUTTONUP:
            return (view_event){.kind = VIEW_EVENT_RELEASE, .x = e.button.x, .y = e.button.y};
        case SDL_MOUSEWHEEL:
            return (view_event){
                .kind = VIEW_EVENT_WHEEL,
                .wheel = e.wheel.direction == SDL_MOUSEWHEEL_FLIPPED ? -e.wheel.y : e.wheel.y};
        case SDL_WINDOWEVENT:
            if (e.window.event == SDL_WINDOWEVENT_EXPOSED ||
                e.window.event == SDL_WINDOWEVENT_SIZE_CHANGED)
                return (view_event){.kind = VIEW_EVENT_EXPOSED};
            return (view_event){.kind = VIEW_EVENT_NONE};
        default:
            return (view_event){.kind = VIEW_EVENT_NONE};
    }
}

void view_window_close(view_window *w) {
    /* No SDL_Quit: it unloads the X11 and OpenGL libraries SDL opened, and LeakSanitizer then
     * reports what they keep from modules no suppression can name (tests/lsan.supp); the
     * process ends next, which closes the display's connection. */
    if (sdl) {
        if (w->texture) sdl->destroy_texture(w->texture);
        if (w->renderer) sdl->destroy_renderer(w->renderer);
        if (w->window) sdl->destroy_window(w->window);
    }
    *w = (view_window){0};
}
