/* integrator_dispatch.c: the builds of the packet integrators (src/render/cpu/integrator_packet.c
 * for report mode, integrator_path_packet.c for path mode, one per vector level, see
 * CMakeLists.txt) and which of them this processor runs. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/cpu/integrator.h"
#include "util/log.h"

typedef void packet_sample_fn(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                              uint32_t sample_index, vec3 *out);

typedef void path_samples_fn(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                             uint32_t first, uint32_t count, vec3 *out);

packet_sample_fn integrator_sample_packet_baseline, integrator_path_packet_baseline;
path_samples_fn integrator_path_samples_baseline;
#ifdef TRAZADOR_PACKET_X86_64_V4
packet_sample_fn integrator_sample_packet_x86_64_v4, integrator_path_packet_x86_64_v4;
path_samples_fn integrator_path_samples_x86_64_v4;

/* AVX-512 F, BW, CD, DQ and VL with AVX2, FMA and BMI2 (x86-64-v4), state saved by the OS. */
static bool runs_x86_64_v4(void) {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512dq") &&
           __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx2") &&
           __builtin_cpu_supports("fma") && __builtin_cpu_supports("bmi2");
}
#endif
#ifdef TRAZADOR_PACKET_AVX2
packet_sample_fn integrator_sample_packet_avx2, integrator_path_packet_avx2;
path_samples_fn integrator_path_samples_avx2;

/* AVX2, state saved by the OS. */
static bool runs_avx2(void) {
    __builtin_cpu_init();
    return __builtin_cpu_supports("avx2");
}
#endif

static bool runs_anywhere(void) { return true; }

/* The reference build: integrator_report_sample for each lane in turn. */
static void sample_reference(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                             uint32_t sample_index, vec3 *out) {
    for (uint32_t k = 0; k < lanes; k++)
        out[k] = integrator_report_sample(p, i + k, j, sample_index);
}

/* Path mode's reference build: integrator_path_sample for each lane in turn. */
static void sample_path_reference(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                  uint32_t sample_index, vec3 *out) {
    for (uint32_t k = 0; k < lanes; k++) out[k] = integrator_path_sample(p, i + k, j, sample_index);
}

/* Path mode's reference build for runs of samples: integrator_path_sample one at a time. */
static void samples_path_reference(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                   uint32_t first, uint32_t count, vec3 *out) {
    for (uint32_t s = 0; s < count; s++)
        sample_path_reference(p, i, j, lanes, first + s, out + (size_t)s * lanes);
}

/* Every build compiled into this binary, fastest first, for report mode and for path mode (of the
 * same name), with what it needs to run. */
static const struct {
    packet_integrator build, path;
    bool (*runs)(void);
} compiled_builds[] = {
#ifdef TRAZADOR_PACKET_X86_64_V4
    {{"x86-64-v4", 16, integrator_sample_packet_x86_64_v4, NULL},
     {"x86-64-v4", TRAZADOR_PATH_LANES_X86_64_V4, integrator_path_packet_x86_64_v4,
      integrator_path_samples_x86_64_v4},
     runs_x86_64_v4},
#endif
#ifdef TRAZADOR_PACKET_AVX2
    {{"avx2", 8, integrator_sample_packet_avx2, NULL},
     {"avx2", TRAZADOR_PATH_LANES_AVX2, integrator_path_packet_avx2, integrator_path_samples_avx2},
     runs_avx2},
#endif
    {{"baseline", 8, integrator_sample_packet_baseline, NULL},
     {"baseline", TRAZADOR_PATH_LANES_BASELINE, integrator_path_packet_baseline,
      integrator_path_samples_baseline},
     runs_anywhere},
    {{RENDER_CPU_REFERENCE, 8, sample_reference, NULL},
     {RENDER_CPU_REFERENCE, 8, sample_path_reference, samples_path_reference},
     runs_anywhere},
};
#define COMPILED_BUILDS (sizeof compiled_builds / sizeof compiled_builds[0])

/* The builds of the mode (path or seed) this processor runs into list, fastest first. */
static int list_builds(bool path, packet_integrator list[PACKET_BUILDS_MAX]) {
    int n = 0;
    for (size_t k = 0; k < COMPILED_BUILDS; k++)
        if (compiled_builds[k].runs())
            list[n++] = path ? compiled_builds[k].path : compiled_builds[k].build;
    return n;
}

int integrator_path_list(packet_integrator list[PACKET_BUILDS_MAX]) {
    return list_builds(true, list);
}

int integrator_packet_list(packet_integrator list[PACKET_BUILDS_MAX]) {
    return list_builds(false, list);
}

/* The fastest build for the scene (see integrator_packet_choose) among the n of list. */
static packet_integrator fastest(const packet_integrator *list, int n, bool walks_bvh) {
    for (int k = 0; walks_bvh && k < n; k++)
        if (list[k].width <= PACKET_WALK_LANES_MAX) return list[k];
    return list[0];
}

/* The build of the mode named wanted (integrator_packet_choose, integrator_path_choose). */
static packet_integrator choose(bool path, const char *wanted, bool walks_bvh) {
    packet_integrator list[PACKET_BUILDS_MAX];
    int n = list_builds(path, list);
    const char *source = wanted ? "packet build " : "TRAZADOR_PACKET_BUILD="; /* for warnings */
    if (!wanted) wanted = getenv("TRAZADOR_PACKET_BUILD");
    if (!wanted || !*wanted) return fastest(list, n, walks_bvh);
    for (int k = 0; k < n; k++)
        if (!strcmp(list[k].name, wanted)) return list[k];
    static bool warned; /* once a run: bench renders many times */
    if (warned) return fastest(list, n, walks_bvh);
    warned = true;
    char names[64] = "";
    for (size_t k = 0; k < COMPILED_BUILDS; k++) {
        if (!strcmp(compiled_builds[k].build.name, wanted)) {
            packet_integrator used = fastest(list, n, walks_bvh);
            log_warn("%s%s: this processor cannot run that build; using %s", source, wanted,
                     used.name);
            return used;
        }
        snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", k ? ", " : "",
                 compiled_builds[k].build.name);
    }
    packet_integrator used = fastest(list, n, walks_bvh);
    log_warn("%s%s: no such build (this binary has %s); using %s", source, wanted, names,
             used.name);
    return used;
}

packet_integrator integrator_packet_choose(const char *wanted, bool walks_bvh) {
    return choose(false, wanted, walks_bvh);
}

packet_integrator integrator_path_choose(const char *wanted, bool walks_bvh) {
    return choose(true, wanted, walks_bvh);
}
