/* integrator.c: the one-sample C integrator (DESIGN section 3), the "reference" build that
 * test_packet checks the packet builds against. Its steps are the shared ones of
 * shaders/common/; its control flow has a GLSL counterpart of the same name in
 * shaders/intersect.glsl and shade.glsl (change both and a test in one commit). */
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

/* The Phong BRDF of sphere s (phong_brdf). */
static vec3 sphere_brdf(const struct gpu_sphere *s, vec3 n, vec3 wi, vec3 wo) {
    return phong_brdf(xyz(s->color_ks), s->color_ks.w, s->params.x, n, wi, wo);
}

/* Direct light from every point light at p (shading normal n, facing wo) on sphere id. */
static vec3 direct_light(const packed_scene *p, int id, vec3 pos, vec3 n, vec3 wo) {
    vec3 o = offset_origin(pos, n);
    vec3 sum = v3(0.0f, 0.0f, 0.0f);
    for (uint32_t k = 0; k < p->frame.light_count; k++) {
        light_sample l = point_light(p->lights[k].position_power, p->lights[k].color, pos, n);
        if (l.cos_i <= 0.0f || integrator_occluded(p, o, l.wi, l.dist, id)) continue;
        sum = v3_add(sum, v3_mul(sphere_brdf(&p->spheres[id], n, l.wi, wo), l.radiance));
    }
    return sum;
}

/* Follows a ray through mirrors and glass to a diffuse hit. Returns the sphere id (-1 on a miss,
 * -2 when the chain exceeds the bounce limit); *o, *d become the last ray, *weight the tints. */
static int follow_specular(const packed_scene *p, vec3 *o, vec3 *d, int self, vec3 *weight,
                           vec3 *pos, vec3 *n) {
    uint32_t bounces = p->frame.bounces;
    for (uint32_t chain = 0;; chain++) {
        float t;
        int id = integrator_nearest(p, *o, *d, self, &t);
        if (id < 0) return -1;
        const struct gpu_sphere *s = &p->spheres[id];
        *pos = v3_add(*o, v3_scale(*d, t));
        vec3 nout = v3_scale(v3_sub(*pos, xyz(s->center_radius)), 1.0f / s->center_radius.w);
        int material = (int)s->params.z;
        if (material == TZ_MATERIAL_LAMBERTIAN || material == TZ_MATERIAL_PHONG) {
            *n = facing_normal(nout, *d);
            return id;
        }
        if (chain == bounces) return -2;
        *weight = v3_mul(*weight, xyz(s->color_ks));
        next_ray next =
            specular_next(*pos, nout, *d, material == TZ_MATERIAL_REFRACTIVE, s->params.y);
        *o = next.o;
        *d = next.d;
        self = id;
    }
}

/* Radiance arriving along a ray: background on a miss, black past the bounce limit, else the
 * direct light of the diffuse surface it reaches through mirrors and glass, times their tints. */
static vec3 radiance_direct_only(const packed_scene *p, vec3 o, vec3 d, int self) {
    vec3 weight = v3(1.0f, 1.0f, 1.0f), pos, n;
    int id = follow_specular(p, &o, &d, self, &weight, &pos, &n);
    if (id == -1) return v3_mul(weight, xyz(p->frame.background));
    if (id == -2) return v3(0.0f, 0.0f, 0.0f);
    return v3_mul(weight, direct_light(p, id, pos, n, v3_scale(d, -1.0f)));
}

/* One cosine-weighted bounce at a diffuse hit: theta = acos(sqrt(1 - y1)), phi = 2 pi y2,
 * pdf = cos(theta) / pi; returns f_r * L_direct * cos / pdf. */
static vec3 indirect_light(const packed_scene *p, int id, vec3 pos, vec3 n, vec3 wo,
                           uint32_t *rng) {
    float y1 = rng_next(rng), y2 = rng_next(rng);
    float cos_t = sqrtf(1.0f - y1), phi = 2.0f * TZ_PI * y2;
    vec3 wi = cosine_direction(n, y1, cosf(phi), sinf(phi));
    vec3 o = offset_origin(pos, n);
    vec3 incoming = radiance_direct_only(p, o, wi, id);
    float pdf = cos_t / TZ_PI;
    vec3 f = sphere_brdf(&p->spheres[id], n, wi, wo);
    return v3_mul(f, v3_scale(incoming, cos_t / pdf));
}

vec3 integrator_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index) {
    const struct gpu_frame *fr = &p->frame;
    uint32_t rng = rng_seed(fr->seed, j * fr->width + i, sample_index);
    /* Both jitter numbers are always drawn so the indirect numbers do not depend on the flag. */
    float u = rng_next(&rng), v = rng_next(&rng);
    if (!(fr->flags & TZ_FLAG_JITTER)) u = v = 0.5f;
    vec3 d = camera_direction(fr->right, fr->up, fr->forward, fr->origin.w, i, j, u, v);
    vec3 o = camera_origin(fr->origin, fr->near_distance, d);
    vec3 weight = v3(1.0f, 1.0f, 1.0f), pos, n;
    int id = follow_specular(p, &o, &d, -1, &weight, &pos, &n);
    if (id == -1) return v3_mul(weight, xyz(fr->background));
    if (id == -2) return v3(0.0f, 0.0f, 0.0f);
    vec3 wo = v3_scale(d, -1.0f);
    vec3 radiance = direct_light(p, id, pos, n, wo);
    if (fr->flags & TZ_FLAG_INDIRECT)
        radiance = v3_add(radiance, indirect_light(p, id, pos, n, wo, &rng));
    return v3_mul(weight, radiance);
}
