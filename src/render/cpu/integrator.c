/* integrator.c: the one-ray C walk of the one-sample integrators (integrator_sample.c): the
 * nearest hit and the shadow test, through the BVH or over every sphere, on the shared sphere
 * and box tests of shaders/common/ray.h; the GLSL walks of the same names are in
 * shaders/intersect.glsl. */
#include "render/cpu/integrator.h"

#include <math.h>
#include <string.h>

#include "common/affine.h"
#include "render/cpu/scene_accessors.h"

/* The shared text calls the accessors above (face_cut). */
#include "common/primitive.h"
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

/* Keeps in *best, *id the nearest of the hit so far and the distances t[] of primitives first,
 * first + 1, ... (nearer_hit, the tie rule). */
static inline void keep_nearest(const float *t, int first, float *best, int *id) {
    float b = *best;
    int i = *id;
    for (int lane = 0; lane < SOA_LANES; lane++) { /* selects: which lane wins is unpredictable */
        int k = first + lane;
        int take = nearer_hit(t[lane], k, b, i);
        b = take ? t[lane] : b;
        i = take ? k : i;
    }
    *best = b;
    *id = i;
}

/* Tests spheres [begin, end) (at most SOA_LANES) and keeps the nearest hit below *best. */
static inline void sphere_leaf_hit(const packed_scene *p, uint32_t begin, uint32_t end, vec3 o,
                                   vec3 d, float tmin, int self, float *best, int *id) {
    float t[SOA_LANES];
    spheres_hit(&p->sphere_soa, (int)begin, (int)end, o, d, tmin, self, t);
    keep_nearest(t, (int)begin, best, id);
}

/* Distances to triangles [begin, begin + SOA_LANES) (primitives sphere_count + begin on) into
 * t[] (triangle_distance), INFINITY past end: SIMD as spheres_hit. */
static inline void triangles_hit(const triangle_soa *tr, int begin, int end, int first_id, vec3 o,
                                 vec3 d, float tmin, int self, float *restrict t) {
    for (int lane = 0; lane < SOA_LANES; lane++) {
        int k = begin + lane;
        vec3 a = v3(tr->v[0][k], tr->v[1][k], tr->v[2][k]);
        vec3 b = v3(tr->v[3][k], tr->v[4][k], tr->v[5][k]);
        vec3 c = v3(tr->v[6][k], tr->v[7][k], tr->v[8][k]);
        float near = triangle_distance(a, b, c, o, d, tmin, first_id + k == self);
        t[lane] = k >= end ? INFINITY : near;
    }
}

/* Bit lane set where primitive first + lane is hit (at t[lane]) but cut away there (face_cut);
 * hits past best, which cannot be kept, are not looked up. Out of line, and on a copy of the
 * distances, so that the walk of scenes without cut-outs keeps them in registers. */
static __attribute__((noinline)) uint32_t faces_cut(const packed_scene *p, int first, vec3 o,
                                                    vec3 d, float best, const float *t) {
    ray_shear sh = shear_of(d);
    uint32_t cut = 0;
    for (int lane = 0; lane < SOA_LANES; lane++)
        if (t[lane] < INFINITY && t[lane] <= best &&
            face_cut(p, first + lane, corners_of(p, first + lane), o, sh))
            cut |= 1u << lane;
    return cut;
}

/* Tests triangles [begin, end) (at most SOA_LANES, by triangle index) and keeps the nearest hit
 * below *best (nearer_hit, over primitive ids: triangle t is first_id + t, sphere_count + t but
 * in an instance, whose faces are keys). */
static inline void triangle_leaf_hit(const packed_scene *p, uint32_t begin, uint32_t end,
                                     int first_id, vec3 o, vec3 d, float tmin, int self,
                                     float *best, int *id) {
    float t[SOA_LANES];
    triangles_hit(&p->triangle_soa, (int)begin, (int)end, first_id, o, d, tmin, self, t);
    if (TZ_HAS_CUTOUTS_OF(p)) {
        float copy[SOA_LANES];
        memcpy(copy, t, sizeof copy);
        /* by the faces' own ids: an instance's keys would name its corners in world space */
        uint32_t cut = faces_cut(p, (int)(p->frame.sphere_count + begin), o, d, *best, copy);
        for (int lane = 0; lane < SOA_LANES; lane++)
            t[lane] = cut >> lane & 1u ? INFINITY : t[lane];
    }
    keep_nearest(t, first_id + (int)begin, best, id);
}

static void instances_hit(const packed_scene *p, uint32_t first, uint32_t count, vec3 o, vec3 d,
                          float tmin, int self, int any_hit, float *best, int *id);

/* Tests the primitives [first, first + count) of one BVH leaf (one kind), triangles by
 * first_id (triangle_leaf_hit). */
static inline void primitive_leaf_hit(const packed_scene *p, uint32_t first, uint32_t count,
                                      int first_id, vec3 o, vec3 d, float tmin, int self,
                                      int any_hit, float *best, int *id) {
    uint32_t spheres = p->frame.sphere_count;
    if (first < spheres)
        sphere_leaf_hit(p, first, first + count, o, d, tmin, self, best, id);
    else if (p->frame.instance_count == 0 || first < p->frame.instance_leaf)
        triangle_leaf_hit(p, first - spheres, first - spheres + count, first_id, o, d, tmin, self,
                          best, id);
    else
        instances_hit(p, first, count, o, d, tmin, self, any_hit, best, id);
}

/* Rays traced by this thread, for Mrays/s (render_cpu.c sums the threads'). */
static _Thread_local uint64_t rays_traced;

uint64_t integrator_rays_traced(void) { return rays_traced; }

void integrator_count_rays(uint64_t n) { rays_traced += n; }

/* The nearest hit below *best through the tree from node root (*best its distance, *id its
 * primitive), or with any_hit the first one found; triangles numbered from first_id (an
 * instance's model walks with its ray in the model's space). Nearer child first, a stack of
 * TZ_BVH_MAX_DEPTH child references (each level pushes at most one), each leaf's primitives tested
 * at once. Always inlined, so that it is compiled into each of trace_ray's SIMD clones. */
static inline __attribute__((always_inline)) void walk_bvh(const packed_scene *p, uint32_t root,
                                                           int first_id, vec3 o, vec3 d, float tmin,
                                                           int self, int any_hit, float *best_io,
                                                           int *id_io) {
    float best = *best_io;
    int id = *id_io;
    vec3 inv = inverse_direction(d);
    uint32_t stack[TZ_BVH_MAX_DEPTH];
    float stack_t[TZ_BVH_MAX_DEPTH];
    int top = 0;
    uint32_t ref = root;
    for (;;) {
        uint32_t leaf = child_count(ref), first = child_index(ref);
        if (leaf > 0) {
            primitive_leaf_hit(p, first, leaf, first_id, o, d, tmin, self, any_hit, &best, &id);
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
    *best_io = best;
    *id_io = id;
}

/* The instances [first, first + count) of a leaf (ids from frame.instance_leaf): each walks its
 * model's tree with the ray moved into its space (never by an identity: a flattened copy's bits),
 * its faces numbered by their keys. Out of line: trace_bvh's clones share it. */
static __attribute__((noinline)) void instances_hit(const packed_scene *p, uint32_t first,
                                                    uint32_t count, vec3 o, vec3 d, float tmin,
                                                    int self, int any_hit, float *best, int *id) {
    for (uint32_t k = first - p->frame.instance_leaf; count-- > 0 && !(any_hit && *id >= 0); k++) {
        const struct gpu_instance *in = &p->instances[k];
        vec3 mo = o, md = d;
        if (!in->model.z) {
            mo = affine_point(in->to_object[0], in->to_object[1], in->to_object[2], o);
            md = affine_direction(in->to_object[0], in->to_object[1], in->to_object[2], d);
        }
        int first_id = TZ_INSTANCE_KEY + (int)(k << p->frame.instance_shift) - (int)in->model.y;
        walk_bvh(p, in->model.x, first_id, mo, md, tmin, self, any_hit, best, id);
    }
}

void integrator_instances_hit(const packed_scene *p, uint32_t first, uint32_t count, vec3 o, vec3 d,
                              int self, int any_hit, float *best, int *id) {
    instances_hit(p, first, count, o, d, ray_eps(o), self, any_hit, best, id);
}

/* Nearest hit below tmax through the BVH (*t its distance), or with any_hit the first one found;
 * -1 when none (walk_bvh from the root). */
static inline __attribute__((always_inline)) int trace_bvh(const packed_scene *p, vec3 o, vec3 d,
                                                           int self, float tmax, int any_hit,
                                                           float *t) {
    float best = tmax;
    int id = -1;
    walk_bvh(p, 0, (int)p->frame.sphere_count, o, d, ray_eps(o), self, any_hit, &best, &id);
    *t = best;
    return id;
}

/* integrator_trace: through the BVH (trace_bvh), or over every sphere SOA_LANES at a time when
 * there is none or the scene is as small as the packets test whole (the tie rule makes both
 * find the same hit). */
SIMD_CLONES static int trace_ray(const packed_scene *p, vec3 o, vec3 d, int self, float tmax,
                                 int any_hit, float *t) {
    uint32_t count = p->frame.sphere_count, triangles = p->frame.triangle_count;
    if (integrator_packet_walks(p)) return trace_bvh(p, o, d, self, tmax, any_hit, t);
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    for (uint32_t begin = 0; begin < count && !(any_hit && id >= 0); begin += SOA_LANES)
        sphere_leaf_hit(p, begin, begin + SOA_LANES < count ? begin + SOA_LANES : count, o, d, tmin,
                        self, &best, &id);
    for (uint32_t begin = 0; begin < triangles && !(any_hit && id >= 0); begin += SOA_LANES)
        triangle_leaf_hit(p, begin, begin + SOA_LANES < triangles ? begin + SOA_LANES : triangles,
                          (int)count, o, d, tmin, self, &best, &id);
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
