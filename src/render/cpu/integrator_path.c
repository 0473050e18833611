/* integrator_path.c: path mode (DESIGN section 3.2) in C, one sample at a time: the scene
 * accessors that shaders/common/path.h asks of its includer, over the packed scene; the GLSL back
 * end provides the same names (shaders/trace.comp). */
#include "render/cpu/integrator.h"

static inline tz_vec4 sphere_center_radius(const packed_scene *p, int k) {
    return p->spheres[k].center_radius;
}
static inline tz_vec4 sphere_color_ks(const packed_scene *p, int k) {
    return p->spheres[k].color_ks;
}
static inline tz_vec4 sphere_params(const packed_scene *p, int k) { return p->spheres[k].params; }
static inline tz_vec4 light_position_power(const packed_scene *p, int k) {
    return p->lights[k].position_power;
}
static inline tz_vec4 light_color(const packed_scene *p, int k) { return p->lights[k].color; }
static inline uint32_t light_count(const packed_scene *p) { return p->frame.light_count; }
static inline tz_vec4 emitter_emission_pick(const packed_scene *p, int e) {
    return p->emitters[e].emission_pick;
}
static inline tz_vec4 emitter_sphere_cdf(const packed_scene *p, int e) {
    return p->emitters[e].sphere_cdf;
}

#include "common/path.h"

vec3 integrator_path_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index) {
    return path_sample(p, i, j, sample_index);
}
