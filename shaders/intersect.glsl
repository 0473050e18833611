/* intersect.glsl: ray offsets, ray/sphere intersection, nearest-hit and shadow queries over the
 * spheres, by brute force or through the BVH; twin of src/integrator.c (integrator_nearest,
 * integrator_occluded, the walk of trace_ray) and of src/integrator_steps.h (ray_eps, the sphere
 * and box tests, under the names noted at each function). The including shader declares `frame`,
 * sphere_center_radius(), sphere_params(), sphere_count(), node_field(), use_bvh() and
 * WALK_BUDGET. */
#ifndef TRAZADOR_INTERSECT_GLSL
#define TRAZADOR_INTERSECT_GLSL

#include "vec3.glsl"

#define TZ_INFINITY uintBitsToFloat(0x7f800000u)

/* Ray offset distance at a point: EPS scaled with the point's magnitude. */
float ray_eps(vec3 p) {
    precise float r = TZ_EPS * max(1.0, v3_max_abs(p));
    return r;
}

/* Distance to sphere k along o + t d: the nearest root greater than tmin, or infinity (Haines
 * et al., Ray Tracing Gems ch. 7); the sphere `self` that the ray leaves counts only by its far
 * root, and only when the ray moves inward (b < 0). Branch-free, the very operations of one lane
 * of spheres_hit() in src/integrator.c (sphere_distance() in src/integrator_steps.h) in the same
 * order, with one read of the sphere. */
float sphere_hit(int k, vec3 o, vec3 d, float tmin, int self) {
    vec4 cr = sphere_center_radius(k);
    precise float ocx = o.x - cr.x, ocy = o.y - cr.y, ocz = o.z - cr.z;
    float r = cr.w;
    precise float b = ocx * d.x + ocy * d.y + ocz * d.z;
    float ax = abs(ocx), ay = abs(ocy), az = abs(ocz);
    precise float xx = ocx * ocx, yy = ocy * ocy, zz = ocz * ocz;
    bool x_big = ax >= ay && ax >= az, y_big = !x_big && ay >= az;
    float big = x_big ? ax : y_big ? ay : az;
    float other1 = x_big ? yy : xx, other2 = x_big || y_big ? zz : yy;
    /* |oc|^2 - r^2 on the largest component: exact for a huge wall sphere along an axis. */
    precise float c = (big - r) * (big + r) + other1 + other2;
    precise float fx = ocx - b * d.x, fy = ocy - b * d.y, fz = ocz - b * d.z;
    precise float l = sqrt(fx * fx + fy * fy + fz * fz);
    precise float disc = (r - l) * (r + l);
    precise float root = sqrt(disc < 0.0 ? 0.0 : disc);
    precise float q = b > 0.0 ? -b - root : -b + root;
    precise float cq = c / q;
    float t0 = cq < q ? cq : q, t1 = cq < q ? q : cq;
    bool is_self = k == self;
    bool near_ok = t0 > tmin && !is_self, far_ok = t1 > tmin && (!is_self || b < 0.0);
    float near = near_ok ? t0 : far_ok ? t1 : TZ_INFINITY;
    bool miss = (c > 0.0 && b > 0.0) || disc < 0.0 || q == 0.0;
    return miss ? TZ_INFINITY : near;
}

/* Set when a walk ran out of WALK_BUDGET passes: main() drops the sample instead of lavapipe
 * silently cutting a loop short. */
bool loop_overflow;

/* Rays this invocation traced (nearest-hit and shadow), for Mrays/s. */
uint rays_traced;

/* Keeps in best/id the nearer of the current hit and sphere k at distance t; an exact tie goes to
 * the lower index, whatever order spheres are visited in (both back ends store them in the same
 * BVH order, --no-bvh too): nearer_hit() in src/integrator_steps.h. Selects, not branches:
 * lavapipe runs both sides of a branch for the whole subgroup. */
void keep_nearest(int k, float t, inout float best, inout int id) {
    bool take = t < best || (t == best && id >= 0 && k < id);
    best = take ? t : best;
    id = take ? k : id;
}

/* Distance at which the ray enters the box lo..hi, infinity when it misses it or enters at or
 * beyond tmax (slab test; inv = 1/d with zero components replaced by 1e30): box_entry() in
 * src/integrator_steps.h, the same comparisons in the same order (GLSL min and max leave NaN
 * operands undefined, and lavapipe spends two more instructions on each). */
float box_entry(vec4 lo, vec4 hi, vec3 o, vec3 inv, float tmax) {
    precise vec3 t1 = (lo.xyz - o) * inv, t2 = (hi.xyz - o) * inv;
    /* precise: a compiler may not turn these selects into min and max */
    precise float near = t1.x < t2.x ? t1.x : t2.x, far = t1.x < t2.x ? t2.x : t1.x;
    precise float ny = t1.y < t2.y ? t1.y : t2.y, fy = t1.y < t2.y ? t2.y : t1.y;
    precise float nz = t1.z < t2.z ? t1.z : t2.z, fz = t1.z < t2.z ? t2.z : t1.z;
    near = near > ny ? near : ny;
    near = near > nz ? near : nz;
    near = near > 0.0 ? near : 0.0;
    far = far < fy ? far : fy;
    far = far < fz ? far : fz;
    return near <= far && near < tmax ? near : TZ_INFINITY;
}

/* Nearest sphere hit below tmax through the BVH (t_out its distance), or with any_hit the first
 * one found; -1 when none. Nearer child first, a stack of TZ_BVH_MAX_DEPTH child references
 * (each level pushes at most one). One loop of at most WALK_BUDGET passes, each doing all it can:
 * a pop when idle, a node visit (a leaf child taken at once becomes the spheres to test), one
 * sphere of the current leaf (lavapipe pays for every test in the loop on every pass; with the
 * BVH's small leaves a second test a pass cost 8-12% more render time). Finds the same sphere
 * as the BVH branch of trace_ray() in src/integrator.c (which tests a leaf's spheres at once):
 * with the tie rule the nearest hit does not depend on the order of visits. */
int trace_bvh(vec3 o, vec3 d, int self, float tmax, bool any_hit, out float t_out) {
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    vec3 inv = vec3(d.x != 0.0 ? 1.0 / d.x : 1e30, d.y != 0.0 ? 1.0 / d.y : 1e30,
                    d.z != 0.0 ? 1.0 / d.z : 1e30);
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
            uint ref = stack[top], count = ref >> TZ_BVH_COUNT_SHIFT;
            if (stack_t[top] < best) {
                node = count == 0u ? ref : none;
                sphere = ref & TZ_BVH_INDEX_MASK;
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
            uint near_count = near_ref >> TZ_BVH_COUNT_SHIFT;
            bool enters = near_t < TZ_INFINITY;
            node = enters && near_count == 0u ? near_ref : none;
            sphere = near_ref & TZ_BVH_INDEX_MASK;
            leaf_end = enters && near_count > 0u ? sphere + near_count : 0u;
            if (far_t < TZ_INFINITY) {
                stack[top] = left_first ? right_lo.w : left_lo.w;
                stack_t[top] = far_t;
                top++;
            }
        }
        if (sphere < leaf_end) {
            keep_nearest(int(sphere), sphere_hit(int(sphere), o, d, tmin, self), best, id);
            sphere++;
            if (any_hit && id >= 0) break;
        }
    }
    t_out = best;
    return id;
}

/* Nearest sphere hit by o + t d with t > EPS, -1 on a miss; t_out is its distance. Small scenes
 * test every sphere with the loop unrolled (sphere_count() a specialization constant). */
int integrator_nearest(vec3 o, vec3 d, int self, out float t_out) {
    rays_traced++;
    if (use_bvh()) return trace_bvh(o, d, self, TZ_INFINITY, false, t_out);
    float tmin = ray_eps(o), best = TZ_INFINITY;
    int id = -1;
    [[unroll]] for (uint k = 0u; k < sphere_count(); k++)
        keep_nearest(int(k), sphere_hit(int(k), o, d, tmin, self), best, id);
    t_out = best;
    return id;
}

/* True when a sphere blocks o + t d for EPS < t < dist; glass blocks too, as in the seed. */
bool integrator_occluded(vec3 o, vec3 d, float dist, int self) {
    rays_traced++;
    float t;
    if (use_bvh()) return trace_bvh(o, d, self, dist, true, t) >= 0;
    float tmin = ray_eps(o);
    [[unroll]] for (uint k = 0u; k < sphere_count(); k++)
        if (sphere_hit(int(k), o, d, tmin, self) < dist) return true;
    return false;
}

#endif
