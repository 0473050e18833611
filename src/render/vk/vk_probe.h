/* vk_probe.h: lavapipe's loop budget. Its compiled shaders silently stop every loop once one
 * invocation has run LAVAPIPE_LOOP_LIMIT iterations in total, all loops together (measured by
 * tests/test_vk_loop_limit.c); the renderer refuses scenes whose worst
 * case could reach it rather than render a wrong image. */
#ifndef TRAZADOR_VK_PROBE_H
#define TRAZADOR_VK_PROBE_H

#include <stdbool.h>
#include <stdint.h>

/* Loop passes one lavapipe invocation may run (Mesa 22.3 with LLVM 15:
 * LP_MAX_TGSI_LOOP_ITERATIONS). */
#define VK_PROBE_LAVAPIPE_LOOP_LIMIT 65535u
/* Loop passes the renderer allows one invocation on lavapipe, a margin below the budget. */
#define VK_PROBE_LAVAPIPE_SAFE_ITERATIONS 60000u

/* Worst-case loop passes of one sample of shaders/trace.comp (brute force over the spheres),
 * counted as lavapipe spends its budget; an invocation of S samples costs S times this plus one.
 * Never fails. */
uint64_t vk_probe_sample_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                    bool indirect);
/* The same for a path-mode sample (shaders/common/path.h): at most bounces + 1 rays, and at each
 * of at most `bounces` diffuse vertices a shadow ray per light, the emitter's binary search and
 * its shadow ray. Never fails. */
uint64_t vk_probe_path_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                  uint32_t emitter_count);

#endif
