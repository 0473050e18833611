/* render_vk.c: the Vulkan back end: packs and uploads the scene once, then runs shaders/trace.comp
 * over tiles of a part's region, sample pass after sample pass within each chunk of samples, each
 * pass adding into the chunk's compensated sums in sample order (a barrier between passes) and
 * the chunk's last pushing its value on each pixel's stack of chunk-tree blocks; the stacks are
 * read back into the part when the render ends or its control asks, or, when a stop abandons a
 * pass, from the snapshot taken as it began. Tiles, dispatches and submissions are as
 * vk_pass_plan.h plans them. The sums match render_cpu's, sample for sample. */
#include <inttypes.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/chunk_tree.h"
#include "render/part.h"
#include "render/pass_loop.h"
#include "render/render.h"
#include "render/scene_pack.h"
#include "render/vk/vk_accel.h"
#include "render/vk/vk_context.h"
#include "render/vk/vk_pass_plan.h"
#include "render/vk/vk_probe.h"
#include "render/vk/vk_render_state.h"
#include "render/vk/vk_strategy.h"
#include "trace_coop_spv.h"
#include "trace_path_regenerate_spv.h"
#include "trace_path_spv.h"
#include "trace_report_spv.h"
#include "trace_rq_spv.h"
#include "util/clock.h"
#include "util/log.h"

/* Loops unrolled by specialization (TZ_SPEC_UNROLLED_*, at most TZ_UNROLL_MAX_*): fewer
 * instructions on lavapipe, at the price of compile time, which grows with the copies of the
 * sphere test, spheres x lights in the shadow rays (docs/PERF.md, "First dispatch"), hence the
 * cap on the product. */
#define UNROLL_MAX_SHADOW_TESTS 16u /* unrolled spheres x unrolled lights */

/* Seconds a submission of a stoppable render aims at: a stop waits for the one in flight. */
#define STOP_SUBMIT_SECONDS 0.1
/* The specialization constants of trace.comp in constant_id order, one 32-bit word each. */
typedef struct spec_data {
    uint32_t words[TZ_SPEC_SCENE];
    struct gpu_unrolled scene;
} spec_data;
#define SPEC_COUNT (sizeof(spec_data) / sizeof(uint32_t))
_Static_assert(offsetof(spec_data, scene) == TZ_SPEC_SCENE * sizeof(uint32_t),
               "scene data start at constant_id TZ_SPEC_SCENE");

/* Records steps [first, last) of the host pass: one dispatch per tile, a barrier before each
 * dispatch pass (and at the first step), each tile's band bound through the dynamic offsets. */
static void record_steps(vk_render *r, const pass_plan *plan, uint64_t first, uint64_t last) {
    VkCommandBuffer cmd = r->cmd;
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->kernel.pipeline);
    for (uint64_t step = first; step < last; step++) {
        pass_step at;
        if (!pass_plan_step(plan, step, &at)) continue;
        /* Each pass reads and writes what the one before wrote: samples add in order. */
        if (at.pass_begins || step == first)
            vk_commands_barrier(
                cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT,
                VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                    VK_ACCESS_UNIFORM_READ_BIT);
        uint32_t offsets[VK_BINDINGS];
        uint32_t dynamic = vk_bindings_dynamic_offsets(r->buffers, r->rows, at.band_y0, offsets);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->kernel.layout, 0, 1,
                                &r->kernel.set, dynamic, offsets);
        uint32_t gx = (at.width + TZ_GROUP_X - 1u) / TZ_GROUP_X;
        uint32_t gy = (at.height + TZ_GROUP_Y - 1u) / TZ_GROUP_Y;
        struct gpu_pass push = {.x0 = at.x0,
                                .y0 = at.y0,
                                .first_sample = at.first_sample,
                                .sample_count = at.sample_count,
                                .group_stride = pass_plan_workgroup_stride(gx * gy),
                                .region_x0 = plan->region_x0,
                                .region_y0 = plan->region_y0,
                                .region_width = plan->width,
                                .region_height = plan->height,
                                .chunk_flags = at.chunk_flags,
                                .chunk_count = at.spans,
                                .stack_depth = plan->depth,
                                .noise_threshold = plan->noise_threshold};
        for (uint32_t c = 0; c < at.spans; c++)
            push.stack_slot[c] = plan->slot[at.chunk + c].top | plan->slot[at.chunk + c].merges
                                                                    << 16u;
        vkCmdPushConstants(cmd, r->kernel.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push,
                           &push);
        vkCmdDispatch(cmd, gx, gy, 1);
    }
}

/* Updates of the progress line one render shows at most: each is a submission of its own, and
 * a submission costs lavapipe a fence wait and a fork and join of its threads. */
#define PROGRESS_UPDATES 200u

/* What run_passes needs beyond the plan: the set-up it owes and the progress line's scale. */
typedef struct pass_run {
    bool setup;         /* the first submission of the render: uploads and zeroing */
    bool resumed;       /* the part had samples: its state was loaded, not zeroed */
    double start;       /* clock_seconds() when rendering began */
    double done, total; /* samples a pixel: rendered before this pass, and in all */
    double deadline;    /* render_opts.deadline */
} pass_run;

/* Records and runs one host pass, submission by submission; adds its non-finite counts when it
 * is done. With progress, submissions are cut finer (down to one tile) so that the line moves;
 * with a stop flag, to about STOP_SUBMIT_SECONDS, and the pass is abandoned between two of them
 * once the flag is up. PASS_FAILED when a
 * sample ran out of loop budget (the reason in `refusal`, else "") or on a Vulkan failure. */
static pass_result run_passes(vk_render *r, const pass_plan *plan, const render_opts *opts,
                              const pass_run *run, uint64_t *nonfinite, uint64_t *rays,
                              char *refusal) {
    vk_context *ctx = &r->ctx;
    uint64_t steps = pass_plan_steps(plan), per_submit = plan->steps_per_submit;
    if (opts->progress) {
        uint64_t fine = (steps + PROGRESS_UPDATES - 1u) / PROGRESS_UPDATES;
        if (fine < per_submit) per_submit = fine;
    }
    volatile sig_atomic_t *stop = opts->control ? opts->control->stop : NULL;
    const uint32_t *counter = r->buffers[TZ_BINDING_COUNTERS].mapped
                                  ? r->buffers[TZ_BINDING_COUNTERS].mapped
                                  : r->readback.mapped;
    bool ok = true;
    uint32_t overflowed = 0; /* samples whose walk ran out of loop passes */
    uint64_t pass_nonfinite = 0;
    double samples_in_pass = (double)plan->sample_end - run->done;
    for (uint64_t first = 0, last; ok && first < steps; first = last) {
        if (stop && *stop) return first == 0 ? PASS_NOT_BEGUN : PASS_ABANDONED;
        uint64_t submit = stop && r->stop_steps < per_submit ? r->stop_steps : per_submit;
        last = steps - first < submit ? steps : first + submit;
        if (!vk_commands_begin(ctx, &r->cmd)) {
            ok = false;
            break;
        }
        double t0 = clock_seconds();
        /* The counters restart each submission: the previous submission's atomics and copy
         * are done (fence) and ordered before the fill. */
        vk_commands_barrier(r->cmd,
                            VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_ACCESS_SHADER_WRITE_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                            VK_ACCESS_TRANSFER_WRITE_BIT);
        if (first == 0 && run->setup)
            vk_render_record_setup(r, run->resumed, (size_t)plan->width * plan->height);
        if (first == 0 && r->snapshot.buffer) vk_render_record_snapshot(r, plan);
        vkCmdFillBuffer(r->cmd, r->buffers[TZ_BINDING_COUNTERS].buffer, 0, VK_WHOLE_SIZE, 0u);
        record_steps(r, plan, first, last);
        vk_render_record_readback(r, plan, false);
        if (!vk_commands_submit_wait(ctx, r->cmd, r->fence)) {
            ok = false;
            break;
        }
        if (stop) { /* the next submission sized to the time these steps took */
            double per_step = (clock_seconds() - t0) / (double)(last - first);
            double fit = per_step > 0.0 ? STOP_SUBMIT_SECONDS / per_step : (double)per_submit;
            r->stop_steps = fit < 1.0 ? 1u : fit < (double)per_submit ? (uint64_t)fit : per_submit;
        }
        pass_nonfinite += counter[0];
        *rays += counter[2] | (uint64_t)counter[3] << 32;
        overflowed = counter[1];
        ok = overflowed == 0;
        if (ok && opts->progress) {
            double done = run->done + samples_in_pass * (double)last / (double)steps;
            render_progress_print(done / run->total, clock_seconds() - run->start,
                                  (double)plan->width * plan->height * run->total, run->deadline);
        }
    }
    if (overflowed > 0)
        snprintf(refusal, RENDER_REASON_SIZE,
                 "%u sample%s had a ray whose BVH walk needed more loop passes than lavapipe "
                 "allows (its shaders stop loops silently past %u in all)",
                 overflowed, overflowed == 1 ? "" : "s", ctx->loop_limit);
    if (!ok) return PASS_FAILED;
    *nonfinite += pass_nonfinite;
    return PASS_DONE;
}

/* Runs the pipeline once on a pass of no pixels (every invocation returns at once): llvmpipe
 * (lavapipe) compiles a shader to machine code at its first dispatch, not in
 * vkCreateComputePipelines, which without a warm shader cache made the first pass of a render
 * seconds slower than the rest (docs/PERF.md, "First dispatch"). Done here, the compilation
 * counts as set-up, not as rendering. False (logged) on a Vulkan failure. */
static bool warm_up_pipeline(vk_render *r) {
    if (!vk_commands_begin(&r->ctx, &r->cmd)) return false;
    vkCmdBindPipeline(r->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->kernel.pipeline);
    uint32_t offsets[VK_BINDINGS];
    uint32_t dynamic = vk_bindings_dynamic_offsets(r->buffers, r->rows, 0u, offsets);
    vkCmdBindDescriptorSets(r->cmd, VK_PIPELINE_BIND_POINT_COMPUTE, r->kernel.layout, 0, 1,
                            &r->kernel.set, dynamic, offsets);
    struct gpu_pass push = {.group_stride = pass_plan_workgroup_stride(1u), .chunk_count = 1u};
    vkCmdPushConstants(r->cmd, r->kernel.layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push,
                       &push);
    vkCmdDispatch(r->cmd, 1, 1, 1);
    return vk_commands_submit_wait(&r->ctx, r->cmd, r->fence);
}

/* Compiles trace.comp for the scene (the module with the cooperative walk, the ray query one
 * with its acceleration structure bound, or the plain one;
 * specialization constants: the strategy, the flags, and the spheres and lights of an unrolled
 * scene), creates the fence and binds the buffers; false (logged) on a Vulkan failure. */
static bool create_kernel(vk_render *r, const packed_scene *packed, const vk_strategy *st) {
    /* Small scenes get their sphere and light loops unrolled, and their spheres and lights
     * become specialization constants: the unrolled tests read immediates, and the loop
     * bookkeeping disappears (each such scene compiles its own pipeline, which Mesa's shader
     * cache keeps). The flags compile out the indirect bounce when it is off. */
    uint32_t lights = packed->frame.light_count;
    bool unroll_lights =
        lights <= TZ_UNROLL_MAX_LIGHTS && !(packed->frame.flags & TZ_FLAG_SHAPED_LIGHTS) &&
        (st->unrolled_spheres == 0u || st->unrolled_spheres * lights <= UNROLL_MAX_SHADOW_TESTS);
    spec_data constants = {.words = {
                               [TZ_SPEC_UNROLLED_SPHERES] = st->unrolled_spheres,
                               [TZ_SPEC_UNROLLED_LIGHTS] = unroll_lights ? lights : 0u,
                               [TZ_SPEC_FLAGS] = packed->frame.flags,
                               [TZ_SPEC_WALK_BUDGET] = vk_strategy_walk_loop(st),
                               [TZ_SPEC_WIDE_BVH] = st->wide_bvh,
                           }};
    /* The unrolled spheres and lights, zero past the scene's (the shader reads none of those). */
    scene_pack_unrolled(packed, st->unrolled_spheres, &constants.scene);
    for (uint32_t k = 0; unroll_lights && k < lights; k++) {
        constants.scene.lights[2 * k] = packed->lights[k].position_power;
        constants.scene.lights[2 * k + 1] = packed->lights[k].color;
    }
    VkSpecializationMapEntry entries[SPEC_COUNT];
    for (uint32_t k = 0; k < SPEC_COUNT; k++)
        entries[k] =
            (VkSpecializationMapEntry){k, k * (uint32_t)sizeof(uint32_t), sizeof(uint32_t)};
    const VkSpecializationInfo spec = {SPEC_COUNT, entries, sizeof constants, &constants};
    bool path = (packed->frame.flags & TZ_FLAG_PATH) != 0u;
    /* trace.comp says why paths restart lane by lane only where no BVH is walked. */
    bool regenerate = path && !st->use_bvh;
    VkDescriptorType types[VK_BINDINGS];
    uint32_t bindings = st->ray_query ? TZ_BINDING_ACCEL + 1u : TZ_BINDING_COUNT;
    vk_bindings_types(bindings, types);
    vk_kernel_desc kernel = {
        .spec = &spec,
        .code = st->ray_query     ? trace_rq_spv
                : st->cooperative ? trace_coop_spv
                : regenerate      ? trace_path_regenerate_spv
                : path            ? trace_path_spv
                                  : trace_report_spv,
        .code_size = st->ray_query     ? sizeof trace_rq_spv
                     : st->cooperative ? sizeof trace_coop_spv
                     : regenerate      ? sizeof trace_path_regenerate_spv
                     : path            ? sizeof trace_path_spv
                                       : sizeof trace_report_spv,
        .types = types,
        .binding_count = bindings,
        .push_size = sizeof(struct gpu_pass),
    };
    VkFenceCreateInfo fence_info = {.sType = VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    if (!vk_kernel_create(&r->ctx, &kernel, &r->kernel) ||
        !VK_CHECK(vkCreateFence(r->ctx.device, &fence_info, NULL, &r->fence)))
        return false;
    vk_bindings_bind(&r->ctx, &r->kernel, r->buffers, r->rows);
    if (st->ray_query) vk_accel_bind(&r->ctx, &r->kernel, TZ_BINDING_ACCEL, &r->accel);
    return true;
}

/* What the Vulkan back end's host passes share across pass_loop_run's calls. */
typedef struct vk_passes {
    vk_render *r;
    pass_plan *plan;
    const render_opts *opts;
    chunk_slot *slots;
    chunk_stack shape, before; /* the stack after the passes run so far, and before the last */
    pass_run run;
    bool current;       /* the last pass was the first: the part is as the device began */
    uint64_t nonfinite; /* since the last sync */
    uint64_t rays;      /* traced in all */
    uint32_t begin;     /* the chunk the render began at */
    char *reason;       /* a refusal */
} vk_passes;

/* pass_backend.run: plans and runs one host pass (run_passes) on the device. */
static pass_result vk_run_pass(void *user, part *p, uint32_t first, uint32_t chunks) {
    vk_passes *v = user;
    v->before = v->shape;
    for (uint32_t k = 0; k < chunks; k++) {
        v->slots[k].top = (uint32_t)v->shape.count;
        v->slots[k].merges = (uint32_t)chunk_stack_push(&v->shape, (chunk_block){0, first + k});
    }
    v->plan->first_chunk = first;
    v->plan->chunks = chunks;
    v->plan->sample_end = part_sample_of(p, first + chunks);
    v->plan->slot = v->slots;
    v->run.done = (double)(part_sample_of(p, first) - part_sample_of(p, v->begin));
    v->current = v->run.setup;
    pass_result result =
        run_passes(v->r, v->plan, v->opts, &v->run, &v->nonfinite, &v->rays, v->reason);
    v->run.setup = false;
    return result;
}

/* pass_backend.sync: reads the sums back into p: as they are, or after a stop as the pass in
 * flight began (from the snapshot once a submission of it ran; nothing to read when it was the
 * first and none ran). */
static bool vk_sync(void *user, part *p, uint32_t done, pass_result result) {
    vk_passes *v = user;
    if (result == PASS_DONE)
        return vk_render_sync_part(v->r, v->plan, false, &v->shape, done, &v->nonfinite, p);
    if (v->current && result == PASS_NOT_BEGUN) return true;
    return vk_render_sync_part(v->r, v->plan, result == PASS_ABANDONED, &v->before, done,
                               &v->nonfinite, p);
}

/* Renders chunks up to end_chunk in the passes opts->control sets (pass_loop_run); false on
 * failure or a refusal (in `reason`). */
static bool render_chunks(vk_render *r, pass_plan *plan, const render_opts *opts, part *p,
                          uint32_t end_chunk, bool resumed, char *reason) {
    uint32_t begin = p->stack.end;
    vk_passes v = {
        .r = r,
        .plan = plan,
        .opts = opts,
        .slots = malloc((end_chunk - begin + 1u) * sizeof(chunk_slot)),
        .shape = p->stack,
        .run = {.setup = true,
                .resumed = resumed,
                .start = clock_seconds(),
                .total = (double)(part_sample_of(p, end_chunk) - part_sample_of(p, begin)),
                .deadline = opts->deadline},
        .begin = begin,
        .reason = reason};
    if (!v.slots) {
        log_error("out of memory for a plan of %u chunks", end_chunk - begin);
        return false;
    }
    pass_backend be = {.run = vk_run_pass, .sync = vk_sync, .user = &v};
    bool ok = pass_loop_run(opts, p, end_chunk, "vulkan", &be);
    if (opts->progress) render_progress_clear(); /* on failure too: messages follow */
    if (opts->stats) opts->stats->rays = v.rays;
    free(v.slots);
    return ok;
}

/* Names this device and driver as the part's back end; false (the reason said) when the part
 * was begun by another back end or driver, whose samples differ by rounding. */
static bool claim_part(const vk_context *ctx, part *p, char *reason) {
    char mine[sizeof p->meta.backend];
    snprintf(mine, sizeof mine, "vulkan: %.160s, driver %.64s, version %" PRIu32,
             ctx->properties.deviceName, ctx->driver_name[0] ? ctx->driver_name : "(unnamed)",
             ctx->properties.driverVersion);
    if (p->meta.backend[0] && strcmp(p->meta.backend, mine)) {
        snprintf(reason, RENDER_REASON_SIZE,
                 "the part to go on from was rendered by the %.150s back end, and this render by "
                 "the %.150s back end: the two differ by rounding, so their samples do not mix",
                 p->meta.backend, mine);
        return false;
    }
    snprintf(p->meta.backend, sizeof p->meta.backend, "%s", mine);
    return true;
}

/* render_backend.render_part of the Vulkan back end. */
static render_status vk_render_part(const scene *s, const render_opts *opts, part *p,
                                    uint32_t sample_end, char *reason) {
    reason[0] = '\0';
    vk_render r = {.stop_steps = 1};
    packed_scene packed = {0};
    bool ok = false;
    double t0 = clock_seconds();
    vk_context_desc desc = {.device = opts->device_given ? opts->device : -1,
                            .validate = opts->validate,
                            .ray_query = vk_strategy_wants_ray_query(opts),
                            .threads = opts->threads};
    if (!vk_context_init(&r.ctx, &desc)) return RENDER_FAILED;
    double t_init = clock_seconds();
    log_debug("vulkan: device %d, %s (%s), instance and device in %.1f ms", r.ctx.device_index,
              r.ctx.properties.deviceName, r.ctx.driver_name, (t_init - t0) * 1e3);
    if (!claim_part(&r.ctx, p, reason)) goto done;
    render_walk walk;
    const char *why;
    if (!vk_strategy_walk(&r.ctx, opts, &walk, &why)) goto done;
    vk_strategy st = vk_strategy_choose(&r.ctx, s, opts, walk);
    log_debug("vulkan: walk %s (%s)%s",
              st.ray_query     ? "rayquery: the device's acceleration structure"
              : st.cooperative ? "cooperative: the subgroup walks the BVH together"
              : st.wide_bvh    ? "compute: each invocation walks the wide BVH"
              : st.use_bvh     ? "compute: each invocation walks the binary BVH"
                               : "compute: every primitive tested (no BVH for this scene)",
              why, walk == RENDER_WALK_COOPERATIVE && !st.cooperative ? "; no BVH to walk" : "");
    render_opts packing = *opts;
    packing.no_bvh = !st.use_bvh;
    int width = p->meta.x1 - p->meta.x0, height = p->meta.y1 - p->meta.y0;
    uint32_t end_chunk = part_chunk_of(p, sample_end);
    /* A noise threshold's state takes two blocks more a pixel (gpu_pass.noise_threshold). */
    uint32_t depth = pass_plan_stack_depth(&p->stack, end_chunk) + (p->adaptive ? 2u : 0u);
    bool stoppable = opts->control && opts->control->stop;
    bool resumed = p->stack.count > 0;
    double t_pack = clock_seconds();
    if (!vk_strategy_check(&r.ctx, s, opts, &st, width, height, depth, reason) ||
        !scene_pack(s, &packing, &packed))
        goto done;
    scene_pack_report(&packed, opts, t_pack);
    double t_buffers = clock_seconds(); /* after the pack, which reports its own time */
    if (!vk_render_create_buffers(&r, &packed, &st, width, height, depth, stoppable)) goto done;
    if (resumed && !vk_render_load_part(&r, p, depth)) goto done;
    double t_upload = clock_seconds();
    log_debug("vulkan: buffers and upload in %.1f ms (%s)", (t_upload - t_buffers) * 1e3,
              r.buffers[TZ_BINDING_ACCUM].host     ? "the process's memory imported"
              : r.buffers[TZ_BINDING_ACCUM].mapped ? "mapped device memory"
                                                   : "staging copies");
    if (st.ray_query) {
        if (!vk_accel_build(&r.ctx, &packed, &r.accel)) goto done;
        double t_accel = clock_seconds();
        log_debug("vulkan: acceleration structure of %u primitives built in %.1f ms",
                  packed.frame.sphere_count + packed.frame.triangle_count,
                  (t_accel - t_upload) * 1e3);
        t_upload = t_accel;
    }
    if (!create_kernel(&r, &packed, &st) || !warm_up_pipeline(&r)) goto done;
    double t_pipeline = clock_seconds();
    log_debug("vulkan: pipeline in %.1f ms", (t_pipeline - t_upload) * 1e3);

    uint64_t loop_fit = r.ctx.loop_limit ? vk_probe_safe_iterations(r.ctx.loop_limit) : 0u;
    pass_plan plan = pass_plan_make(&p->meta, st.sample_iterations, loop_fit, stoppable);
    plan.depth = depth;
    memcpy(&plan.noise_threshold, &opts->noise_threshold, sizeof plan.noise_threshold);
    log_debug("vulkan: %" PRIu64
              " loop passes per sample at most, %u sample%s per dispatch on tiles of %u x %u, "
              "%" PRIu64 " dispatch%s per submission%s, %u chunk-tree block%s a pixel",
              st.sample_iterations, plan.per_dispatch, plan.per_dispatch == 1 ? "" : "s",
              plan.tile_width, plan.tile_height, plan.steps_per_submit,
              plan.steps_per_submit == 1 ? "" : "es",
              stoppable ? " at most (a stop waits for one)" : "", depth, depth == 1 ? "" : "s");
    if (!render_chunks(&r, &plan, opts, p, end_chunk, resumed, reason)) goto done;
    double t_render = clock_seconds();
    if (opts->stats) opts->stats->render_seconds = t_render - t_pipeline;
    log_debug("vulkan: rendering and read-back in %.1f ms", (t_render - t_pipeline) * 1e3);
    ok = true;
done:
    vk_render_destroy(&r);
    scene_pack_free(&packed);
    bool valid = vk_context_destroy(&r.ctx);
    if (!valid) log_error("the Vulkan validation layer reported errors: the render failed");
    /* A refusal stands only when nothing else went wrong: validation errors fail the run. */
    if (ok && valid) return RENDER_DONE;
    if (reason[0] && valid) return RENDER_REFUSED;
    if (reason[0]) log_error("%s" RENDER_USE_CPU, reason);
    return valid ? RENDER_FAILED : RENDER_INVALID;
}

const render_backend render_backend_vulkan = {.name = "vulkan",
                                              .device_count = vk_context_device_count,
                                              .cpu_only = vk_context_cpu_only,
                                              .describe = vk_context_print_devices,
                                              .render_part = vk_render_part};
