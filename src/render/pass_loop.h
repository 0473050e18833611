/* pass_loop.h: the loop both back ends run over a part's passes (render_control's protocol):
 * ask the control for the next pass, run it, bring the part up to date when the control asks
 * or the render ends, and after a pass abandoned for a stop, hand the part as that pass began
 * and end. A back end supplies how it runs one pass and how it syncs the part. */
#ifndef TRAZADOR_PASS_LOOP_H
#define TRAZADOR_PASS_LOOP_H

#include <stdbool.h>
#include <stdint.h>

#include "render/part.h"
#include "render/render.h"

/* How a pass ended: done; abandoned for a stop (before it changed anything, or after); failed
 * (logged, or a refusal the back end keeps). */
typedef enum pass_result { PASS_DONE, PASS_NOT_BEGUN, PASS_ABANDONED, PASS_FAILED } pass_result;

typedef struct pass_backend {
    /* Renders chunks first to first + chunks - 1 of the part. */
    pass_result (*run)(void *user, part *p, uint32_t first, uint32_t chunks);
    /* Brings p up to chunk `done` (the back end may keep its sums elsewhere), or after a pass that
     * ended as `result` (not begun, abandoned) as that pass began; false (logged) on failure. */
    bool (*sync)(void *user, part *p, uint32_t done, pass_result result);
    void *user;
} pass_backend;

/* Runs the passes of p up to chunk end_chunk as opts->control sets them (all at once without
 * one); false on a failed pass or sync, or when the control fails. */
bool pass_loop_run(const render_opts *opts, part *p, uint32_t end_chunk, const char *name,
                   const pass_backend *be);

#endif
