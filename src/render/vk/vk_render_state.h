/* vk_render_state.h: what one Vulkan render holds on the device (the packed scene's buffers,
 * the sums, compensations and stacks of the part, their staging, the snapshot a stop reads) and
 * how the part's state moves in and out of it; render_vk.c records the passes between. */
#ifndef TRAZADOR_VK_RENDER_STATE_H
#define TRAZADOR_VK_RENDER_STATE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "render/part.h"
#include "render/scene_pack.h"
#include "render/vk/vk_accel.h"
#include "render/vk/vk_bindings.h"
#include "render/vk/vk_context.h"
#include "render/vk/vk_pass_plan.h"
#include "render/vk/vk_strategy.h"

typedef struct vk_render {
    vk_context ctx;
    vk_buffer buffers[VK_BINDINGS]; /* binding k's buffer, as vk_bindings.c's table makes it */
    uint32_t rows;                  /* of the region, padded to whole bands */
    vk_buffer upload;               /* staging for the inputs when device memory is not mapped */
    vk_buffer state;                /* staging for a resumed part's counts and stacks, likewise */
    vk_buffer readback; /* staging: the counters at 0, the sums at 16, then the stacks */
    /* A stoppable render's sums and stacks as the host pass in flight began, laid out as in
     * readback: a pass abandoned for a stop leaves the part as it was. */
    vk_buffer snapshot;
    uint64_t stop_steps; /* steps a stoppable render's submission runs: 1, then measured to fit */
    vk_accel accel;      /* the ray query walk's acceleration structure */
    vk_kernel kernel;
    VkFence fence;
    VkCommandBuffer cmd;
} vk_render;
_Static_assert(TZ_COUNTER_WORDS * sizeof(uint32_t) <= 16,
               "the counters fit before the accumulation");

/* Creates the buffers and writes the packed scene into them (mapped, or through `upload`): the
 * BVH's nodes, binary or wide or both, as the strategy's walks read them (one zeroed node for a
 * layout no walk reads). */
bool vk_render_create_buffers(vk_render *r, const packed_scene *p, const vk_strategy *st, int width,
                              int height, uint32_t depth, bool stoppable);
/* Writes the part's counts and stacks (a resumed part) where the shader reads them: into the
 * mapped buffers, or into `state` for record_setup to copy; false (logged) on out of memory. */
bool vk_render_load_part(vk_render *r, const part *p, uint32_t depth);
/* Copies the staged inputs into place (when staged), and the resumed part's state likewise, or
 * zeroes the accumulation buffers of a new part. */
void vk_render_record_setup(vk_render *r, bool resumed, size_t pixels);
/* Copies the sums and stacks as they are into the snapshot, in the order of the commands. */
void vk_render_record_snapshot(vk_render *r, const pass_plan *plan);
/* Makes the counter (and with `final` the sums and stacks) readable by the host after the
 * fence. */
void vk_render_record_readback(vk_render *r, const pass_plan *plan, bool final);
/* Brings p up to date from the device: its sums and stacks as they are (live_state), or with
 * `abandoned` as the pass in flight began (the snapshot); false (logged) on failure. */
bool vk_render_sync_part(vk_render *r, const pass_plan *plan, bool abandoned,
                         const chunk_stack *shape, uint32_t done, uint64_t *nonfinite, part *p);
/* Waits for the device and frees what the render created on it (not the context). */
void vk_render_destroy(vk_render *r);

#endif
