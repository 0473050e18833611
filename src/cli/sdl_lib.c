/* sdl_lib.c: opens SDL2 (TRAZADOR_SDL_SONAME, the library the build's headers belong to) and
 * looks up the functions of sdl_lib.h. */
#include "cli/sdl_lib.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>

#include "util/run_time_lib.h"

static sdl_lib lib;
static bool opened;
static char why[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void open_library(void) {
    const run_time_symbol symbols[] = {
        {"SDL_SetHint", &lib.set_hint},
        {"SDL_Init", &lib.init},
        {"SDL_Quit", &lib.quit},
        {"SDL_GetError", &lib.get_error},
        {"SDL_GetCurrentVideoDriver", &lib.get_current_video_driver},
        {"SDL_CreateWindow", &lib.create_window},
        {"SDL_DestroyWindow", &lib.destroy_window},
        {"SDL_SetWindowTitle", &lib.set_window_title},
        {"SDL_ShowWindow", &lib.show_window},
        {"SDL_CreateRenderer", &lib.create_renderer},
        {"SDL_DestroyRenderer", &lib.destroy_renderer},
        {"SDL_CreateTexture", &lib.create_texture},
        {"SDL_DestroyTexture", &lib.destroy_texture},
        {"SDL_UpdateTexture", &lib.update_texture},
        {"SDL_RenderClear", &lib.render_clear},
        {"SDL_RenderCopy", &lib.render_copy},
        {"SDL_RenderPresent", &lib.render_present},
        {"SDL_WaitEventTimeout", &lib.wait_event_timeout},
        {"SDL_PollEvent", &lib.poll_event},
    };
    opened = run_time_lib_open(TRAZADOR_SDL_SONAME, "SDL2 (Debian: libsdl2-2.0-0)", symbols,
                               (int)(sizeof symbols / sizeof *symbols), why, sizeof why);
}

const sdl_lib *sdl_lib_open(char *error, size_t error_size) {
    pthread_once(&once, open_library);
    if (!opened) snprintf(error, error_size, "%s", why);
    return opened ? &lib : NULL;
}
