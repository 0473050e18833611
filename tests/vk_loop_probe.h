/* vk_loop_probe.h: the loop probe of the tests: how many loop iterations a Vulkan device's
 * invocations really complete (lavapipe stops loops silently past a budget). */
#ifndef TRAZADOR_VK_LOOP_PROBE_H
#define TRAZADOR_VK_LOOP_PROBE_H

#include <stdbool.h>
#include <stdint.h>

#include "render/vk/vk_context.h"

/* Invocations the probe runs: two workgroups of 64 (eight lavapipe subgroups each). */
#define VK_LOOP_PROBE_INVOCATIONS 128u

/* Runs tests/loop_probe.comp once: in every invocation a loop of n[0] iterations, then one of
 * n[1]; least[k] and most[k] receive the fewest and most iterations loop k completed in any
 * invocation. False (logged) on a Vulkan failure. */
bool vk_loop_probe_run(vk_context *ctx, const uint32_t n[2], uint32_t least[2], uint32_t most[2]);

#endif
