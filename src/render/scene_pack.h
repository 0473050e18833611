/* scene_pack.h: struct scene + render options -> the flat GPU layout both back ends consume. */
#ifndef TRAZADOR_SCENE_PACK_H
#define TRAZADOR_SCENE_PACK_H

#include "render/render.h"
#include "shared_layout.h"

#define SOA_LANES 8

/* Sphere centres and radii as separate arrays, each padded with zeros to a multiple of
 * SOA_LANES: the C integrator tests 8 spheres at a time. */
typedef struct sphere_soa {
    float *cx, *cy, *cz, *r;
} sphere_soa;

/* Triangle corners as separate arrays (corner k of triangle t at v[3 * k + axis][t]), padded as
 * sphere_soa: the C integrator tests 8 triangles at a time. */
typedef struct triangle_soa {
    float *v[9];
} triangle_soa;

typedef struct packed_scene {
    struct gpu_frame frame;
    struct gpu_sphere *spheres;
    struct gpu_triangle *triangles; /* frame.triangle_count, one zeroed when none */
    struct gpu_material *materials; /* the scene's materials, one zeroed when none */
    struct gpu_normals *normals;    /* the smooth triangles' normals, one zeroed when none */
    uint32_t material_count, normals_count;
    uint32_t *texture_words; /* the texture table (TZ_TEXTURE_*), one zeroed word without any */
    size_t texture_word_count;
    struct gpu_light *lights;
    sphere_soa sphere_soa;          /* the C back end's copy of spheres[].center_radius */
    triangle_soa triangle_soa;      /* and of triangles[]' corners */
    struct gpu_bvh_node *nodes;     /* frame.node_count of them; NULL (0) without a BVH */
    struct gpu_emitter *emitters;   /* frame.emitter_count (path mode), one zeroed when none */
    struct gpu_instance *instances; /* frame.instance_count, NULL when none */
    tz_vec4 *environment;           /* TZ_BINDING_ENVIRONMENT's texels, one zeroed without a map */
    uint32_t environment_texels;
    uint32_t bvh_depth;
    double bvh_seconds; /* build time */
} packed_scene;

/* The environment map's texels and sampling tables (TZ_BINDING_ENVIRONMENT) into out and its
 * mean radiance over the sphere of directions (the mean of its channels) into *mean; false
 * (logged) on out-of-memory (environment_pack.c). */
bool environment_pack(const environment_map *m, packed_scene *out, double *mean);

/* v with w as a vec4 of the shaders' structs. */
static inline tz_vec4 vec4_from(vec3 v, float w) { return (tz_vec4){v.x, v.y, v.z, w}; }

/* A sun with a disc in path mode: an emitter of this radiance and power (0: none). */
typedef struct sun_disc {
    vec3 radiance;
    double power;
} sun_disc;
/* Packs the scene's lights into out->lights (allocated by scene_pack) and frame.light_count,
 * TZ_FLAG_SHAPED_LIGHTS when a spot or a sun is among them; in path mode a sun with a disc is
 * left out for an emitter: frame.sun and TZ_FLAG_SUN_DISC set, and its radiance and power
 * (its flux through the disc of the scene's radius, in the environment's unit) returned
 * (light_pack.c). */
sun_disc lights_pack(const scene *s, bool path_mode, double scene_radius, packed_scene *out);
/* The radius of a sphere about the scene's box (1 for an empty scene), in double: the
 * environment's and the sun's powers are those of their light through the disc of that radius
 * (emitter_pack.c). */
double emitter_scene_radius(const scene *s);
/* Path mode's emitter table into out->emitters (emitter_pack.c: spheres, faces in BVH order by
 * triangle_source, the environment of power env_power, the sun's disc), each emitting
 * primitive's slot + 1 written back; false (logged) out of memory. */
bool emitters_pack(packed_scene *out, const scene *sc, bool path_mode,
                   const uint32_t *triangle_source, double env_power, const sun_disc *sun);
/* Packs the scene with the options applied, spheres in BVH order unless opts->no_bvh;
 * false (logged) on out-of-memory. */
bool scene_pack(const scene *s, const render_opts *opts, packed_scene *out);
/* The texture table of s (texture_pack.c) into out->texture_words, after the triangles are
 * packed (their UVs follow the gpu_normals indices); false (logged) out of memory or past the
 * 2^32 words the shaders address. */
bool texture_pack(const scene *s, packed_scene *out);
/* Fills the first `spheres` spheres of out (gpu_unrolled's layout) from p; never fails. */
void scene_pack_unrolled(const packed_scene *p, uint32_t spheres, struct gpu_unrolled *out);
/* Records the packing's figures (time since pack_start, BVH, sizes) into opts->stats if any;
 * never fails. */
void scene_pack_report(const packed_scene *p, const render_opts *opts, double pack_start);
/* Frees the packed arrays; safe on a zeroed packed_scene. */
void scene_pack_free(packed_scene *p);

#endif
