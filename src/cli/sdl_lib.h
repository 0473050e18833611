/* sdl_lib.h: the functions of SDL2 that `trazador view` calls, from the library opened on first
 * use (sdl_lib.c): linked, SDL2 and the fifty libraries it needs (X11, Wayland, PulseAudio, ...)
 * would load with every trazador process, and a machine without them could not render at all. */
#ifndef TRAZADOR_SDL_LIB_H
#define TRAZADOR_SDL_LIB_H

#include <SDL.h>
#include <stddef.h>

/* Each member has the type of a pointer to the SDL function it is named after. */
typedef struct sdl_lib {
    __typeof__(&SDL_SetHint) set_hint;
    __typeof__(&SDL_Init) init;
    __typeof__(&SDL_Quit) quit;
    __typeof__(&SDL_GetError) get_error;
    __typeof__(&SDL_GetCurrentVideoDriver) get_current_video_driver;
    __typeof__(&SDL_CreateWindow) create_window;
    __typeof__(&SDL_DestroyWindow) destroy_window;
    __typeof__(&SDL_SetWindowTitle) set_window_title;
    __typeof__(&SDL_ShowWindow) show_window;
    __typeof__(&SDL_CreateRenderer) create_renderer;
    __typeof__(&SDL_DestroyRenderer) destroy_renderer;
    __typeof__(&SDL_CreateTexture) create_texture;
    __typeof__(&SDL_DestroyTexture) destroy_texture;
    __typeof__(&SDL_UpdateTexture) update_texture;
    __typeof__(&SDL_RenderClear) render_clear;
    __typeof__(&SDL_RenderCopy) render_copy;
    __typeof__(&SDL_RenderPresent) render_present;
    __typeof__(&SDL_WaitEventTimeout) wait_event_timeout;
    __typeof__(&SDL_PollEvent) poll_event;
} sdl_lib;

/* SDL's functions, the library opened once a process (thread-safe); NULL when it cannot be, with
 * why in error. */
const sdl_lib *sdl_lib_open(char *error, size_t error_size);

#endif
