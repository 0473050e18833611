/* integrator.h: the integrators of DESIGN section 3 in C: one sample at a time (the
 * "reference" build, the oracle the packet builds and the Vulkan back end are checked against)
 * and the packet builds the CPU back end renders with. */
#ifndef TRAZADOR_INTEGRATOR_H
#define TRAZADOR_INTEGRATOR_H

#include <stdbool.h>
#include <stdint.h>

#include "render/scene_pack.h"

/* Radiance of report-mode sample `sample_index` of pixel (i, j), i to the right and j down;
 * never fails. */
vec3 integrator_report_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index);

/* Radiance of path-mode sample `sample_index` of pixel (i, j) (DESIGN section 3.2); never fails.
 */
vec3 integrator_path_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index);

/* A sample's first-hit features (shaders/common/aov.h): hit false on a miss, the others zero. */
typedef struct integrator_aov {
    vec3 albedo, normal, position, emission;
    float depth;
    bool hit;
} integrator_aov;

/* The first-hit features of sample `sample_index` of pixel (i, j) (aov_sample); never fails. */
integrator_aov integrator_aov_sample(const packed_scene *p, uint32_t i, uint32_t j,
                                     uint32_t sample_index);

/* The widest packet of any packet integrator. */
#define PACKET_LANES_MAX 16
/* The most packet integrators a build has, the one-sample reference included. */
#define PACKET_BUILDS_MAX 4

/* A build of the packet integrator (src/render/cpu/integrator_packet.c) for one vector level:
 * sample(p, i, j, lanes, sample_index, out) sets out[k] = integrator_report_sample(p, i + k, j,
 * sample_index) for k < lanes (<= width), bit for bit, computing all of them at once; never fails.
 */
typedef struct packet_integrator {
    const char *name; /* its vector level, e.g. "x86-64-v4" */
    uint32_t width;
    void (*sample)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                   uint32_t sample_index, vec3 *out);
    /* Path builds only (else NULL): samples(p, i, j, lanes, first, count, out) sets
     * out[s * lanes + k] = integrator_path_sample(p, i + k, j, first + s) for k < lanes (<=
     * width), s < count, bit for bit, keeping every lane busy until the last samples. */
    void (*samples)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes, uint32_t first,
                    uint32_t count, vec3 *out);
} packet_integrator;

/* Scenes of at most this many primitives are intersected packet against every one; bigger ones
 * through the BVH. */
#define PACKET_BRUTE_FORCE_MAX 16
/* The widest packet that walks the BVH well: wider packets drag more lanes through nodes only
 * some of them enter (docs/PERF.md, "Integrator and shaders"), while they win where every sphere
 * is tested. */
#define PACKET_WALK_LANES_MAX 8

/* 1 when the packet integrators walk the BVH for this scene (it has one and more than
 * PACKET_BRUTE_FORCE_MAX primitives), 0 when they test every one; never fails. */
static inline int integrator_packet_walks(const packed_scene *p) {
    return p->frame.node_count > 0 &&
           (p->frame.sphere_count + p->frame.triangle_count > PACKET_BRUTE_FORCE_MAX ||
            p->frame.instance_count > 0);
}

/* The packet integrators this processor runs into list, fastest first (the reference last);
 * returns how many (>= 2). */
int integrator_packet_list(packet_integrator list[PACKET_BUILDS_MAX]);
/* The build named `wanted`, or when NULL the one TRAZADOR_PACKET_BUILD names, or the fastest
 * for the scene: the first listed, or with walks_bvh the first of at most PACKET_WALK_LANES_MAX
 * lanes; never fails (warns, falls back to the fastest). */
packet_integrator integrator_packet_choose(const char *wanted, bool walks_bvh);
/* The path-mode builds (src/render/cpu/integrator_path_packet.c: sample(p, i, j, lanes,
 * sample_index, out) sets out[k] = integrator_path_sample(p, i + k, j, sample_index) bit for bit)
 * this processor runs into list, fastest first (the reference last); returns how many (>= 2). */
int integrator_path_list(packet_integrator list[PACKET_BUILDS_MAX]);
/* The path-mode build named `wanted` (the names of integrator_packet_choose), chosen as that
 * chooses; never fails (warns, falls back to the fastest). */
packet_integrator integrator_path_choose(const char *wanted, bool walks_bvh);

/* Nearest sphere hit by the ray o + t d (|d| = 1) with t > EPS, -1 on a miss; `self` is the
 * sphere the ray leaves (-1 for none): its near root is the ray's own origin and is ignored. */
int integrator_nearest(const packed_scene *p, vec3 o, vec3 d, int self, float *t_out);
/* Nearest sphere hit below tmax (*t its distance), or with any_hit the first one found; -1 when
 * none. Through the BVH when the scene has one, else over every sphere; counts no ray. */
int integrator_trace(const packed_scene *p, vec3 o, vec3 d, int self, float tmax, int any_hit,
                     float *t);
/* Tests instances [first, first + count) (BVH leaf ids from frame.instance_leaf) against the ray
 * o + t d leaving self, keeping in *best, *id the nearest hit below *best (or with any_hit the
 * first found), as integrator_trace's walk does; counts no ray. */
void integrator_instances_hit(const packed_scene *p, uint32_t first, uint32_t count, vec3 o, vec3 d,
                              int self, int any_hit, float *best, int *id);
/* Rays (nearest-hit and shadow) the calling thread has traced so far, counted by
 * integrator_nearest, integrator_occluded and integrator_count_rays; never fails. */
uint64_t integrator_rays_traced(void);
/* Adds n rays to the calling thread's count; never fails. */
void integrator_count_rays(uint64_t n);
/* 1 when a sphere (glass too, as in the course report) blocks o + t d for EPS < t < dist, else 0;
 * never fails. */
int integrator_occluded(const packed_scene *p, vec3 o, vec3 d, float dist, int self);

#endif
