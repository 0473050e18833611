/* vk_probe.h: the loop budget of the running driver. lavapipe up to Mesa 22.3 silently stops
 * every loop once one invocation has run a fixed number of iterations in total, all loops
 * together (65,535 there; later Mesa runs loops to the end): vk_probe_loop_limit measures it on
 * the device, and the renderer refuses scenes whose worst case could reach it rather than render
 * a wrong image (tests/test_vk_loop_limit.c). */
#ifndef TRAZADOR_VK_PROBE_H
#define TRAZADOR_VK_PROBE_H

#include <stdbool.h>
#include <stdint.h>

#include "render/vk/vk_context.h"

/* Loop passes the probe runs, twice lavapipe 22.3's budget: a driver whose loops complete them all
 * is taken to have no limit (more passes make every context slower to open). */
#define VK_PROBE_REACH (1u << 17)
/* Invocations the probe runs: two workgroups of 64 (eight lavapipe subgroups each). */
#define VK_PROBE_INVOCATIONS 128u

/* Runs shaders/loop_probe.comp once: in every invocation a loop of n[0] iterations, then one of
 * n[1]; least[k] and most[k] receive the fewest and most iterations loop k completed in any
 * invocation. False (logged) on a Vulkan failure. */
bool vk_probe_loops(vk_context *ctx, const uint32_t n[2], uint32_t least[2], uint32_t most[2]);
/* Sets ctx->loop_limit: the loop passes one invocation completes before the driver stops its
 * loops (lavapipe 22.3: 65,535), 0 when a loop of VK_PROBE_REACH passes runs to the end. Probes
 * only lavapipe (other drivers run loops to the end). False (logged) on a Vulkan failure. */
bool vk_probe_loop_limit(vk_context *ctx);
/* Loop passes the renderer allows one invocation under a limit of `limit`: a margin below it
 * (60,000 of lavapipe 22.3's 65,535); UINT64_MAX for no limit (0). Never fails. */
uint64_t vk_probe_safe_iterations(uint32_t limit);

/* Worst-case loop passes of one sample of shaders/trace.comp (brute force over the spheres),
 * counted as lavapipe spends its budget; an invocation of S samples costs S times this plus one.
 * Never fails. */
uint64_t vk_probe_sample_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                    bool indirect);
/* The same for a path-mode sample (shaders/common/path.h): at most bounces + 1 rays, and at each
 * of at most `bounces` diffuse vertices a shadow ray per light and, light_samples times, the
 * emitter's binary search and its shadow ray. Never fails. */
uint64_t vk_probe_path_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                  uint32_t light_samples, uint32_t emitter_count);

#endif
