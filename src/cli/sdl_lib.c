/* sdl_lib.c: opens SDL2 (TRAZADOR_SDL_SONAME, the library the build's headers belong to) and
 * looks up the functions of sdl_lib.h. */
#include "cli/sdl_lib.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

static sdl_lib lib;
static bool opened;
static char why[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

/* Looks function `name` up in the library into *slot; false (why set) when it lacks it. */
static bool find(void *handle, const char *name, void *slot) {
    void *f = dlsym(handle, name);
    if (!f) {
        snprintf(why, sizeof why, "%s has no %s", TRAZADOR_SDL_SONAME, name);
        return false;
    }
    memcpy(slot, &f, sizeof f); /* a data pointer's bits as a function pointer's, as dlsym means */
    return true;
}

static void open_library(void) {
    void *handle = dlopen(TRAZADOR_SDL_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char *e = dlerror();
        snprintf(why, sizeof why, "cannot open SDL2 (Debian: libsdl2-2.0-0): %s",
                 e ? e : TRAZADOR_SDL_SONAME);
        return;
    }
    opened = find(handle, "SDL_SetHint", &lib.set_hint) && find(handle, "SDL_Init", &lib.init) &&
             find(handle, "SDL_Quit", &lib.quit) && find(handle, "SDL_GetError", &lib.get_error) &&
             find(handle, "SDL_GetCurrentVideoDriver", &lib.get_current_video_driver) &&
             find(handle, "SDL_CreateWindow", &lib.create_window) &&
             find(handle, "SDL_DestroyWindow", &lib.destroy_window) &&
             find(handle, "SDL_SetWindowTitle", &lib.set_window_title) &&
             find(handle, "SDL_ShowWindow", &lib.show_window) &&
             find(handle, "SDL_CreateRenderer", &lib.create_renderer) &&
             find(handle, "SDL_DestroyRenderer", &lib.destroy_renderer) &&
             find(handle, "SDL_CreateTexture", &lib.create_texture) &&
             find(handle, "SDL_DestroyTexture", &lib.destroy_texture) &&
             find(handle, "SDL_UpdateTexture", &lib.update_texture) &&
             find(handle, "SDL_RenderClear", &lib.render_clear) &&
             find(handle, "SDL_RenderCopy", &lib.render_copy) &&
             find(handle, "SDL_RenderPresent", &lib.render_present) &&
             find(handle, "SDL_WaitEventTimeout", &lib.wait_event_timeout) &&
             find(handle, "SDL_PollEvent", &lib.poll_event);
}

const sdl_lib *sdl_lib_open(char *error, size_t error_size) {
    pthread_once(&once, open_library);
    if (!opened) snprintf(error, error_size, "%s", why);
    return opened ? &lib : NULL;
}
