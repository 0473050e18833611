/* vk_strategy.c: the Vulkan back end's intersection strategy for a scene and its refusals
 * (vk_strategy.h), on the loop budget the driver was probed to have (vk_probe.h). */
#include "render/vk/vk_strategy.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/vk/vk_probe.h"
#include "shared_layout.h"
#include "util/log.h"

/* Loop passes a ray's BVH walk must be allowed at least, where loops are cut, for a scene to be
 * tried. */
#define MIN_WALK_BUDGET 256u
/* Primitives from which lavapipe before Mesa 25 walks the wide BVH faster than the binary one
 * (docs/PERF.md, "Wide BVH"): below, its shallower trees save fewer node visits than the wide
 * node's decoding costs. */
#define WIDE_BVH_MIN_PRIMITIVES_MESA22 50000u

/* The walk TRAZADOR_VK_WALK names (the alias of --walk), auto when it names none; a name that is
 * no walk is warned about, once a process (the strategy asks more than once). */
static render_walk walk_from_environment(void) {
    static bool warned;
    const char *name = getenv("TRAZADOR_VK_WALK");
    if (!name || !*name || !strcmp(name, "auto")) return RENDER_WALK_AUTO;
    if (!strcmp(name, "compute") || !strcmp(name, "invocation")) return RENDER_WALK_COMPUTE;
    if (!strcmp(name, "cooperative")) return RENDER_WALK_COOPERATIVE;
    if (!strcmp(name, "rayquery")) return RENDER_WALK_RAY_QUERY;
    if (!warned)
        log_warn("TRAZADOR_VK_WALK=%s is no walk (auto, compute, cooperative or rayquery): auto",
                 name);
    warned = true;
    return RENDER_WALK_AUTO;
}

bool vk_strategy_wants_ray_query(const render_opts *opts) {
    render_walk walk = opts->walk != RENDER_WALK_AUTO ? opts->walk : walk_from_environment();
    return walk == RENDER_WALK_AUTO || walk == RENDER_WALK_RAY_QUERY;
}

/* Why the device cannot do `walk`, NULL when it can. The ray query walk's candidate loop is the
 * device's, which a driver that cuts loops (lavapipe 22.3) could cut unseen. */
static const char *walk_missing(const vk_context *ctx, render_walk walk) {
    if (walk == RENDER_WALK_COOPERATIVE && !vk_context_has_subgroup_walk(ctx))
        return "it lacks the subgroup operations (basic, arithmetic) in subgroups of at most 63 "
               "lanes that the cooperative walk needs";
    if (walk == RENDER_WALK_RAY_QUERY && !ctx->ray_query)
        return "it does not offer VK_KHR_ray_query and VK_KHR_acceleration_structure with "
               "bufferDeviceAddress (Vulkan 1.2)";
    if (walk == RENDER_WALK_RAY_QUERY && ctx->loop_limit)
        return "its shaders stop loops silently, which would cut ray queries short";
    return NULL;
}

static const char *walk_name(render_walk walk) {
    return walk == RENDER_WALK_COOPERATIVE ? "cooperative"
           : walk == RENDER_WALK_RAY_QUERY ? "rayquery"
                                           : "compute";
}

/* Auto's walk: ray queries on GPUs that have them (traversal hardware, or at least the driver's
 * own walk), the compute walk on CPU devices, where lavapipe 25 measured ray queries slower
 * (docs/PERF.md, "Ray query walk"). The cooperative walk measured slower on lavapipe and
 * diverges on GPUs, so auto never takes it. */
static render_walk auto_walk(const vk_context *ctx, const char **why) {
    bool cpu = ctx->properties.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU;
    bool rq = walk_missing(ctx, RENDER_WALK_RAY_QUERY) == NULL;
    *why = cpu && rq ? "auto: ray queries measured slower than the compute walk on CPU devices"
           : cpu     ? "auto: the compute walk on CPU devices"
           : rq      ? "auto: ray queries, which this GPU has"
                     : "auto: the compute walk, this GPU has no ray queries";
    return rq && !cpu ? RENDER_WALK_RAY_QUERY : RENDER_WALK_COMPUTE;
}

bool vk_strategy_walk(const vk_context *ctx, const render_opts *opts, render_walk *walk,
                      const char **why) {
    render_walk env = walk_from_environment();
    if (opts->walk != RENDER_WALK_AUTO) {
        const char *missing = walk_missing(ctx, opts->walk);
        if (missing) {
            log_error("--walk %s: Vulkan device %d (%s, driver %s %s) cannot do it: %s",
                      walk_name(opts->walk), ctx->device_index, ctx->properties.deviceName,
                      ctx->driver_name, ctx->driver_info, missing);
            return false;
        }
        *walk = opts->walk;
        *why = "--walk asked for it";
        return true;
    }
    *walk = auto_walk(ctx, why);
    if (env == RENDER_WALK_AUTO) return true;
    const char *missing = walk_missing(ctx, env);
    if (missing) {
        log_info("TRAZADOR_VK_WALK=%s: this device cannot do it (%s); the %s walk instead",
                 getenv("TRAZADOR_VK_WALK"), missing, walk_name(*walk));
        return true;
    }
    *walk = env;
    *why = "TRAZADOR_VK_WALK asked for it";
    return true;
}

/* The major version of a Mesa driver ("Mesa 25.0.7"), 0 for another driver. */
static int mesa_major(const vk_context *ctx) {
    int major = 0;
    return sscanf(ctx->driver_info, "Mesa %d", &major) == 1 ? major : 0;
}

/* Whether the walk per invocation reads the wide BVH: as TRAZADOR_VK_BVH says (wide or binary,
 * for tests and measurements), else wherever it measured faster: everywhere but lavapipe of Mesa
 * 22-24, where only big scenes gain. */
static bool wide_bvh_pays(const vk_context *ctx, const scene *s) {
    const char *forced = getenv("TRAZADOR_VK_BVH");
    if (forced && !strcmp(forced, "wide")) return true;
    if (forced && !strcmp(forced, "binary")) return false;
    int mesa = mesa_major(ctx);
    bool old_lavapipe = vk_context_is_lavapipe(ctx) && mesa > 0 && mesa < 25;
    return !old_lavapipe || (uint64_t)s->sphere_count + (uint64_t)s->triangle_count >=
                                WIDE_BVH_MIN_PRIMITIVES_MESA22;
}

/* TZ_SPEC_WALK_BUDGET: the passes each walk loop may take. A cooperative ray may run both walks
 * (lanes of the subgroup that disagree on coherence), each loop with its exit pass, so each gets
 * half of the ray's passes; 0 (unlimited) stays 0. */
uint32_t vk_strategy_walk_loop(const vk_strategy *st) {
    if (!st->cooperative || st->walk == 0u) return st->walk;
    return st->walk > 1u ? (st->walk - 1u) / 2u : 1u;
}

/* The words of s's texture table (texture_pack.c): its fixed tables and header, slots, images,
 * the UVs of every face with corner data (a bound: the packer gives UVs to those alone) and the
 * texels. */
static uint64_t texture_words(const scene *s) {
    if (s->slot_count == 0 && !scene_has_microfacet(s)) return 0;
    return TZ_TEXTURE_FIRST_SLOT + (uint64_t)s->slot_count * TZ_SLOT_WORDS +
           (uint64_t)s->image_count * TZ_IMAGE_WORDS + 6u * (uint64_t)s->normals_count +
           s->texel_bytes / 4u;
}

/* Refuses what the device could not render right: scene or accumulation buffers past its limits,
 * and where the driver cuts loops (lavapipe 22.3) a sample whose worst-case loop work could
 * reach that limit; false with the reason in `reason` (RENDER_REASON_SIZE bytes), nothing
 * logged. */
bool vk_strategy_check(const vk_context *ctx, const scene *s, const render_opts *opts,
                       const vk_strategy *st, int width, int height, uint32_t depth, char *reason) {
    bool use_bvh = st->use_bvh;
    uint64_t sample_iterations = st->sample_iterations;
    uint32_t loop_limit = ctx->loop_limit;
    if (loop_limit && use_bvh && vk_strategy_walk_loop(st) < MIN_WALK_BUDGET) {
        snprintf(reason, RENDER_REASON_SIZE,
                 "with %d lights and this bounce limit a ray could walk the BVH only %u loop "
                 "passes on lavapipe (its shaders stop loops silently after %u)",
                 s->light_count, vk_strategy_walk_loop(st), loop_limit);
        return false;
    }
    /* One sample an invocation: its passes and the sample loop's exit pass. */
    if (loop_limit && !use_bvh && sample_iterations + 1u > vk_probe_safe_iterations(loop_limit)) {
        snprintf(reason, RENDER_REASON_SIZE,
                 "this scene needs up to %" PRIu64
                 " loop passes per sample, past lavapipe's safe "
                 "limit of %" PRIu64 " (its shaders stop loops silently after %u%s)",
                 sample_iterations + 1u, vk_probe_safe_iterations(loop_limit), loop_limit,
                 opts->no_bvh ? "; --no-bvh tests every sphere for every ray" : "");
        return false;
    }
    /* The accumulation buffer is addressed with 32-bit dynamic offsets, and drivers cap buffers
     * below 4 GiB (lavapipe's maxBufferSize is 2^32 - 1): 16384 x 16384 pixels need 2^32 bytes. */
    uint64_t rows = ((uint64_t)height + TZ_BAND_ROWS - 1u) / TZ_BAND_ROWS * TZ_BAND_ROWS;
    uint64_t row_bytes = (uint64_t)width * (ACCUM_PIXEL_BYTES > depth * STACK_BLOCK_BYTES
                                                ? ACCUM_PIXEL_BYTES
                                                : depth * STACK_BLOCK_BYTES);
    uint64_t accum_bytes = rows * row_bytes;
    if (accum_bytes > UINT32_MAX) {
        snprintf(reason, RENDER_REASON_SIZE,
                 "a %d x %d region with %u chunk-tree blocks a pixel needs %" PRIu64
                 " bytes of accumulation buffer (rows rounded up to whole %u-row bands), past the "
                 "4 GiB - 1 the Vulkan back end addresses (at this width %" PRIu64
                 " rows fit; --region splits the image)",
                 width, height, depth, accum_bytes, TZ_BAND_ROWS,
                 UINT32_MAX / row_bytes / TZ_BAND_ROWS * TZ_BAND_ROWS);
        return false;
    }
    const VkPhysicalDeviceLimits *limits = &ctx->properties.limits;
    uint64_t primitives = (uint64_t)s->sphere_count + (uint64_t)s->triangle_count;
    /* A texel is one vec4 of the shared structs. */
    const uint64_t sphere_texels = sizeof(struct gpu_sphere) / 16u;
    const uint64_t material_texels = sizeof(struct gpu_material) / 16u;
    uint64_t sizes[] = {(uint64_t)s->sphere_count * sphere_texels, (uint64_t)s->light_count * 2u,
                        (uint64_t)TZ_BAND_ROWS * row_bytes,
                        use_bvh ? primitives * 4u : 0u, /* < 1 node a primitive */
                        (uint64_t)s->triangle_count * 3u,
                        (uint64_t)s->material_count * material_texels, texture_words(s),

                        /* the map's texels and its tables, four floats a texel (a bound) */
                        (uint64_t)s->environment.width * (uint64_t)s->environment.height * 5u / 4u +
                            (uint64_t)s->environment.height + 2u};
    uint64_t limit[] = {limits->maxTexelBufferElements, limits->maxTexelBufferElements,
                        limits->maxStorageBufferRange,  limits->maxTexelBufferElements,
                        limits->maxTexelBufferElements, limits->maxTexelBufferElements,
                        limits->maxTexelBufferElements};
    const char *what[] = {"texels of spheres",          "texels of lights",
                          "bytes of accumulation rows", "texels of BVH nodes",
                          "texels of triangles",        "texels of materials",
                          "words of textures",          "texels of the environment map"};
    for (int k = 0; k < 7; k++) {
        if (sizes[k] > limit[k]) {
            snprintf(reason, RENDER_REASON_SIZE,
                     "the scene needs %" PRIu64
                     " %s in one buffer, past this device's limit of %" PRIu64,
                     sizes[k], what[k], limit[k]);
            return false;
        }
    }
    return true;
}

/* Worst-case loop passes of one sample of the scene's mode (with `emitters` emitting spheres) when
 * a ray costs what testing `spheres` spheres does (vk_probe.h). */
static uint64_t sample_iterations(const scene *s, const render_opts *opts, uint32_t emitters,
                                  uint32_t spheres) {
    uint32_t lights = (uint32_t)s->light_count, bounces = (uint32_t)opts->bounces;
    if (opts->mode != RENDER_MODE_PATH)
        return vk_probe_sample_iterations(spheres, lights, bounces, opts->indirect);
    return vk_probe_path_iterations(spheres, lights, bounces, (uint32_t)render_light_samples(opts),
                                    emitters);
}

/* The most passes one ray's BVH walk may take under a loop limit of `limit` so that a sample,
 * every ray walking that far, stays within the safe share of it; 0 when even walks of no length
 * do not fit. */
static uint32_t walk_budget(const scene *s, const render_opts *opts, uint32_t emitters,
                            uint32_t limit) {
    uint64_t safe = vk_probe_safe_iterations(limit);
    uint64_t fixed = sample_iterations(s, opts, emitters, 0u);
    uint64_t rays = sample_iterations(s, opts, emitters, 1u) - fixed;
    if (fixed + 1u >= safe) return 0u;
    uint64_t walk = (safe - 1u - fixed) / rays;
    return walk < UINT32_MAX ? (uint32_t)walk : UINT32_MAX;
}

/* With ray queries every scene walks the device's acceleration structure. Otherwise small scenes
 * test every sphere in unrolled loops; bigger ones walk the BVH, each walk bounded where the
 * driver cuts loops by TZ_SPEC_WALK_BUDGET passes as if it tested that many spheres (a guess of
 * 64 sizes the dispatches elsewhere). */
vk_strategy vk_strategy_choose(const vk_context *ctx, const scene *s, const render_opts *opts,
                               render_walk walk) {
    /* A ray tests spheres and triangles alike: one loop pass a primitive. */
    uint32_t spheres = (uint32_t)s->sphere_count + (uint32_t)s->triangle_count, emitters = 0;
    for (int k = 0; opts->mode == RENDER_MODE_PATH && k < s->sphere_count; k++)
        emitters += sphere_emits(s, &s->spheres[k]);
    for (int k = 0; opts->mode == RENDER_MODE_PATH && k < s->triangle_count; k++)
        emitters += triangle_emits(s, &s->triangles[k]);
    /* Only spheres are unrolled (their data become specialization constants). */
    if (walk == RENDER_WALK_RAY_QUERY) {
        /* The device's walk: no loop of trazador's own to bound, a guessed 64 tests a ray. */
        vk_strategy rq = {.ray_query = true};
        rq.sample_iterations = sample_iterations(s, opts, emitters, 64u);
        return rq;
    }
    /* Textured spheres need their material's index, which the unrolled constants leave out. */
    bool unroll = spheres <= TZ_UNROLL_MAX_SPHERES && s->triangle_count == 0 &&
                  s->slot_count == 0 && s->instance_count == 0;
    vk_strategy st = {.unrolled_spheres = unroll ? spheres : 0u};
    /* Instances live in the tree's leaves: it is walked whatever --no-bvh says (scene_pack.c). */
    st.use_bvh =
        (!opts->no_bvh && st.unrolled_spheres == 0u && spheres > 0u) || s->instance_count > 0;
    st.cooperative = st.use_bvh && walk == RENDER_WALK_COOPERATIVE;
    uint32_t limit = ctx->loop_limit;
    bool cut = limit != 0u; /* the driver stops loops silently */
    st.walk = st.use_bvh && cut ? walk_budget(s, opts, emitters, limit) : 0u;
    /* Unrolled sphere tests are no loop: a ray then costs only its own loop passes. */
    uint64_t every_sphere =
        sample_iterations(s, opts, emitters, st.unrolled_spheres ? 0u : spheres);
    /* Many lights leave each walk too few passes; testing every sphere may still fit. */
    if (st.use_bvh && cut && vk_strategy_walk_loop(&st) < MIN_WALK_BUDGET &&
        s->instance_count == 0 && every_sphere < vk_probe_safe_iterations(limit)) {
        st.use_bvh = st.cooperative = false;
        st.walk = 0u;
    }
    /* The wide tree holds the scene's nodes alone: the instances' models are binary trees. */
    st.wide_bvh = st.use_bvh && s->instance_count == 0 && wide_bvh_pays(ctx, s);
    st.sample_iterations =
        st.use_bvh ? sample_iterations(s, opts, emitters, cut ? st.walk : 64u) : every_sphere;
    return st;
}
