/* integrator_packet.c: the C integrator over a packet of PACKET_LANES samples at once (the same
 * sample of a run of pixels in one row). Each lane does the very operations of integrator.c,
 * through the shared steps of shaders/common/, so the images are bit-identical to it (tested);
 * the loops over lanes compile to SIMD, the lanes' diverging paths become selects. */
#include <math.h>
#include <string.h>

#include "common/ray.h"
#include "common/rng.h"
#include "common/shade.h"
#include "render/cpu/integrator.h"

/* Built once per vector level (CMakeLists.txt): PACKET_LANES lanes, the entry point named
 * integrator_sample_packet_<PACKET_VARIANT>; src/render/cpu/integrator_dispatch.c picks one at run
 * time. */
#ifndef PACKET_LANES
#define PACKET_LANES 8
#define PACKET_VARIANT baseline
#endif
#define LANES PACKET_LANES
#define PACKET_ENTRY_NAME(variant) integrator_sample_packet_##variant
#define PACKET_ENTRY(variant) PACKET_ENTRY_NAME(variant)
/* A packet's active lanes walk the BVH together when there are at least this many (fewer walk it
 * one by one): three eighths of the lanes for nearest hits, 2 for shadow rays, which converge on
 * their light and end at the first blocker (the thresholds were measured: docs/PERF.md).
 * Lanes of every direction walk together: split by the octant of their directions, the
 * cosine-distributed bounce rays made groups too small to walk together. */
#define WALK_GROUP_MIN (LANES * 3 / 8)
#define SHADOW_WALK_GROUP_MIN 2

/* The whole packet path is inlined into its entry point. */
#define LANE_FN static inline __attribute__((always_inline))

/* One vec3 per lane, structure of arrays. */
typedef struct lanes3 {
    float x[LANES], y[LANES], z[LANES];
} lanes3;

LANE_FN vec3 get3(const lanes3 *a, int k) { return v3(a->x[k], a->y[k], a->z[k]); }

LANE_FN void set3(lanes3 *a, int k, vec3 v) {
    a->x[k] = v.x;
    a->y[k] = v.y;
    a->z[k] = v.z;
}

/* Vector registers of PACKET_LANES floats and ints (GCC and clang vector extensions). */
typedef float float_lanes __attribute__((vector_size(LANES * sizeof(float))));
typedef int32_t int_lanes __attribute__((vector_size(LANES * sizeof(int32_t))));

/* best, id = ts, s in the lanes where take has all bits set. */
LANE_FN void blend_hits(float_lanes *best, int_lanes *id, const float_lanes *ts,
                        const int_lanes *take, int s) {
    *best = (float_lanes)(((int_lanes)*ts & *take) | ((int_lanes)*best & ~*take));
    *id = (*id & ~*take) | (s & *take);
}

/* best[k], id[k] = ts[k], s where ts[k] < best[k]: sphere s is nearer than the hit so far (spheres
 * must come in increasing order for the tie rule to hold). In vector registers: the equivalent
 * loop over lanes compiles to masked stores, whose reloads stall the next sphere's update. */
LANE_FN void keep_nearer_in_order(float *best, int *id, const float *ts, int s) {
    float_lanes b, t;
    int_lanes i;
    memcpy(&b, best, sizeof b);
    memcpy(&t, ts, sizeof t);
    memcpy(&i, id, sizeof i);
    int_lanes nearer = t < b;
    blend_hits(&b, &i, &t, &nearer, s);
    memcpy(best, &b, sizeof b);
    memcpy(id, &i, sizeof i);
}

/* keep_nearer_in_order with the whole tie rule (nearer_hit): sphere s also wins a tie with a
 * higher index, so the order of a walk's leaves cannot change the hit (keep_nearer of
 * shaders/intersect.glsl). The rule is taken lane by lane: as one
 * vector expression gcc 12 scalarizes the loops around it. */
LANE_FN void keep_nearer(float *best, int *id, const float *ts, int s) {
    int32_t takes[LANES];
    for (int k = 0; k < LANES; k++) takes[k] = -nearer_hit(ts[k], s, best[k], id[k]);
    float_lanes b, t;
    int_lanes i, take;
    memcpy(&b, best, sizeof b);
    memcpy(&t, ts, sizeof t);
    memcpy(&i, id, sizeof i);
    memcpy(&take, takes, sizeof take);
    blend_hits(&b, &i, &t, &take, s);
    memcpy(best, &b, sizeof b);
    memcpy(id, &i, sizeof i);
}

/* The smallest of the lanes' values, as a tree of halvings: the chain of LANES - 1 minimums of a
 * plain loop lay on the walk's critical path. */
LANE_FN float lanes_min(const float *values) {
    float m[LANES];
    memcpy(m, values, sizeof m);
    for (int half = LANES / 2; half > 0; half /= 2)
        for (int k = 0; k < half; k++) m[k] = m[k + half] < m[k] ? m[k + half] : m[k];
    return m[0];
}

LANE_FN int any_lane(const int *mask) {
    int any = 0;
    for (int k = 0; k < LANES; k++) any |= mask[k];
    return any;
}

/* Tests sphere s against every lane's ray, keeping the nearest hits in best and id (the tie rule
 * too with tie; without, spheres must come in increasing order). */
LANE_FN void packet_sphere(const packed_scene *p, uint32_t s, const lanes3 *o, const lanes3 *d,
                           const int *self, const float *tmin, int tie, float *best, int *id) {
    float cx = p->soa.cx[s], cy = p->soa.cy[s], cz = p->soa.cz[s], r = p->soa.r[s], ts[LANES];
    for (int k = 0; k < LANES; k++)
        ts[k] = sphere_distance(cx, cy, cz, r, get3(o, k), get3(d, k), tmin[k], (int)s == self[k]);
    if (tie)
        keep_nearer(best, id, ts, (int)s);
    else
        keep_nearer_in_order(best, id, ts, (int)s);
}

/* 1 when every active lane has a hit. */
LANE_FN int all_hit(const int *id, const int *active) {
    int all = 1;
    for (int k = 0; k < LANES; k++) all &= !active[k] | (id[k] >= 0);
    return all;
}

/* The whole packet walks the BVH, as integrator_trace walks it with one ray: a node is entered
 * when a lane's ray enters its box before that lane's hit so far, nearer child (over the lanes)
 * first, each level pushing at most one node; every entered leaf is tested against every lane.
 * With the tie rule, the spheres tested beyond one lane's own walk cannot change its hit. */
LANE_FN void packet_walk(const packed_scene *p, const lanes3 *o, const lanes3 *d, const int *self,
                         const float *tmin, const int *active, int any_hit, float *best, int *id) {
    lanes3 inv;
    for (int k = 0; k < LANES; k++) set3(&inv, k, inverse_direction(get3(d, k)));
    uint32_t stack[TZ_BVH_MAX_DEPTH];
    float stack_t[TZ_BVH_MAX_DEPTH][LANES];
    int top = 0;
    uint32_t ref = 0; /* the root */
    for (;;) {
        uint32_t leaf_count = child_count(ref), first = child_index(ref);
        if (leaf_count > 0) {
            for (uint32_t s = first; s < first + leaf_count; s++)
                packet_sphere(p, s, o, d, self, tmin, 1, best, id);
            if (any_hit && all_hit(id, active)) return;
        } else {
            const struct gpu_bvh_node *n = &p->nodes[first];
            float tl[LANES], tr[LANES], near_l, near_r;
            for (int k = 0; k < LANES; k++) {
                tl[k] = box_entry(n->left_lo, n->left_hi, get3(o, k), get3(&inv, k), best[k]);
                tr[k] = box_entry(n->right_lo, n->right_hi, get3(o, k), get3(&inv, k), best[k]);
            }
            near_l = lanes_min(tl);
            near_r = lanes_min(tr);
            if (near_l < INFINITY || near_r < INFINITY) {
                int left_first = near_l <= near_r;
                uint32_t left = uint_bits(n->left_lo.w), right = uint_bits(n->right_lo.w);
                ref = left_first ? left : right;
                if ((left_first ? near_r : near_l) < INFINITY) {
                    stack[top] = left_first ? right : left;
                    memcpy(stack_t[top++], left_first ? tr : tl, sizeof tl);
                }
                continue;
            }
        }
        /* pop the next pending child that a lane can still find a nearer hit in */
        int go = 0;
        while (top > 0 && !go) {
            top--;
            ref = stack[top];
            for (int k = 0; k < LANES; k++) go |= stack_t[top][k] < best[k];
        }
        if (!go) return;
    }
}

/* packet_walk for nearest hits and for shadow rays. The 8-lane builds compile each once, out of
 * line: inlined at every trace, the walk made their entry point big enough to slow down scenes
 * that never walk. The 16-lane build inlines them: out of line it lost on scenes that walk
 * (docs/PERF.md). */
#if LANES > 8
#define WALK_FN LANE_FN
#else
#define WALK_FN static __attribute__((noinline))
#endif

WALK_FN void packet_walk_nearest(const packed_scene *p, const lanes3 *o, const lanes3 *d,
                                 const int *self, const float *tmin, const int *active, float *best,
                                 int *id) {
    packet_walk(p, o, d, self, tmin, active, 0, best, id);
}

WALK_FN void packet_walk_shadow(const packed_scene *p, const lanes3 *o, const lanes3 *d,
                                const int *self, const float *tmin, const int *active, float *best,
                                int *id) {
    packet_walk(p, o, d, self, tmin, active, 1, best, id);
}

/* Hits of the active lanes' rays below tmax: id[k] the nearest sphere (-1 none) at t[k], or with
 * any_hit some sphere nearer than tmax[k]. Small scenes test every sphere for all lanes at once;
 * in others the lanes walk the BVH together (WALK_GROUP_MIN) or one by one. */
LANE_FN void packet_trace(const packed_scene *p, const lanes3 *o, const lanes3 *d, const int *self,
                          const float *tmax, const int *active, int any_hit, int *id, float *t) {
    float tmin[LANES];
    int rays = 0;
    for (int k = 0; k < LANES; k++) {
        tmin[k] = ray_eps(get3(o, k));
        t[k] = active[k] ? tmax[k] : -INFINITY; /* nothing is nearer than -inf: lane idle */
        id[k] = -1;
        rays += active[k];
    }
    integrator_count_rays((uint64_t)rays);
    uint32_t count = p->frame.sphere_count;
    if (!integrator_packet_walks(p)) {
        for (uint32_t s = 0; s < count; s++) packet_sphere(p, s, o, d, self, tmin, 0, t, id);
    } else if (rays >= (any_hit ? SHADOW_WALK_GROUP_MIN : WALK_GROUP_MIN)) {
        if (any_hit)
            packet_walk_shadow(p, o, d, self, tmin, active, t, id);
        else
            packet_walk_nearest(p, o, d, self, tmin, active, t, id);
    } else {
        for (int k = 0; k < LANES; k++)
            if (active[k])
                id[k] = integrator_trace(p, get3(o, k), get3(d, k), self[k], t[k], any_hit, &t[k]);
    }
    for (int k = 0; k < LANES; k++) t[k] = active[k] ? t[k] : INFINITY;
}

/* A packet's rays followed through mirrors and glass (follow_specular of integrator.c, lane by
 * lane): result[k] the diffuse sphere reached, -1 on a miss, -2 past the bounce limit (-1 for
 * inactive lanes); o, d become the last rays, weight the tints, pos and n the diffuse hits. */
LANE_FN void packet_follow_specular(const packed_scene *p, lanes3 *o, lanes3 *d, int *self,
                                    const int *active_in, lanes3 *weight, lanes3 *pos, lanes3 *n,
                                    int *result) {
    uint32_t bounces = p->frame.bounces;
    int active[LANES];
    float tmax[LANES];
    for (int k = 0; k < LANES; k++) {
        active[k] = active_in[k];
        tmax[k] = INFINITY;
        result[k] = -1;
        set3(pos, k, v3(0.0f, 0.0f, 0.0f));
        set3(n, k, v3(0.0f, 0.0f, 0.0f));
    }
    for (uint32_t chain = 0; any_lane(active); chain++) {
        int id[LANES], material[LANES];
        float t[LANES], ior[LANES];
        lanes3 center, tint;
        float radius[LANES];
        packet_trace(p, o, d, self, tmax, active, 0, id, t);
        for (int k = 0; k < LANES; k++) { /* gather the hit spheres */
            const struct gpu_sphere *s = &p->spheres[id[k] >= 0 ? id[k] : 0];
            set3(&center, k, xyz(s->center_radius));
            radius[k] = s->center_radius.w;
            set3(&tint, k, xyz(s->color_ks));
            material[k] = (int)s->params.z;
            ior[k] = s->params.y;
        }
        lanes3 hit_pos, nout;
        int onward[LANES];
        for (int k = 0; k < LANES; k++) {
            vec3 dk = get3(d, k), pk = v3_add(get3(o, k), v3_scale(dk, t[k]));
            vec3 nk = v3_scale(v3_sub(pk, get3(&center, k)), 1.0f / radius[k]);
            int hit = active[k] & (id[k] >= 0);
            int diffuse = hit & ((material[k] == TZ_MATERIAL_LAMBERTIAN) |
                                 (material[k] == TZ_MATERIAL_PHONG));
            onward[k] = hit & !diffuse & (chain != bounces);
            int done = active[k] & !onward[k];
            result[k] = done ? (diffuse ? id[k] : hit ? -2 : -1) : result[k];
            set3(pos, k, select3(diffuse, pk, get3(pos, k)));
            set3(n, k, select3(diffuse, facing_normal(nk, dk), get3(n, k)));
            set3(&hit_pos, k, pk);
            set3(&nout, k, nk);
        }
        for (int k = 0; k < LANES; k++) { /* mirror and glass lanes go on */
            next_ray next = specular_next(get3(&hit_pos, k), get3(&nout, k), get3(d, k),
                                          material[k] == TZ_MATERIAL_REFRACTIVE, ior[k]);
            set3(weight, k,
                 select3(onward[k], v3_mul(get3(weight, k), get3(&tint, k)), get3(weight, k)));
            set3(o, k, select3(onward[k], next.o, get3(o, k)));
            set3(d, k, select3(onward[k], next.d, get3(d, k)));
            self[k] = onward[k] ? id[k] : self[k];
            active[k] = onward[k];
        }
    }
}

/* The Phong parameters of each lane's sphere id[k], gathered once for all the BRDF evaluations
 * at that hit. */
typedef struct phong_lanes {
    lanes3 kd;
    float ks[LANES], alpha[LANES];
} phong_lanes;

LANE_FN void packet_gather_phong(const packed_scene *p, const int *id, phong_lanes *m) {
    for (int k = 0; k < LANES; k++) {
        const struct gpu_sphere *s = &p->spheres[id[k] >= 0 ? id[k] : 0];
        set3(&m->kd, k, xyz(s->color_ks));
        m->ks[k] = s->color_ks.w;
        m->alpha[k] = s->params.x;
    }
}

/* Normalized Phong BRDF per lane (sphere_brdf of integrator.c); powf only where a lane needs it. */
LANE_FN void packet_phong(const phong_lanes *m, const lanes3 *n, const lanes3 *wi, const lanes3 *wo,
                          const int *active, lanes3 *f) {
    float x[LANES], lobe[LANES];
    for (int k = 0; k < LANES; k++) x[k] = phong_lobe_cos(get3(n, k), get3(wi, k), get3(wo, k));
    for (int k = 0; k < LANES; k++)
        lobe[k] = active[k] && m->ks[k] > 0.0f ? phong_lobe(x[k], m->alpha[k]) : 0.0f;
    for (int k = 0; k < LANES; k++)
        set3(f, k, phong_from_lobe(get3(&m->kd, k), m->ks[k], m->alpha[k], lobe[k]));
}

/* The lanes whose path reached a diffuse hit (id[k] >= 0), and wo, the way back along their last
 * rays d. */
LANE_FN void packet_diffuse_hits(const int *active, const int *id, const lanes3 *d, int *diffuse,
                                 lanes3 *wo) {
    for (int k = 0; k < LANES; k++) {
        diffuse[k] = active[k] & (id[k] >= 0);
        set3(wo, k, v3_scale(get3(d, k), -1.0f));
    }
}

/* What a path ending as id brings back: its weight times the background on a miss (-1), black
 * past the bounce limit (-2), else its weight times the light found at its diffuse hit. */
LANE_FN vec3 path_radiance(int id, vec3 weight, vec3 background, vec3 found) {
    vec3 lit = id == -1 ? v3_mul(weight, background) : v3_mul(weight, found);
    return id == -2 ? v3(0.0f, 0.0f, 0.0f) : lit;
}

/* Direct light from every point light at the active lanes' diffuse hits (direct_light of
 * integrator.c, lane by lane) into sum. */
LANE_FN void packet_direct_light(const packed_scene *p, const int *id, const lanes3 *pos,
                                 const lanes3 *n, const lanes3 *wo, const int *active,
                                 lanes3 *sum) {
    lanes3 o;
    phong_lanes m;
    packet_gather_phong(p, id, &m);
    for (int k = 0; k < LANES; k++) {
        vec3 pk = get3(pos, k);
        set3(&o, k, offset_origin(pk, get3(n, k)));
        set3(sum, k, v3(0.0f, 0.0f, 0.0f));
    }
    for (uint32_t l = 0; l < p->frame.light_count; l++) {
        lanes3 wi, light, f;
        float dist[LANES];
        int facing[LANES], blocker[LANES];
        float blocker_t[LANES];
        tz_vec4 position_power = p->lights[l].position_power, color = p->lights[l].color;
        for (int k = 0; k < LANES; k++) {
            light_sample ls = point_light(position_power, color, get3(pos, k), get3(n, k));
            set3(&light, k, ls.radiance);
            set3(&wi, k, ls.wi);
            dist[k] = ls.dist;
            facing[k] = active[k] & !(ls.cos_i <= 0.0f);
        }
        if (!any_lane(facing)) continue;
        packet_trace(p, &o, &wi, id, dist, facing, 1, blocker, blocker_t);
        packet_phong(&m, n, &wi, wo, facing, &f);
        for (int k = 0; k < LANES; k++) {
            int lit = facing[k] & (blocker[k] < 0);
            vec3 s = get3(sum, k);
            set3(sum, k, select3(lit, v3_add(s, v3_mul(get3(&f, k), get3(&light, k))), s));
        }
    }
}

/* Radiance arriving along the active lanes' rays (radiance_direct_only of integrator.c). */
LANE_FN void packet_radiance_direct_only(const packed_scene *p, lanes3 *o, lanes3 *d, int *self,
                                         const int *active, lanes3 *radiance) {
    lanes3 weight, pos, n, wo, direct;
    int id[LANES];
    for (int k = 0; k < LANES; k++) set3(&weight, k, v3(1.0f, 1.0f, 1.0f));
    packet_follow_specular(p, o, d, self, active, &weight, &pos, &n, id);
    int diffuse[LANES];
    packet_diffuse_hits(active, id, d, diffuse, &wo);
    packet_direct_light(p, id, &pos, &n, &wo, diffuse, &direct);
    vec3 background = xyz(p->frame.background);
    for (int k = 0; k < LANES; k++)
        set3(radiance, k, path_radiance(id[k], get3(&weight, k), background, get3(&direct, k)));
}

/* One cosine-weighted bounce at the active lanes' diffuse hits (indirect_light of integrator.c),
 * added to radiance. */
LANE_FN void packet_indirect_light(const packed_scene *p, const int *id, const lanes3 *pos,
                                   const lanes3 *n, const lanes3 *wo, const int *active,
                                   uint32_t *rng, lanes3 *radiance) {
    float y1[LANES], phi[LANES], cos_phi[LANES], sin_phi[LANES], cos_t[LANES];
    for (int k = 0; k < LANES; k++) {
        y1[k] = rng_next(&rng[k]);
        float y2 = rng_next(&rng[k]);
        cos_t[k] = sqrtf(1.0f - y1[k]);
        phi[k] = 2.0f * TZ_PI * y2;
    }
    for (int k = 0; k < LANES; k++) {
        cos_phi[k] = active[k] ? cosf(phi[k]) : 1.0f;
        sin_phi[k] = active[k] ? sinf(phi[k]) : 0.0f;
    }
    lanes3 o, wi, incoming, f;
    int self[LANES];
    for (int k = 0; k < LANES; k++) {
        vec3 nk = get3(n, k), pk = get3(pos, k);
        set3(&wi, k, cosine_direction(nk, y1[k], cos_phi[k], sin_phi[k]));
        set3(&o, k, offset_origin(pk, nk));
        self[k] = id[k];
    }
    phong_lanes m;
    packet_gather_phong(p, id, &m);
    packet_phong(&m, n, &wi, wo, active, &f); /* before the walk below turns wi into its last ray */
    packet_radiance_direct_only(p, &o, &wi, self, active, &incoming);
    for (int k = 0; k < LANES; k++) {
        float pdf = cos_t[k] / TZ_PI;
        vec3 light = v3_mul(get3(&f, k), v3_scale(get3(&incoming, k), cos_t[k] / pdf));
        vec3 r = get3(radiance, k);
        set3(radiance, k, select3(active[k], v3_add(r, light), r));
    }
}

/* The packet_integrator sample function of this build (integrator.h). */
void PACKET_ENTRY(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                  uint32_t sample_index, vec3 *out);

void PACKET_ENTRY(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                  uint32_t sample_index, vec3 *out) {
    const struct gpu_frame *fr = &p->frame;
    uint32_t rng[LANES];
    int active[LANES], self[LANES], id[LANES];
    lanes3 o, d, weight, pos, n, wo, radiance;
    /* Copied once, here: read through fr in the loop, gcc copied them for every lane
     * (docs/PERF.md). */
    tz_vec4 right = fr->right, up = fr->up, forward = fr->forward;
    tz_vec4 origin = fr->origin;
    float pixel = fr->origin.w, near_distance = fr->near_distance;
    for (int k = 0; k < LANES; k++) {
        active[k] = (uint32_t)k < lanes;
        rng[k] = rng_seed(fr->seed, j * fr->width + i + (uint32_t)k, sample_index);
        /* Both jitter numbers are always drawn so the indirect numbers do not depend on the flag.
         */
        float u = rng_next(&rng[k]), v = rng_next(&rng[k]);
        if (!(fr->flags & TZ_FLAG_JITTER)) u = v = 0.5f;
        vec3 dk = camera_direction(right, up, forward, pixel, i + (uint32_t)k, j, u, v);
        set3(&d, k, dk);
        set3(&o, k, camera_origin(origin, near_distance, dk));
        set3(&weight, k, v3(1.0f, 1.0f, 1.0f));
        self[k] = -1;
    }
    packet_follow_specular(p, &o, &d, self, active, &weight, &pos, &n, id);
    int diffuse[LANES];
    packet_diffuse_hits(active, id, &d, diffuse, &wo);
    packet_direct_light(p, id, &pos, &n, &wo, diffuse, &radiance);
    if (fr->flags & TZ_FLAG_INDIRECT)
        packet_indirect_light(p, id, &pos, &n, &wo, diffuse, rng, &radiance);
    vec3 background = xyz(fr->background);
    for (int k = 0; k < LANES; k++)
        out[k] = path_radiance(id[k], get3(&weight, k), background, get3(&radiance, k));
}
