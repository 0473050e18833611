/* test_vk_plan.c: the Vulkan back end's pass planning (src/render/vk/vk_pass_plan.c), without a
 * device: for regions, sample counts, per-sample costs, loop limits and stoppable renders, the
 * steps of every host pass give every pixel each of its samples once and in order, open and
 * close each chunk once, keep each tile inside one band of TZ_BAND_ROWS rows, and keep a
 * dispatch within the loop limit and (stoppable) within PASS_DISPATCH_BUDGET; workgroup strides
 * are coprime with the workgroup count; the stack depth is the chunk tree's. */
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "render/vk/vk_pass_plan.h"
#include "shared_layout.h"

/* CHECK, and on failure returns `value`. */
#define CHECK_RETURN(cond, value, ...) \
    do {                               \
        bool held_ = (cond);           \
        CHECK(held_, __VA_ARGS__);     \
        if (!held_) return value;      \
    } while (0)

/* Every step of the host pass of chunks [first, first + chunks) over the region; next[] holds
 * each pixel's next sample. False (checked) at the first step that breaks a rule. */
static bool check_host_pass(pass_plan *plan, uint32_t first, uint32_t chunks, uint64_t iterations,
                            uint64_t loop_fit, bool stoppable, uint32_t *next) {
    chunk_slot slots[64] = {{0}};
    plan->first_chunk = first;
    plan->chunks = chunks;
    plan->slot = slots;
    uint64_t end_sample = (uint64_t)(first + chunks) * TZ_CHUNK_SAMPLES;
    plan->sample_end = end_sample < plan->spp ? (uint32_t)end_sample : plan->spp;
    uint64_t steps = pass_plan_steps(plan);
    for (uint64_t step = 0; step < steps; step++) {
        pass_step at;
        if (!pass_plan_step(plan, step, &at)) continue;
        uint32_t s0 = at.first_sample, n = at.sample_count;
        CHECK_RETURN(
            n >= 1 && at.spans >= 1 && at.spans <= TZ_PASS_CHUNKS && at.chunk + at.spans <= chunks,
            false, "step %llu: %u samples over %u chunks from chunk %u of %u",
            (unsigned long long)step, n, at.spans, at.chunk, chunks);
        CHECK_RETURN(s0 / TZ_CHUNK_SAMPLES == first + at.chunk &&
                         (s0 + n - 1u) / TZ_CHUNK_SAMPLES == first + at.chunk + at.spans - 1u,
                     false, "step %llu: samples %u..%u are not chunks %u..%u",
                     (unsigned long long)step, s0, s0 + n - 1u, first + at.chunk,
                     first + at.chunk + at.spans - 1u);
        uint32_t last_chunk_end = (first + at.chunk + at.spans) * TZ_CHUNK_SAMPLES;
        if (last_chunk_end > plan->spp) last_chunk_end = plan->spp;
        bool opens = (at.chunk_flags & TZ_CHUNK_OPEN) != 0;
        bool closes = (at.chunk_flags & TZ_CHUNK_CLOSE) != 0;
        CHECK_RETURN(opens == (s0 % TZ_CHUNK_SAMPLES == 0) && closes == (s0 + n == last_chunk_end),
                     false, "step %llu: samples %u..%u flagged open %d close %d",
                     (unsigned long long)step, s0, s0 + n - 1u, opens, closes);
        CHECK_RETURN(
            at.x0 % plan->tile_width == 0 && at.y0 % plan->tile_height == 0 && at.width >= 1 &&
                at.width <= plan->tile_width && at.height >= 1 && at.height <= plan->tile_height &&
                at.x0 + at.width <= plan->width && at.y0 + at.height <= plan->height,
            false, "step %llu: tile %u,%u of %u x %u in a %u x %u region", (unsigned long long)step,
            at.x0, at.y0, at.width, at.height, plan->width, plan->height);
        CHECK_RETURN(at.band_y0 % TZ_BAND_ROWS == 0 && at.band_y0 <= at.y0 &&
                         at.y0 + at.height <= at.band_y0 + TZ_BAND_ROWS,
                     false, "step %llu: rows %u..%u outside the band from %u",
                     (unsigned long long)step, at.y0, at.y0 + at.height - 1u, at.band_y0);
        if (loop_fit && iterations < loop_fit)
            CHECK_RETURN(n * iterations <= loop_fit - 1u, false,
                         "step %llu: %u samples of %llu passes past the loop limit %llu",
                         (unsigned long long)step, n, (unsigned long long)iterations,
                         (unsigned long long)loop_fit);
        bool smallest = n == 1 && plan->tile_width == TZ_GROUP_X && plan->tile_height == TZ_GROUP_Y;
        if (stoppable && !smallest)
            CHECK_RETURN((uint64_t)at.width * at.height * n * iterations <= PASS_DISPATCH_BUDGET,
                         false, "step %llu: a stoppable dispatch of %u x %u pixels x %u samples",
                         (unsigned long long)step, at.width, at.height, n);
        for (uint32_t y = at.y0; y < at.y0 + at.height; y++)
            for (uint32_t x = at.x0; x < at.x0 + at.width; x++) {
                uint32_t *pixel = &next[(size_t)y * plan->width + x];
                if (*pixel != s0) { /* not CHECK: it would count every pixel */
                    CHECK(false, "step %llu: pixel %u,%u takes sample %u, its next is %u",
                          (unsigned long long)step, x, y, s0, *pixel);
                    return false;
                }
                *pixel = s0 + n;
            }
    }
    size_t wrong = 0;
    for (size_t i = 0; i < (size_t)plan->width * plan->height; i++)
        wrong += next[i] != plan->sample_end;
    CHECK_RETURN(wrong == 0, false, "%zu pixels do not end the pass at sample %u", wrong,
                 plan->sample_end);
    return true;
}

/* A whole render of spp samples over a width x height region at (x0, y0), in host passes of
 * `pass_chunks` chunks. */
static bool check_render(int width, int height, uint32_t spp, uint64_t iterations,
                         uint64_t loop_fit, bool stoppable, uint32_t pass_chunks) {
    part_meta meta = {.spp = spp, .x0 = 3, .x1 = 3 + width, .y0 = 5, .y1 = 5 + height};
    pass_plan plan = pass_plan_make(&meta, iterations, loop_fit, stoppable);
    CHECK_RETURN(plan.per_dispatch >= 1 && plan.per_dispatch <= TZ_CHUNK_SAMPLES &&
                     plan.steps_per_submit >= 1 && plan.region_x0 == 3 && plan.region_y0 == 5,
                 false, "plan of %d x %d: %u per dispatch, %llu steps a submission", width, height,
                 plan.per_dispatch, (unsigned long long)plan.steps_per_submit);
    if (!stoppable)
        CHECK_RETURN(plan.tile_width == TZ_BAND_ROWS && plan.tile_height == TZ_BAND_ROWS, false,
                     "a render that need not stop has tiles of %u x %u", plan.tile_width,
                     plan.tile_height);
    uint32_t *next = calloc((size_t)width * height, sizeof *next);
    if (!next) return false;
    uint32_t chunk_count = (spp + TZ_CHUNK_SAMPLES - 1u) / TZ_CHUNK_SAMPLES;
    bool ok = true;
    for (uint32_t c = 0; ok && c < chunk_count; c += pass_chunks) {
        uint32_t chunks = chunk_count - c < pass_chunks ? chunk_count - c : pass_chunks;
        ok = check_host_pass(&plan, c, chunks, iterations, loop_fit, stoppable, next);
    }
    free(next);
    CHECK_RETURN(ok, false, "%d x %d, %u spp, %llu passes a sample, loop fit %llu, %s, %u chunks",
                 width, height, spp, (unsigned long long)iterations, (unsigned long long)loop_fit,
                 stoppable ? "stoppable" : "not stoppable", pass_chunks);
    return true;
}

static void test_renders(void) {
    static const int sizes[][2] = {{1, 1}, {7, 3}, {64, 48}, {300, 20}, {20, 530}, {257, 260}};
    static const uint32_t spps[] = {1, 16, 37, 200};
    static const uint64_t costs[] = {1, 60, 5000, 40000, 3000000};
    static const uint32_t passes[] = {1, 3, 8};
    for (size_t a = 0; a < sizeof sizes / sizeof sizes[0]; a++)
        for (size_t b = 0; b < sizeof spps / sizeof spps[0]; b++)
            for (size_t c = 0; c < sizeof costs / sizeof costs[0]; c++)
                for (int stoppable = 0; stoppable < 2; stoppable++)
                    for (size_t d = 0; d < sizeof passes / sizeof passes[0]; d++) {
                        uint64_t fit = c % 2 ? 0u : 65000u; /* lavapipe 22.3's, or none */
                        CHECK(check_render(sizes[a][0], sizes[a][1], spps[b], costs[c], fit,
                                           stoppable, passes[d]),
                              "render plan");
                    }
}

/* A heavy scene's stoppable tiles are smaller than a band; a light one's are not. */
static void test_stoppable_tiles(void) {
    part_meta meta = {.spp = 64, .x1 = 512, .y1 = 512};
    pass_plan heavy = pass_plan_make(&meta, 40000, 0, true);
    CHECK((uint64_t)heavy.tile_width * heavy.tile_height * 40000u <= PASS_DISPATCH_BUDGET,
          "heavy stoppable tile %u x %u", heavy.tile_width, heavy.tile_height);
    pass_plan light = pass_plan_make(&meta, 60, 0, true);
    CHECK(light.tile_width == TZ_BAND_ROWS && light.tile_height == TZ_BAND_ROWS,
          "light stoppable tile %u x %u", light.tile_width, light.tile_height);
    part_meta small = {.spp = 64, .x1 = 20, .y1 = 10};
    pass_plan fitted = pass_plan_make(&small, 60, 0, true);
    CHECK(fitted.tile_width == 32 && fitted.tile_height == 16, "a 20 x 10 region's tile %u x %u",
          fitted.tile_width, fitted.tile_height);
}

static uint32_t gcd(uint32_t a, uint32_t b) {
    while (b) {
        uint32_t t = a % b;
        a = b;
        b = t;
    }
    return a;
}

static void test_workgroup_stride(void) {
    uint32_t most = (TZ_BAND_ROWS / TZ_GROUP_X) * (TZ_BAND_ROWS / TZ_GROUP_Y);
    for (uint32_t groups = 1; groups <= most; groups++) {
        uint32_t stride = pass_plan_workgroup_stride(groups);
        CHECK(gcd(groups, stride) == 1u, "stride %u of %u groups", stride, groups);
        CHECK(groups < 8u || (stride > groups / 2u && stride < groups), "stride %u of %u groups",
              stride, groups);
    }
}

static void test_stack_depth(void) {
    chunk_stack empty = {0};
    static const uint32_t ends[] = {0, 1, 2, 3, 7, 8, 15, 16, 1000};
    static const uint32_t depths[] = {1, 1, 1, 2, 3, 3, 4, 4, 9};
    for (size_t k = 0; k < sizeof ends / sizeof ends[0]; k++)
        CHECK(pass_plan_stack_depth(&empty, ends[k]) == depths[k], "depth to chunk %u: %u", ends[k],
              pass_plan_stack_depth(&empty, ends[k]));
}

int main(void) {
    CHECK_CASE(test_renders);
    CHECK_CASE(test_stoppable_tiles);
    CHECK_CASE(test_workgroup_stride);
    CHECK_CASE(test_stack_depth);
    return check_summary("test_vk_plan");
}
