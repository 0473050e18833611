/* integrator.c: the one-ray C walk of the one-sample integrators (integrator_sample.c): the
 * nearest hit and the shadow test, through the BVH or over every sphere, on the shared sphere
 * and box tests of shaders/common/ray.h; the GLSL walks of the same names are in
 * shaders/intersect.glsl. */
#include "render/cpu/integrator.h"

#include <math.h>

#include "common/ray.h"
#include "common/rng.h"
#include "common/shade.h"
#include "render/cpu/simd_clones.h"

/* Distances to spheres [begin, begin + SOA_LANES) into t[] (sphere_distance), INFINITY past
 * end: a fixed trip count over the padded structure-of-arrays, so it compiles to 8-wide SIMD. */
static inline void spheres_hit(const sphere_soa *sp, int begin, int end, vec3 o, vec3 d, float tmin,
                               int self, float *restrict t) {
    for (int lane = 0; lane < SOA_LANES; lane++) {
        int k = begin + lane;
        float near =
            sphere_distance(sp->cx[k], sp->cy[k], sp->cz[k], sp->r[k], o, d, tmin, k == self);
        t[lane] = k >= end ? INFINITY : near;
    }
}

/* Tests spheres [begin, end) (at most SOA_LANES) and keeps the nearest hit below *best
 * (nearer_hit, the tie rule). */
static inline void leaf_hit(const packed_scene *p, uint32_t begin, uint32_t end, vec3 o, vec3 d,
                            float tmin, int self, float *best, int *id) {
    float t[SOA_LANES];
    spheres_hit(&p->soa, (int)begin, (int)end, o, d, tmin, self, t);
    float b = *best;
    int i = *id;
    for (int lane = 0; lane < SOA_LANES; lane++) { /* selects: which lane wins is unpredictable */
        int k = (int)begin + lane;
        int take = nearer_hit(t[lane], k, b, i);
        b = take ? t[lane] : b;
        i = take ? k : i;
    }
    *best = b;
    *id = i;
}

/* Rays traced by this thread, for Mrays/s (render_cpu sums the threads'). */
static _Thread_local uint64_t rays_traced;

uint64_t integrator_rays_traced(void) { return rays_traced; }

void integrator_count_rays(uint64_t n) { rays_traced += n; }

/* Nearest sphere hit below tmax through the BVH (*t its distance), or with any_hit the first one
 * found; -1 when none. Nearer child first, a stack of TZ_BVH_MAX_DEPTH child references (each
 * level pushes at most one), each leaf's spheres tested at once. Always inlined, so that it is
 * compiled into each of trace_ray's SIMD clones. */
static inline __attribute__((always_inline)) int trace_bvh(const packed_scene *p, vec3 o, vec3 d,
                                                           int self, float tmax, int any_hit,
                                                           float *t) {
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    vec3 inv = inverse_direction(d);
    uint32_t stack[TZ_BVH_MAX_DEPTH];
    float stack_t[TZ_BVH_MAX_DEPTH];
    int top = 0;
    uint32_t ref = 0; /* the root */
    for (;;) {
        uint32_t leaf = child_count(ref), first = child_index(ref);
        if (leaf > 0) {
            leaf_hit(p, first, first + leaf, o, d, tmin, self, &best, &id);
            if (any_hit && id >= 0) break;
        } else {
            const struct gpu_bvh_node *n = &p->nodes[first];
            float tl = box_entry(n->left_lo, n->left_hi, o, inv, best);
            float tr = box_entry(n->right_lo, n->right_hi, o, inv, best);
            if (tl < INFINITY || tr < INFINITY) {
                int left_first = tl <= tr;
                uint32_t left = uint_bits(n->left_lo.w), right = uint_bits(n->right_lo.w);
                ref = left_first ? left : right;
                float other_t = left_first ? tr : tl;
                if (other_t < INFINITY) {
                    stack[top] = left_first ? right : left;
                    stack_t[top++] = other_t;
                }
                continue;
            }
        }
        int go = 0; /* pop the nearest pending child that can still hold a nearer hit */
        while (top > 0 && !go) {
            top--;
            ref = stack[top];
            go = stack_t[top] < best;
        }
        if (!go) break;
    }
    *t = best;
    return id;
}

/* integrator_trace: through the BVH (trace_bvh), or over every sphere SOA_LANES at a time when
 * there is none or the scene is as small as the packets test whole (the tie rule makes both
 * find the same hit). */
SIMD_CLONES static int trace_ray(const packed_scene *p, vec3 o, vec3 d, int self, float tmax,
                                 int any_hit, float *t) {
    if (p->frame.node_count > 0 && p->frame.sphere_count > PACKET_BRUTE_FORCE_MAX)
        return trace_bvh(p, o, d, self, tmax, any_hit, t);
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    uint32_t count = p->frame.sphere_count;
    for (uint32_t begin = 0; begin < count && !(any_hit && id >= 0); begin += SOA_LANES)
        leaf_hit(p, begin, begin + SOA_LANES < count ? begin + SOA_LANES : count, o, d, tmin, self,
                 &best, &id);
    *t = best;
    return id;
}

int integrator_trace(const packed_scene *p, vec3 o, vec3 d, int self, float tmax, int any_hit,
                     float *t) {
    return trace_ray(p, o, d, self, tmax, any_hit, t);
}

int integrator_nearest(const packed_scene *p, vec3 o, vec3 d, int self, float *t_out) {
    rays_traced++;
    return integrator_trace(p, o, d, self, INFINITY, 0, t_out);
}

int integrator_occluded(const packed_scene *p, vec3 o, vec3 d, float dist, int self) {
    float t;
    rays_traced++;
    return integrator_trace(p, o, d, self, dist, 1, &t) >= 0;
}
