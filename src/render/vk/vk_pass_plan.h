/* vk_pass_plan.h: how the Vulkan back end cuts a host pass (whole chunks of samples of every
 * pixel of the region) into dispatches and submissions: the samples a dispatch takes, the tile it
 * covers, and the steps (dispatch pass, tile) in order with what each pushes to trace.comp. No
 * Vulkan here, so that tests/test_vk_plan.c can check that the steps take every sample of every
 * pixel once, in order, opening and closing each chunk once. */
#ifndef TRAZADOR_VK_PASS_PLAN_H
#define TRAZADOR_VK_PASS_PLAN_H

#include <stdbool.h>
#include <stdint.h>

#include "render/chunk_tree.h"
#include "render/part.h"

/* Loop passes (about one ray/primitive test each) one dispatch may cost, so that a dispatch
 * stays well under a second on a GPU (and about a third of one on lavapipe, worst case, for a
 * stoppable render); samples per dispatch are chosen to fit. */
#define PASS_DISPATCH_BUDGET (UINT64_C(1) << 29)

/* Where chunk k of a host pass goes on the stack (chunk_stack_push). */
typedef struct chunk_slot {
    uint32_t top, merges;
} chunk_slot;

typedef struct pass_plan {
    uint32_t width, height; /* the region */
    uint32_t region_x0, region_y0;
    uint32_t spp;          /* samples per pixel of the whole render */
    uint32_t per_dispatch; /* samples one invocation renders, in order, within a chunk */
    uint32_t group;        /* whole chunks a dispatch spans when per_dispatch is a chunk */
    /* A dispatch's pixels: powers of two of at most TZ_BAND_ROWS, so that tiles pave each band
     * of TZ_BAND_ROWS rows. Smaller than a band only when a stop must not wait for a dispatch. */
    uint32_t tile_width, tile_height;
    uint64_t steps_per_submit; /* steps a submission runs at most */
    uint32_t depth;            /* stack blocks a pixel has room for */
    uint32_t noise_threshold;  /* gpu_pass.noise_threshold: the float's bits, 0 when off */
    /* The host pass being run: chunks first_chunk to first_chunk + chunks - 1, ending at sample
     * sample_end, each placed by slot[k]. */
    uint32_t first_chunk, chunks, sample_end;
    const chunk_slot *slot;
} pass_plan;

/* One step of a host pass: a dispatch over one tile for some samples of one or more chunks. */
typedef struct pass_step {
    uint32_t x0, y0, width, height; /* the tile, in pixels of the region */
    uint32_t band_y0;               /* the first row of the band the tile lies in */
    uint32_t chunk;                 /* the host pass's chunk the samples start in (slot index) */
    uint32_t spans;                 /* chunks the samples span */
    uint32_t first_sample, sample_count;
    uint32_t chunk_flags; /* TZ_CHUNK_OPEN, TZ_CHUNK_CLOSE */
    bool pass_begins;     /* the first tile of its dispatch pass: a barrier comes before it */
} pass_step;

/* Plans the dispatches of part `meta` whose samples cost at most sample_iterations loop passes
 * each: loop_fit is the most passes one invocation may run (0: no limit), and stoppable asks for
 * dispatches and submissions short enough that a stop between them comes within a fraction of a
 * second. The host pass fields are left for the caller. */
pass_plan pass_plan_make(const part_meta *meta, uint64_t sample_iterations, uint64_t loop_fit,
                         bool stoppable);
/* Tiles of the region. */
uint32_t pass_plan_tiles(const pass_plan *plan);
/* Steps of the host pass: its dispatch passes times the tiles. */
uint64_t pass_plan_steps(const pass_plan *plan);
/* Step `step` of the host pass into *out; false when it has no samples (the render's last chunk
 * is short), which is then skipped. */
bool pass_plan_step(const pass_plan *plan, uint64_t step, pass_step *out);
/* The workgroup stride of a dispatch of `groups` workgroups (gpu_pass.group_stride). */
uint32_t pass_plan_workgroup_stride(uint32_t groups);
/* The most blocks the stack holds on its way from `from` to chunk end, at least 1. */
uint32_t pass_plan_stack_depth(const chunk_stack *from, uint32_t end);

#endif
