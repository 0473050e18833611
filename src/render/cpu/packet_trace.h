/* packet_trace.h: a packet of LANES rays traced at once (the lanes of the packet integrators,
 * src/render/cpu/integrator_packet.c and integrator_path_packet.c): against every sphere in small
 * scenes, through the BVH together or one by one in others, each lane finding the very hit
 * integrator_trace finds. The includer defines LANES first. */
#ifndef TRAZADOR_PACKET_TRACE_H
#define TRAZADOR_PACKET_TRACE_H

#include <math.h>
#include <string.h>

#include "common/affine.h"
#include "render/cpu/scene_accessors.h"

/* The shared text calls the accessors above (face_cut). */
#include "common/primitive.h"
#include "common/ray.h"
#include "render/cpu/integrator.h"

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

/* Vector registers of LANES floats and ints (GCC and clang vector extensions). */
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
    float cx = p->sphere_soa.cx[s], cy = p->sphere_soa.cy[s], cz = p->sphere_soa.cz[s],
          r = p->sphere_soa.r[s], ts[LANES];
    for (int k = 0; k < LANES; k++)
        ts[k] = sphere_distance(cx, cy, cz, r, get3(o, k), get3(d, k), tmin[k], (int)s == self[k]);
    if (tie)
        keep_nearer(best, id, ts, (int)s);
    else
        keep_nearer_in_order(best, id, ts, (int)s);
}

/* The lanes' rays as the watertight test takes them (shear_of). Coherent rays share one axis
 * order: then (uniform) each triangle's corners are put in it once for all lanes and the origins
 * once a trace, and the lanes do only the test's arithmetic; with mixed orders each lane shears
 * its own (triangle_distance). The bits are the same either way. */
typedef struct shear_lanes {
    int uniform, kz, swap;
    lanes3 o;                             /* the origins in shear_axes order, when uniform */
    int lane_kz[LANES], lane_swap[LANES]; /* each lane's order, when not */
    float sx[LANES], sy[LANES], sz[LANES];
} shear_lanes;

/* The shear of the lanes' rays, once a trace: whether their order is uniform is decided by the
 * active lanes alone (the others' hits are never taken). */
LANE_FN void shear_lanes_of(const lanes3 *o, const lanes3 *d, const int *active, shear_lanes *sh) {
    int first = 0, uniform = 0;
    sh->kz = 0, sh->swap = 0;         /* read by no lane unless uniform */
    for (int k = 0; k < LANES; k++) { /* branch-free: vector code */
        ray_shear r = shear_of(get3(d, k));
        sh->lane_kz[k] = r.kz, sh->lane_swap[k] = r.swap;
        sh->sx[k] = r.sx, sh->sy[k] = r.sy, sh->sz[k] = r.sz;
    }
    while (first < LANES && !active[first]) first++;
    if (first < LANES) {
        uniform = 1;
        for (int k = 0; k < LANES; k++)
            uniform &= (!active[k]) | ((sh->lane_kz[k] == sh->lane_kz[first]) &
                                       (sh->lane_swap[k] == sh->lane_swap[first]));
    }
    sh->uniform = uniform;
    if (!uniform) return;
    sh->kz = sh->lane_kz[first], sh->swap = sh->lane_swap[first];
    for (int k = 0; k < LANES; k++) set3(&sh->o, k, shear_axes(get3(o, k), sh->kz, sh->swap));
}

/* Bit lane set where the lane's ray hits triangle primitive s (at ts[lane]) but the face is cut
 * away there (face_cut, with the lane's shear_of); hits past the lane's best, which cannot be
 * kept, are not looked up. Out of line and on a copy of the distances, as scenes without
 * cut-outs never call it. */
static __attribute__((noinline)) uint32_t packet_faces_cut(const packed_scene *p, uint32_t s,
                                                           const shear_lanes *sh, const lanes3 *o,
                                                           const float *best, const float *ts) {
    uint32_t cut = 0;
    triangle_corners k = corners_of(p, (int)s);
    for (int lane = 0; lane < LANES; lane++) {
        ray_shear r = {sh->lane_kz[lane], sh->lane_swap[lane], sh->sx[lane], sh->sy[lane],
                       sh->sz[lane]};
        if (ts[lane] < INFINITY && ts[lane] <= best[lane] &&
            face_cut(p, (int)s, k, get3(o, lane), r))
            cut |= 1u << lane;
    }
    return cut;
}

/* packet_sphere for the triangle of primitive id s, numbered key (an instance's face: its key,
 * shaders/shared_layout.h), the lanes' rays sheared by sh; with cutouts (a constant:
 * packet_triangles_cut) faces cut away where a lane's ray meets them are no hit. */
LANE_FN void packet_triangle_keyed(const packed_scene *p, uint32_t s, int key,
                                   const shear_lanes *sh, const lanes3 *o, const int *self,
                                   const float *tmin, int tie, int cutouts, float *best, int *id) {
    const struct gpu_triangle *tr = &p->triangles[s - p->frame.sphere_count];
    vec3 a = v3(tr->v0.x, tr->v0.y, tr->v0.z);
    vec3 b = v3(tr->v1.x, tr->v1.y, tr->v1.z);
    vec3 c = v3(tr->v2.x, tr->v2.y, tr->v2.z);
    float ts[LANES];
    if (sh->uniform) {
        vec3 as = shear_axes(a, sh->kz, sh->swap), bs = shear_axes(b, sh->kz, sh->swap);
        vec3 cs = shear_axes(c, sh->kz, sh->swap);
        for (int lane = 0; lane < LANES; lane++) {
            vec3 os = get3(&sh->o, lane);
            triangle_edges e =
                sheared_edge_functions(v3_sub(as, os), v3_sub(bs, os), v3_sub(cs, os), sh->sx[lane],
                                       sh->sy[lane], sh->sz[lane]);
            ts[lane] = edges_distance(e, tmin[lane], key == self[lane]);
        }
    } else { /* triangle_distance with each lane's shear of the trace */
        for (int lane = 0; lane < LANES; lane++) {
            ray_shear r = {sh->lane_kz[lane], sh->lane_swap[lane], sh->sx[lane], sh->sy[lane],
                           sh->sz[lane]};
            ts[lane] =
                sheared_triangle_distance(a, b, c, get3(o, lane), r, tmin[lane], key == self[lane]);
        }
    }
    if (cutouts) {
        float copy[LANES];
        memcpy(copy, ts, sizeof copy);
        uint32_t cut = packet_faces_cut(p, s, sh, o, best, copy);
        for (int lane = 0; lane < LANES; lane++) ts[lane] = cut >> lane & 1u ? INFINITY : ts[lane];
    }
    if (tie)
        keep_nearer(best, id, ts, key);
    else
        keep_nearer_in_order(best, id, ts, key);
}

/* packet_triangle_keyed for triangle primitive s numbered s (the triangles' ids follow the
 * spheres'). */
LANE_FN void packet_triangle(const packed_scene *p, uint32_t s, const shear_lanes *sh,
                             const lanes3 *o, const int *self, const float *tmin, int tie,
                             int cutouts, float *best, int *id) {
    packet_triangle_keyed(p, s, (int)s, sh, o, self, tmin, tie, cutouts, best, id);
}

/* packet_triangle_keyed with cut-outs over triangle primitives [first, end), numbered from
 * key_offset on (an instance's): out of line, so that the walks of scenes without cut-outs are
 * the code they were. */
static __attribute__((noinline)) void packet_triangles_cut(const packed_scene *p, uint32_t first,
                                                           uint32_t end, int key_offset,
                                                           const shear_lanes *sh, const lanes3 *o,
                                                           const int *self, const float *tmin,
                                                           int tie, float *best, int *id) {
    for (uint32_t s = first; s < end; s++)
        packet_triangle_keyed(p, s, (int)s + key_offset, sh, o, self, tmin, tie, 1, best, id);
}

/* 1 when every active lane has a hit. */
LANE_FN int all_hit(const int *id, const int *active) {
    int all = 1;
    for (int k = 0; k < LANES; k++) all &= !active[k] | (id[k] >= 0);
    return all;
}

/* Every sphere against the lanes' shadow rays (any hit, ids in t and id as packet_sphere's) until
 * every active lane is blocked; with hint, *hint first: the sphere whose test blocked the last
 * whole packet, which it becomes again. Whether a lane is blocked does not depend on the order.
 * Returns whether every active lane is blocked. */
LANE_FN int packet_shadow_spheres(const packed_scene *p, const lanes3 *o, const lanes3 *d,
                                  const int *self, const float *tmin, const int *active,
                                  uint32_t *hint, float *t, int *id) {
    uint32_t count = p->frame.sphere_count, first = hint && *hint < count ? *hint : count;
    if (first < count) {
        packet_sphere(p, first, o, d, self, tmin, 0, t, id);
        if (all_hit(id, active)) return 1;
    }
    for (uint32_t s = 0; s < count; s++) {
        if (s == first) continue;
        packet_sphere(p, s, o, d, self, tmin, 0, t, id);
        if (all_hit(id, active)) {
            if (hint) *hint = s;
            return 1;
        }
    }
    return 0;
}

/* The whole packet walks the BVH, as integrator_trace walks it with one ray: a node is entered
 * when a lane's ray enters its box before that lane's hit so far, nearer child (over the lanes)
 * first, each level pushing at most one node; every entered leaf is tested against every lane.
 * With the tie rule, the spheres tested beyond one lane's own walk cannot change its hit. */
static void packet_walk_instances(const packed_scene *p, uint32_t first, uint32_t count,
                                  const lanes3 *o, const lanes3 *d, const int *self,
                                  const float *tmin, const int *active, int any_hit, float *best,
                                  int *id);

/* packet_walk from node root, triangle primitive s numbered s + key_offset (an instance's model
 * walks with the lanes' rays in its space, its faces numbered by their keys). */
LANE_FN void packet_walk_from(const packed_scene *p, uint32_t root, int key_offset, const lanes3 *o,
                              const lanes3 *d, const int *self, const float *tmin,
                              const int *active, int any_hit, float *best, int *id) {
    lanes3 inv;
    for (int k = 0; k < LANES; k++) set3(&inv, k, inverse_direction(get3(d, k)));
    shear_lanes sh; /* read by triangle leaves alone */
    sh.uniform = 0, sh.kz = 0, sh.swap = 0;
    if (p->frame.triangle_count > 0) shear_lanes_of(o, d, active, &sh);
    int cutouts = TZ_HAS_CUTOUTS_OF(p);
    uint32_t stack[TZ_BVH_MAX_DEPTH];
    float stack_t[TZ_BVH_MAX_DEPTH][LANES];
    int top = 0;
    uint32_t ref = root;
    for (;;) {
        uint32_t leaf_count = child_count(ref), first = child_index(ref);
        if (leaf_count > 0) {
            if (first < p->frame.sphere_count) { /* a leaf holds one kind */
                for (uint32_t s = first; s < first + leaf_count; s++)
                    packet_sphere(p, s, o, d, self, tmin, 1, best, id);
            } else if (p->frame.instance_count > 0 && first >= p->frame.instance_leaf) {
                packet_walk_instances(p, first, leaf_count, o, d, self, tmin, active, any_hit, best,
                                      id);
            } else if (cutouts) {
                packet_triangles_cut(p, first, first + leaf_count, key_offset, &sh, o, self, tmin,
                                     1, best, id);
            } else {
                for (uint32_t s = first; s < first + leaf_count; s++)
                    packet_triangle_keyed(p, s, (int)s + key_offset, &sh, o, self, tmin, 1, 0, best,
                                          id);
            }
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

/* The whole packet walks the scene's tree (packet_walk_from its root). */
LANE_FN void packet_walk(const packed_scene *p, const lanes3 *o, const lanes3 *d, const int *self,
                         const float *tmin, const int *active, int any_hit, float *best, int *id) {
    packet_walk_from(p, 0, 0, o, d, self, tmin, active, any_hit, best, id);
}

/* The instances [first, first + count) of a leaf (ids from frame.instance_leaf): the packet's
 * rays moved into each one's space (never by an identity) walk its model's tree together, as
 * integrator_instances_hit walks it with one. Out of line: the walks above inline it once. */
static __attribute__((noinline)) void packet_walk_instances(const packed_scene *p, uint32_t first,
                                                            uint32_t count, const lanes3 *o,
                                                            const lanes3 *d, const int *self,
                                                            const float *tmin, const int *active,
                                                            int any_hit, float *best, int *id) {
    for (uint32_t k = first - p->frame.instance_leaf; count-- > 0; k++) {
        if (any_hit && all_hit(id, active)) return;
        const struct gpu_instance *in = &p->instances[k];
        lanes3 mo = *o, md = *d;
        if (!in->model.z) {
            for (int lane = 0; lane < LANES; lane++) {
                set3(&mo, lane,
                     affine_point(in->to_object[0], in->to_object[1], in->to_object[2],
                                  get3(o, lane)));
                set3(&md, lane,
                     affine_direction(in->to_object[0], in->to_object[1], in->to_object[2],
                                      get3(d, lane)));
            }
        }
        int key_offset = TZ_INSTANCE_KEY + (int)(k << p->frame.instance_shift) - (int)in->model.y -
                         (int)p->frame.sphere_count;
        packet_walk_from(p, in->model.x, key_offset, &mo, &md, self, tmin, active, any_hit, best,
                         id);
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
 * any_hit some sphere nearer than tmax[k]. Small scenes test every sphere for all lanes at once
 * (shadow rays until all are blocked, hint as packet_shadow_spheres'); in others the lanes walk
 * the BVH together (WALK_GROUP_MIN) or one by one. */
LANE_FN void packet_trace(const packed_scene *p, const lanes3 *o, const lanes3 *d, const int *self,
                          const float *tmax, const int *active, int any_hit, uint32_t *hint,
                          int *id, float *t) {
    float tmin[LANES];
    int rays = 0;
    for (int k = 0; k < LANES; k++) {
        tmin[k] = ray_eps(get3(o, k));
        t[k] = active[k] ? tmax[k] : -INFINITY; /* nothing is nearer than -inf: lane idle */
        id[k] = -1;
        rays += active[k];
    }
    integrator_count_rays((uint64_t)rays);
    uint32_t count = p->frame.sphere_count, all = count + p->frame.triangle_count;
    if (!integrator_packet_walks(p)) {
        int blocked = 0;
        if (any_hit)
            blocked = packet_shadow_spheres(p, o, d, self, tmin, active, hint, t, id);
        else
            for (uint32_t s = 0; s < count; s++) packet_sphere(p, s, o, d, self, tmin, 0, t, id);
        if (all > count && !blocked) {
            shear_lanes sh;
            shear_lanes_of(o, d, active, &sh);
            if (TZ_HAS_CUTOUTS_OF(p))
                packet_triangles_cut(p, count, all, 0, &sh, o, self, tmin, 0, t, id);
            else
                for (uint32_t s = count; s < all; s++)
                    packet_triangle(p, s, &sh, o, self, tmin, 0, 0, t, id);
        }
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

#endif
