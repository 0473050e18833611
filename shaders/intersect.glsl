/* intersect.glsl: the GLSL back end's nearest-hit and shadow queries over the spheres, by brute
 * force or through the BVH, on the shared steps of common/ray.h; the C back end's functions of
 * the same names are in src/render/cpu/integrator.c (trace_bvh, integrator_nearest,
 * integrator_occluded). The including shader declares `frame`, sphere_center_radius(),
 * sphere_params(), sphere_count(), node_field(), use_bvh() and WALK_BUDGET. */
#ifndef TRAZADOR_INTERSECT_GLSL
#define TRAZADOR_INTERSECT_GLSL

#include "common/ray.h"

/* Distance to sphere k along o + t d (sphere_distance), with one read of the sphere. */
float sphere_distance_at(int k, vec3 o, vec3 d, float tmin, int self) {
    vec4 cr = sphere_center_radius(k);
    return sphere_distance(cr.x, cr.y, cr.z, cr.w, o, d, tmin, k == self);
}

/* Set when a walk ran out of WALK_BUDGET passes: main() drops the sample instead of lavapipe
 * silently cutting a loop short. */
bool loop_overflow;

/* Rays this invocation traced (nearest-hit and shadow), for Mrays/s. */
uint rays_traced;

/* Keeps in best/id the nearer of the hit so far and sphere k at distance t (nearer_hit, the tie
 * rule). Selects, not branches: lavapipe runs both sides of a branch for the whole subgroup. */
void keep_nearer(int k, float t, inout float best, inout int id) {
    bool take = nearer_hit(t, k, best, id);
    best = take ? t : best;
    id = take ? k : id;
}

/* Nearest sphere hit below tmax through the BVH (t_out its distance), or with any_hit the first
 * one found; -1 when none. Nearer child first, a stack of TZ_BVH_MAX_DEPTH child references
 * (each level pushes at most one). One loop of at most WALK_BUDGET passes, each doing all it can:
 * a pop when idle, a node visit (a leaf child taken at once becomes the spheres to test), one
 * sphere of the current leaf (lavapipe pays for every test in the loop on every pass; with the
 * BVH's small leaves a second test a pass costs more than it saves). The C walks test a leaf's
 * spheres at once and find the same sphere (src/render/bvh.h: the tie rule). */
int trace_bvh(vec3 o, vec3 d, int self, float tmax, bool any_hit, out float t_out) {
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    vec3 inv = inverse_direction(d);
    uint stack[TZ_BVH_MAX_DEPTH];
    float stack_t[TZ_BVH_MAX_DEPTH];
    int top = 0;
    const uint none = 0xffffffffu;
    uint node = 0u;                  /* the root */
    uint sphere = 0u, leaf_end = 0u; /* the leaf's spheres still to test */
    for (uint pass = 0u;; pass++) {
        if (WALK_BUDGET > 0u && pass == WALK_BUDGET) {
            loop_overflow = true;
            break;
        }
        if (sphere >= leaf_end && node == none) {
            if (top == 0) break;
            top--;
            uint ref = stack[top], count = child_count(ref);
            if (stack_t[top] < best) {
                node = count == 0u ? ref : none;
                sphere = child_index(ref);
                leaf_end = count == 0u ? 0u : sphere + count;
            }
        }
        if (sphere >= leaf_end && node != none) {
            uvec4 left_lo = node_field(node, 0u), left_hi = node_field(node, 1u);
            uvec4 right_lo = node_field(node, 2u), right_hi = node_field(node, 3u);
            float tl = box_entry(uintBitsToFloat(left_lo), uintBitsToFloat(left_hi), o, inv, best);
            float tr =
                box_entry(uintBitsToFloat(right_lo), uintBitsToFloat(right_hi), o, inv, best);
            bool left_first = tl <= tr;
            float near_t = left_first ? tl : tr, far_t = left_first ? tr : tl;
            uint near_ref = left_first ? left_lo.w : right_lo.w;
            uint near_count = child_count(near_ref);
            bool enters = near_t < TZ_INFINITY;
            node = enters && near_count == 0u ? near_ref : none;
            sphere = child_index(near_ref);
            leaf_end = enters && near_count > 0u ? sphere + near_count : 0u;
            if (far_t < TZ_INFINITY) {
                stack[top] = left_first ? right_lo.w : left_lo.w;
                stack_t[top] = far_t;
                top++;
            }
        }
        if (sphere < leaf_end) {
            keep_nearer(int(sphere), sphere_distance_at(int(sphere), o, d, tmin, self), best, id);
            sphere++;
            if (any_hit && id >= 0) break;
        }
    }
    t_out = best;
    return id;
}

/* Nearest sphere hit by o + t d with t > EPS, -1 on a miss; t_out is its distance. Through the
 * BVH when the scene has one, else over every sphere with the loop unrolled (sphere_count() a
 * specialization constant): trace_ray of the C back end. */
int integrator_nearest(vec3 o, vec3 d, int self, out float t_out) {
    rays_traced++;
    if (use_bvh()) return trace_bvh(o, d, self, TZ_INFINITY, false, t_out);
    float tmin = ray_eps(o), best = TZ_INFINITY;
    int id = -1;
    [[unroll]] for (uint k = 0u; k < sphere_count(); k++)
        keep_nearer(int(k), sphere_distance_at(int(k), o, d, tmin, self), best, id);
    t_out = best;
    return id;
}

/* True when a sphere blocks o + t d for EPS < t < dist; glass blocks too, as in the seed. The
 * unrolled loop returns at the first blocker, with no tie rule to keep. */
bool integrator_occluded(vec3 o, vec3 d, float dist, int self) {
    rays_traced++;
    float t;
    if (use_bvh()) return trace_bvh(o, d, self, dist, true, t) >= 0;
    float tmin = ray_eps(o);
    [[unroll]] for (uint k = 0u; k < sphere_count(); k++)
        if (sphere_distance_at(int(k), o, d, tmin, self) < dist) return true;
    return false;
}

#endif
