/* vk_probe.c: bounds the loop work of one trace.comp sample, as lavapipe counts it. */
#include "render/vk/vk_probe.h"

uint64_t vk_probe_sample_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                    bool indirect) {
    /* lavapipe spends one unit per pass of any loop, the pass that leaves the loop included. A
     * ray costs a pass per sphere, the sphere loop's exit pass and the pass of the loop that
     * casts it. A path casts at most bounces + 1 rays in follow_specular and one shadow ray per
     * light in direct_light, whose loop adds its exit pass; the indirect bounce is a second
     * path; main()'s sample loop adds a pass per sample. */
    uint64_t per_ray = (uint64_t)sphere_count + 2u;
    uint64_t path = ((uint64_t)bounces + 1u + light_count) * per_ray + 1u;
    return path * (indirect ? 2u : 1u) + 1u;
}

uint64_t vk_probe_path_iterations(uint32_t sphere_count, uint32_t light_count, uint32_t bounces,
                                  uint32_t emitter_count) {
    /* A ray costs as in seed mode. The path loop runs a pass a vertex (bounces + 1, and one
     * spare); a diffuse vertex adds its light loop's passes and exit pass, the binary search's
     * passes (ceil(log2(emitters)) and its exit) and the emitter's shadow ray. */
    uint64_t per_ray = (uint64_t)sphere_count + 2u;
    uint32_t search = 1u;
    while (emitter_count > 1u && (1u << (search - 1u)) < emitter_count && search < 32u) search++;
    uint64_t vertex = ((uint64_t)light_count + (emitter_count ? 1u : 0u)) * per_ray + 1u + search;
    return ((uint64_t)bounces + 2u) + ((uint64_t)bounces + 1u) * per_ray +
           (uint64_t)bounces * vertex + 1u;
}
