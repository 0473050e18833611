/* vk_pass_plan.c: the dispatches and submissions of the Vulkan back end's host passes (see
 * vk_pass_plan.h). */
#include "render/vk/vk_pass_plan.h"

#include "shared_layout.h"

/* Loop passes one submission may cost: a few seconds on lavapipe, the granularity of the progress
 * line and of the non-finite counter read-back. */
#define SUBMIT_BUDGET (UINT64_C(1) << 31)
/* Pixels an image is charged for at least: a smaller one leaves the device's lanes idle, and its
 * few invocations take as long as this many would (docs/PERF.md, "Vulkan pass planning"). */
#define MIN_CHARGED_PIXELS 1024u

/* A dispatch has at most (TZ_BAND_ROWS / 8) x (TZ_BAND_ROWS / 4) workgroups. */
_Static_assert((uint64_t)(TZ_BAND_ROWS / TZ_GROUP_X) * (TZ_BAND_ROWS / TZ_GROUP_Y) *
                       (TZ_BAND_ROWS / TZ_GROUP_X) * (TZ_BAND_ROWS / TZ_GROUP_Y) <=
                   UINT32_MAX,
               "trace.comp's workgroup n * stride stays within 32 bits");

/* The smallest power of two from `least` to TZ_BAND_ROWS holding n. */
static uint32_t power_of_two_over(uint32_t n, uint32_t least) {
    uint32_t p = least;
    while (p < n && p < TZ_BAND_ROWS) p *= 2u;
    return p;
}

/* A stoppable render's tile: halved (the longer side first) from the region's size until a
 * dispatch of one sample a pixel fits the budget, or a workgroup is left. */
static void shrink_tile(pass_plan *plan, uint64_t sample_iterations) {
    plan->tile_width = power_of_two_over(plan->width, TZ_GROUP_X);
    plan->tile_height = power_of_two_over(plan->height, TZ_GROUP_Y);
    while ((uint64_t)plan->tile_width * plan->tile_height * sample_iterations >
           PASS_DISPATCH_BUDGET) {
        bool wide = plan->tile_width / TZ_GROUP_X >= plan->tile_height / TZ_GROUP_Y;
        if (wide && plan->tile_width > TZ_GROUP_X)
            plan->tile_width /= 2u;
        else if (plan->tile_height > TZ_GROUP_Y)
            plan->tile_height /= 2u;
        else
            break;
    }
}

pass_plan pass_plan_make(const part_meta *meta, uint64_t sample_iterations, uint64_t loop_fit,
                         bool stoppable) {
    pass_plan plan = {.width = (uint32_t)(meta->x1 - meta->x0),
                      .height = (uint32_t)(meta->y1 - meta->y0),
                      .region_x0 = (uint32_t)meta->x0,
                      .region_y0 = (uint32_t)meta->y0,
                      .spp = meta->spp,
                      .tile_width = TZ_BAND_ROWS,
                      .tile_height = TZ_BAND_ROWS};
    if (sample_iterations == 0) sample_iterations = 1;
    if (stoppable) shrink_tile(&plan, sample_iterations);
    uint64_t tile_pixels = (uint64_t)plan.tile_width * plan.tile_height;
    uint64_t per_dispatch = PASS_DISPATCH_BUDGET / (tile_pixels * sample_iterations);
    if (loop_fit) {
        uint64_t fit = (loop_fit - 1u) / sample_iterations;
        if (fit < per_dispatch) per_dispatch = fit;
    }
    /* A pass over the whole image stays within a submission, so that big images show progress
     * (docs/PERF.md, "Vulkan pass planning"). */
    uint64_t pixels = (uint64_t)plan.width * plan.height;
    if (pixels < MIN_CHARGED_PIXELS) pixels = MIN_CHARGED_PIXELS;
    uint64_t whole = SUBMIT_BUDGET / pixels / sample_iterations;
    if (whole < per_dispatch) per_dispatch = whole;
    /* Whole chunks, up to TZ_PASS_CHUNKS, where a dispatch has room for more than one. */
    uint64_t group = per_dispatch / TZ_CHUNK_SAMPLES;
    plan.group = group > TZ_PASS_CHUNKS ? TZ_PASS_CHUNKS : group > 1u ? (uint32_t)group : 1u;
    if (per_dispatch > TZ_CHUNK_SAMPLES) per_dispatch = TZ_CHUNK_SAMPLES;
    if (per_dispatch > plan.spp) per_dispatch = plan.spp;
    plan.per_dispatch = per_dispatch ? (uint32_t)per_dispatch : 1u;
    uint64_t cost; /* saturated: 16384^2 pixels of 4096 lights, 2^24 spheres, --no-bvh */
    uint64_t charged = stoppable ? tile_pixels : pixels; /* a step, or a dispatch pass */
    if (__builtin_mul_overflow(charged * plan.per_dispatch * plan.group, sample_iterations, &cost))
        cost = UINT64_MAX;
    uint64_t per_submit = (stoppable ? PASS_DISPATCH_BUDGET : SUBMIT_BUDGET) / cost;
    if (per_submit == 0) per_submit = 1;
    plan.steps_per_submit = stoppable ? per_submit : per_submit * pass_plan_tiles(&plan);
    return plan;
}

uint32_t pass_plan_tiles(const pass_plan *plan) {
    return ((plan->width + plan->tile_width - 1u) / plan->tile_width) *
           ((plan->height + plan->tile_height - 1u) / plan->tile_height);
}

/* Dispatch passes a chunk takes. */
static uint32_t subpasses(const pass_plan *plan) {
    return (TZ_CHUNK_SAMPLES + plan->per_dispatch - 1u) / plan->per_dispatch;
}

uint64_t pass_plan_steps(const pass_plan *plan) {
    /* Groups of whole chunks, or each chunk in subpasses. */
    uint64_t passes = plan->group > 1u ? (plan->chunks + plan->group - 1u) / plan->group
                                       : (uint64_t)plan->chunks * subpasses(plan);
    return passes * pass_plan_tiles(plan);
}

/* Dispatch pass d of the host pass is pass d % subpasses of chunk first_chunk + d / subpasses,
 * or with groups chunks d * group on; the render's last chunk may need fewer. */
bool pass_plan_step(const pass_plan *plan, uint64_t step, pass_step *out) {
    uint32_t tiles = pass_plan_tiles(plan);
    uint32_t tiles_x = (plan->width + plan->tile_width - 1u) / plan->tile_width;
    uint32_t subs = subpasses(plan);
    uint32_t pass = (uint32_t)(step / tiles), tile = (uint32_t)(step % tiles);
    uint32_t group = plan->group > 1u ? plan->group : 1u;
    uint32_t k = plan->group > 1u ? pass * group : pass / subs;
    uint32_t sub = plan->group > 1u ? 0u : pass % subs;
    uint32_t spans = plan->chunks - k < group ? plan->chunks - k : group;
    uint32_t chunk = plan->first_chunk + k, last_chunk = chunk + spans - 1u;
    uint32_t chunk_begin = last_chunk * TZ_CHUNK_SAMPLES;
    uint32_t chunk_end =
        plan->spp - chunk_begin < TZ_CHUNK_SAMPLES ? plan->spp : chunk_begin + TZ_CHUNK_SAMPLES;
    uint32_t sample = chunk * TZ_CHUNK_SAMPLES + sub * plan->per_dispatch;
    if (sample >= chunk_end) return false;
    uint32_t count = spans > 1u                                ? chunk_end - sample
                     : chunk_end - sample < plan->per_dispatch ? chunk_end - sample
                                                               : plan->per_dispatch;
    uint32_t x0 = tile % tiles_x * plan->tile_width, y0 = tile / tiles_x * plan->tile_height;
    *out = (pass_step){
        .x0 = x0,
        .y0 = y0,
        .width = plan->width - x0 < plan->tile_width ? plan->width - x0 : plan->tile_width,
        .height = plan->height - y0 < plan->tile_height ? plan->height - y0 : plan->tile_height,
        .band_y0 = y0 - y0 % TZ_BAND_ROWS,
        .chunk = k,
        .spans = spans,
        .first_sample = sample,
        .sample_count = count,
        .chunk_flags =
            (sub == 0u ? TZ_CHUNK_OPEN : 0u) | (sample + count == chunk_end ? TZ_CHUNK_CLOSE : 0u),
        .pass_begins = tile == 0u};
    return true;
}

/* Coprime with the count, so every block is rendered once, and near groups / golden ratio, so
 * that any run of consecutive workgroups spreads evenly over the tile (a Weyl sequence). */
uint32_t pass_plan_workgroup_stride(uint32_t groups) {
    uint32_t stride = (uint32_t)(groups * 0.6180339887 + 0.5);
    for (;; stride++) {
        uint32_t a = groups, b = stride;
        while (b) {
            uint32_t t = a % b;
            a = b;
            b = t;
        }
        if (a == 1u) return stride;
    }
}

uint32_t pass_plan_stack_depth(const chunk_stack *from, uint32_t end) {
    chunk_stack st = *from;
    uint32_t depth = st.count > 0 ? (uint32_t)st.count : 1u;
    for (uint32_t k = st.end; k < end; k++) {
        chunk_stack_push(&st, (chunk_block){0, k});
        if ((uint32_t)st.count > depth) depth = (uint32_t)st.count;
    }
    return depth;
}
