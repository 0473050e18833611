/* scene_accessors.h: the scene accessors that the shared integrators (shaders/common/report.h and
 * path.h) ask of their includer, over the packed scene, for the C integrators; the GLSL back end
 * provides the same names (shaders/trace.comp). */
#ifndef TRAZADOR_SCENE_ACCESSORS_H
#define TRAZADOR_SCENE_ACCESSORS_H

#include "render/cpu/integrator.h"

static inline tz_vec4 sphere_center_radius(const packed_scene *p, int k) {
    return p->spheres[k].center_radius;
}
/* The material fields as the shared text reads them: color_ks, and params x alpha, y ior, z the
 * kind and w (a sphere's) its emitter + 1. */
static inline tz_vec4 material_params(const packed_scene *p, int m) {
    const struct gpu_material *g = &p->materials[m];
    return (tz_vec4){g->alpha, g->ior, g->kind, g->reserved0};
}
static inline tz_vec4 sphere_color_ks(const packed_scene *p, int k) {
    return p->materials[(int)p->spheres[k].material].color_ks;
}
static inline tz_vec4 sphere_params(const packed_scene *p, int k) {
    const struct gpu_sphere *s = &p->spheres[k];
    tz_vec4 params = material_params(p, (int)s->material);
    params.w = s->emitter;
    return params;
}
static inline tz_vec4 triangle_v0(const packed_scene *p, int t) { return p->triangles[t].v0; }
static inline tz_vec4 triangle_v1(const packed_scene *p, int t) { return p->triangles[t].v1; }
static inline tz_vec4 triangle_v2(const packed_scene *p, int t) { return p->triangles[t].v2; }
static inline tz_vec4 material_color_ks(const packed_scene *p, int m) {
    return p->materials[m].color_ks;
}
static inline tz_uvec4 material_maps(const packed_scene *p, int m) { return p->materials[m].maps; }
static inline int sphere_material_index(const packed_scene *p, int k) {
    return (int)p->spheres[k].material;
}
static inline uint32_t texture_word(const packed_scene *p, uint32_t i) {
    return p->texture_words[i];
}
static inline tz_vec4 normals_n0(const packed_scene *p, int s) { return p->normals[s].n0; }
static inline tz_vec4 normals_n1(const packed_scene *p, int s) { return p->normals[s].n1; }
static inline tz_vec4 normals_n2(const packed_scene *p, int s) { return p->normals[s].n2; }
static inline tz_vec4 light_position_power(const packed_scene *p, int k) {
    return p->lights[k].position_power;
}
static inline tz_vec4 light_color(const packed_scene *p, int k) { return p->lights[k].color; }
static inline tz_vec4 light_shape(const packed_scene *p, int k) { return p->lights[k].shape; }
static inline uint32_t light_count(const packed_scene *p) { return p->frame.light_count; }
static inline tz_vec4 instance_to_object(const packed_scene *p, int i, int r) {
    return p->instances[i].to_object[r];
}
static inline tz_vec4 instance_to_world(const packed_scene *p, int i, int r) {
    return p->instances[i].to_world[r];
}
static inline tz_uvec4 instance_model(const packed_scene *p, int i) {
    return p->instances[i].model;
}
static inline tz_vec4 emitter_emission_pick(const packed_scene *p, int e) {
    return p->emitters[e].emission_pick;
}
static inline tz_vec4 emitter_primitive_cdf(const packed_scene *p, int e) {
    return p->emitters[e].primitive_cdf;
}
/* Texel k of the environment map and float k of its sampling tables (TZ_BINDING_ENVIRONMENT). */
static inline tz_vec4 environment_texel(const packed_scene *p, int k) { return p->environment[k]; }
static inline float environment_float(const packed_scene *p, int k) {
    size_t map = (size_t)p->frame.env_width * p->frame.env_height;
    return ((const float *)(p->environment + map))[k];
}

#endif
