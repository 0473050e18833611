/* intersect.glsl: the GLSL back end's nearest-hit and shadow queries over the spheres and
 * triangles, by brute force or through the BVH, on the shared steps of common/ray.h; the C back
 * end's functions of the same names are in src/render/cpu/integrator.c (trace_bvh,
 * integrator_nearest, integrator_occluded). The including shader declares `frame`,
 * sphere_center_radius(), sphere_params(), sphere_count(), node_field(), use_bvh() and WALK_BUDGET;
 * with TZ_SUBGROUP_WALK defined (and the subgroup extensions enabled) the walk is cooperative for
 * coherent rays; with TZ_RAY_QUERY_WALK every query goes through the device's acceleration
 * structure scene_accel. */
#ifndef TRAZADOR_INTERSECT_GLSL
#define TRAZADOR_INTERSECT_GLSL

#include "common/primitive.h"
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

/* No node: the walk tests a leaf or pops. */
#define WALK_NONE 0xffffffffu

/* The walk's next step when it enters child ref (a reference of shared_layout.h): the inner node
 * to visit, or the leaf's primitives first..end - 1 to test; neither when it does not enter. */
void enter_child(uint ref, bool enters, out uint node, out uint first, out uint end) {
    uint count = child_count(ref);
    node = enters && count == 0u ? ref : WALK_NONE;
    first = child_index(ref);
    end = enters && count > 0u ? first + count : 0u;
}

/* Keeps the nearer of two children of a wide node, by entry distance, in (ta, ra). */
void nearer_child_first(inout float ta, inout uint ra, inout float tb, inout uint rb) {
    bool swap = tb < ta;
    float t = ta;
    uint r = ra;
    ta = swap ? tb : ta, ra = swap ? rb : ra;
    tb = swap ? t : tb, rb = swap ? r : rb;
}

/* Where the ray enters child c of the wide node whose fields 0, 2 and 3 are given (box_entry of
 * its decoded box), infinity for no child (reference 0). */
float wide_child_entry(uvec4 frame_bits, uvec4 lo, uvec4 hi, uint ref, uint c, vec3 o, vec3 inv,
                       float tmax) {
    uint shift = 8u * c;
    vec3 origin = uintBitsToFloat(frame_bits.xyz);
    uvec3 exponents = (uvec3(frame_bits.w) >> uvec3(0u, 8u, 16u)) & 255u;
    vec3 scale = uintBitsToFloat(exponents << 23u);
    vec3 box_lo = origin + vec3((lo.xyz >> shift) & 255u) * scale;
    vec3 box_hi = origin + vec3((uvec3(lo.w, hi.x, hi.y) >> shift) & 255u) * scale;
    float t = box_entry(vec4(box_lo, 0.0), vec4(box_hi, 0.0), o, inv, tmax);
    return ref == 0u ? TZ_INFINITY : t;
}

/* A walk's second level (DESIGN section 3.4): the instance whose model it walks, with the ray
 * moved into the model's space (never by an identity, as the C walks), its faces numbered by
 * their keys (a face's key is its primitive id + offset), and what it returns to: the stack's
 * height on entry, the rest of the top-level leaf and the ray in world space. */
struct instance_walk {
    bool inside;
    int top;
    int offset;
    uint next, end;
    vec3 o, d, inv;
    ray_shear sh;
};

/* A walk at the top level of the ray o + t d (inv and sh its inverse_direction and shear_of). */
instance_walk instance_walk_start(vec3 o, vec3 d, vec3 inv, ray_shear sh) {
    instance_walk iw;
    iw.inside = false;
    iw.top = 0;
    iw.offset = 0;
    iw.next = iw.end = 0u;
    iw.o = o, iw.d = d, iw.inv = inv, iw.sh = sh;
    return iw;
}

/* Whether leaf primitive k of the walk is an instance (the top level's leaves after the faces). */
bool is_instance_leaf(instance_walk iw, uint k) {
    return !iw.inside && k >= frame.instance_leaf;
}

/* The ray o + t d in the space of instance i's model (moved by its rows unless they are the
 * identity: a flattened copy's bits), its inverse direction and shear; returns the offset of its
 * faces' keys over their primitive ids. model is instance_model(i). */
int instance_ray(int i, uvec4 model, vec3 o, vec3 d, out vec3 mo, out vec3 md, out vec3 minv,
                 out ray_shear msh) {
    mo = o, md = d;
    if (model.z == 0u) {
        mo = affine_point(instance_to_object(i, 0), instance_to_object(i, 1),
                          instance_to_object(i, 2), o);
        md = affine_direction(instance_to_object(i, 0), instance_to_object(i, 1),
                              instance_to_object(i, 2), d);
    }
    minv = inverse_direction(md);
    msh = shear_of(md);
    return TZ_INSTANCE_KEY + (i << frame.instance_shift) - int(model.y) -
           int(frame.sphere_count);
}

/* Enters the instance of leaf primitive k (the walk's `sphere`, end its leaf's end): the ray
 * moved into its model's space, the walk on at the model's root. */
void instance_enter(inout instance_walk iw, int top, out vec3 o, out vec3 d, out vec3 inv,
                    out ray_shear sh, inout uint k, inout uint end, out uint node) {
    int i = int(k - frame.instance_leaf);
    uvec4 model = instance_model(i);
    iw.inside = true;
    iw.top = top;
    iw.next = k + 1u, iw.end = end;
    iw.offset = instance_ray(i, model, iw.o, iw.d, o, d, inv, sh);
    k = end = 0u;
    node = model.x;
}

/* Leaves the instance: the ray back in world space, the walk on at the rest of its leaf. */
void instance_leave(inout instance_walk iw, out vec3 o, out vec3 d, out vec3 inv,
                    out ray_shear sh, out uint k, out uint end) {
    o = iw.o, d = iw.d, inv = iw.inv, sh = iw.sh;
    k = iw.next, end = iw.end;
    iw.inside = false;
    iw.offset = 0;
}

/* Nearest sphere hit below tmax through the BVH (t_out its distance), or with any_hit the first
 * one found; -1 when none. Nearer child first, the others on a stack of child references. The
 * nodes are the binary ones (each level pushes at most one, TZ_BVH_MAX_DEPTH in all) or with
 * WIDE_BVH the wide ones of src/render/bvh_wide.h (up to three a visit, TZ_WIDE_STACK in all,
 * which the build keeps every walk within; every decoded box holds its binary box). One loop of
 * at most WALK_BUDGET passes, each doing all it can: a pop when idle, a node visit (a leaf child
 * taken at once becomes the spheres to test), one sphere of the current leaf (lavapipe pays for
 * every test in the loop on every pass; with the BVH's small leaves a second test a pass costs
 * more than it saves). The C walks test a leaf's spheres at once over the binary nodes and find
 * the same sphere (src/render/bvh.h: the tie rule). */
int trace_bvh(vec3 o, vec3 d, int self, float tmax, bool any_hit, out float t_out) {
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    vec3 inv = inverse_direction(d);
    ray_shear sh = shear_of(d); /* the triangles', once a walk */
    uint stack[TZ_WIDE_STACK]; /* >= TZ_BVH_MAX_DEPTH: the binary walk's too */
    float stack_t[TZ_WIDE_STACK];
    int top = 0;
    uint node = 0u;                  /* the root */
    uint sphere = 0u, leaf_end = 0u; /* the leaf's spheres still to test */
    instance_walk iw = instance_walk_start(o, d, inv, sh);
    for (uint pass = 0u;; pass++) {
        if (WALK_BUDGET > 0u && pass == WALK_BUDGET) {
            loop_overflow = true;
            break;
        }
        if (sphere >= leaf_end && node == WALK_NONE) {
            /* the end of an instance: back to the top level, then on as the idle walk goes */
            if (TZ_HAS_INSTANCES && iw.inside && top == iw.top)
                instance_leave(iw, o, d, inv, sh, sphere, leaf_end);
            if (sphere >= leaf_end) {
                if (top == 0) break;
                top--;
                enter_child(stack[top], stack_t[top] < best, node, sphere, leaf_end);
            }
        }
        if (sphere >= leaf_end && node != WALK_NONE && WIDE_BVH != 0u) {
            uvec4 frame_bits = wide_node_field(node, 0u), refs = wide_node_field(node, 1u);
            uvec4 lo = wide_node_field(node, 2u), hi = wide_node_field(node, 3u);
            float t0 = wide_child_entry(frame_bits, lo, hi, refs.x, 0u, o, inv, best);
            float t1 = wide_child_entry(frame_bits, lo, hi, refs.y, 1u, o, inv, best);
            float t2 = wide_child_entry(frame_bits, lo, hi, refs.z, 2u, o, inv, best);
            float t3 = wide_child_entry(frame_bits, lo, hi, refs.w, 3u, o, inv, best);
            uint r0 = refs.x, r1 = refs.y, r2 = refs.z, r3 = refs.w;
            nearer_child_first(t0, r0, t1, r1);
            nearer_child_first(t0, r0, t2, r2);
            nearer_child_first(t0, r0, t3, r3);
            enter_child(r0, t0 < TZ_INFINITY, node, sphere, leaf_end);
            if (t3 < TZ_INFINITY) stack[top] = r3, stack_t[top] = t3, top++;
            if (t2 < TZ_INFINITY) stack[top] = r2, stack_t[top] = t2, top++;
            if (t1 < TZ_INFINITY) stack[top] = r1, stack_t[top] = t1, top++;
        } else if (sphere >= leaf_end && node != WALK_NONE) {
            uvec4 left_lo = node_field(node, 0u), left_hi = node_field(node, 1u);
            uvec4 right_lo = node_field(node, 2u), right_hi = node_field(node, 3u);
            float tl = box_entry(uintBitsToFloat(left_lo), uintBitsToFloat(left_hi), o, inv, best);
            float tr =
                box_entry(uintBitsToFloat(right_lo), uintBitsToFloat(right_hi), o, inv, best);
            bool left_first = tl <= tr;
            float near_t = left_first ? tl : tr, far_t = left_first ? tr : tl;
            uint near_ref = left_first ? left_lo.w : right_lo.w;
            enter_child(near_ref, near_t < TZ_INFINITY, node, sphere, leaf_end);
            if (far_t < TZ_INFINITY) {
                stack[top] = left_first ? right_lo.w : left_lo.w;
                stack_t[top] = far_t;
                top++;
            }
        }
        if (TZ_HAS_INSTANCES && sphere < leaf_end && is_instance_leaf(iw, sphere)) {
            instance_enter(iw, top, o, d, inv, sh, sphere, leaf_end, node);
        } else if (sphere < leaf_end) {
            float t = primitive_distance(int(sphere), o, d, sh, tmin, self - iw.offset, best);
            keep_nearer(int(sphere) + iw.offset, t, best, id);
            sphere++;
            if (any_hit && id >= 0) break;
        }
    }
    t_out = best;
    return id;
}

#ifdef TZ_SUBGROUP_WALK
/* Lane counts packed into one uint, so that one subgroupAdd a pass takes every vote (lavapipe
 * runs each subgroup operation as a loop over the lanes): fields of COOP_BITS bits, at most
 * 2^COOP_BITS - 1 lanes (vk_context_has_subgroup_walk checks the subgroup size). */
#define COOP_BITS 6u
#define COOP_MASK 63u
#define COOP_ENTER_LEFT 0u  /* lanes whose rays enter the left child before their hit so far */
#define COOP_ENTER_RIGHT 1u /* the same for the right child */
#define COOP_LEFT_FIRST 2u  /* lanes that enter the left child first (or it alone) */
#define COOP_PENDING 3u     /* lanes that can find a nearer hit in the child on top of the stack */
#define COOP_HIT 4u         /* lanes with a hit */
uint coop_field(uint votes, uint field) { return (votes >> (COOP_BITS * field)) & COOP_MASK; }

/* trace_bvh walked by the whole subgroup at once, as packet_walk of the CPU back end walks a
 * packet: a child is entered when any active lane's ray enters its box before that lane's hit so
 * far, the child most lanes enter first first, one stack for all. The passes are trace_bvh's (a
 * node visit or one sphere test, then a pop), counted for the whole subgroup against
 * WALK_BUDGET; every branch and loop exit is subgroup-uniform, so the active lanes stay together
 * and any subset of the subgroup may call it. One subgroupAdd a pass takes the votes. Node and
 * sphere indices are the same for every lane. With any_hit a lane stops voting at its first hit
 * and the walk ends when every lane has one. The tie rule makes its hits trace_bvh's. */
int trace_bvh_cooperative(vec3 o, vec3 d, int self, float tmax, bool any_hit, out float t_out) {
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    vec3 inv = inverse_direction(d);
    ray_shear sh = shear_of(d); /* the triangles', once a walk */
    uint stack[TZ_BVH_MAX_DEPTH];
    float stack_t[TZ_BVH_MAX_DEPTH]; /* per lane: where its ray enters the pending child */
    int top = 0;
    uint lanes = subgroupAdd(1u);
    uint node = 0u;                  /* the root */
    uint sphere = 0u, leaf_end = 0u; /* the leaf's spheres still to test */
    instance_walk iw = instance_walk_start(o, d, inv, sh);
    for (uint pass = 0u;; pass++) {
        if (WALK_BUDGET > 0u && pass == WALK_BUDGET) {
            loop_overflow = true;
            break;
        }
        bool visit = node != WALK_NONE, test = sphere < leaf_end;
        uvec4 left_lo = node_field(visit ? node : 0u, 0u);
        uvec4 left_hi = node_field(visit ? node : 0u, 1u);
        uvec4 right_lo = node_field(visit ? node : 0u, 2u);
        uvec4 right_hi = node_field(visit ? node : 0u, 3u);
        /* How far a lane's ray may still find a nearer hit: nowhere once a shadow ray has one. */
        float reach = any_hit && id >= 0 ? -TZ_INFINITY : best;
        float tl = box_entry(uintBitsToFloat(left_lo), uintBitsToFloat(left_hi), o, inv, reach);
        float tr = box_entry(uintBitsToFloat(right_lo), uintBitsToFloat(right_hi), o, inv, reach);
        /* Every lane enters an instance together: its index is the subgroup's. */
        bool enter = TZ_HAS_INSTANCES && test && is_instance_leaf(iw, sphere);
        uint entered_node = WALK_NONE;
        if (enter) {
            instance_enter(iw, top, o, d, inv, sh, sphere, leaf_end, entered_node);
        } else if (test) {
            float t = primitive_distance(int(sphere), o, d, sh, tmin, self - iw.offset, best);
            keep_nearer(int(sphere) + iw.offset, t, best, id);
            sphere++;
        }
        reach = any_hit && id >= 0 ? -TZ_INFINITY : best;
        bool pending = top > 0 && stack_t[max(top - 1, 0)] < reach;
        uint vote = (tl < TZ_INFINITY ? 1u : 0u) << (COOP_BITS * COOP_ENTER_LEFT);
        vote |= (tr < TZ_INFINITY ? 1u : 0u) << (COOP_BITS * COOP_ENTER_RIGHT);
        vote |= (tl <= tr && tl < TZ_INFINITY ? 1u : 0u) << (COOP_BITS * COOP_LEFT_FIRST);
        vote |= (pending ? 1u : 0u) << (COOP_BITS * COOP_PENDING);
        vote |= (id >= 0 ? 1u : 0u) << (COOP_BITS * COOP_HIT);
        uint votes = subgroupAdd(vote);
        if (any_hit && coop_field(votes, COOP_HIT) == lanes) break;
        node = entered_node;
        if (enter) continue;
        if (visit) {
            uint enter_l = coop_field(votes, COOP_ENTER_LEFT);
            uint enter_r = coop_field(votes, COOP_ENTER_RIGHT);
            bool left_first = 2u * coop_field(votes, COOP_LEFT_FIRST) >= enter_l + enter_r;
            left_first = enter_r == 0u || (enter_l > 0u && left_first);
            uint near_ref = left_first ? left_lo.w : right_lo.w;
            bool enters = enter_l + enter_r > 0u;
            enter_child(near_ref, enters, node, sphere, leaf_end);
            if (enter_l > 0u && enter_r > 0u) {
                stack[top] = left_first ? right_lo.w : left_lo.w;
                stack_t[top] = left_first ? tr : tl;
                top++;
            }
            if (enters) continue;
        } else if (sphere < leaf_end) {
            continue;
        }
        /* Nothing left to visit: back to the top level at the end of an instance, or pop the
         * child on top, entered when a lane voted for it. */
        if (TZ_HAS_INSTANCES && iw.inside && top == iw.top) {
            instance_leave(iw, o, d, inv, sh, sphere, leaf_end);
            if (sphere < leaf_end) continue;
        }
        if (top == 0) break;
        top--;
        enter_child(stack[top], coop_field(votes, COOP_PENDING) > 0u, node, sphere, leaf_end);
    }
    t_out = best;
    return id;
}

/* True while this invocation traces its camera ray and the shadow rays of the camera ray's hit:
 * rays of neighbouring lanes that stay close together. Set by every nearest-hit query (a camera
 * ray is the one that leaves no sphere). */
bool coherent_rays;

#endif

#ifdef TZ_RAY_QUERY_WALK
/* The largest tmax handed to the device: ray queries take finite distances only. */
#define RAY_QUERY_FAR 3.0e38

/* trace_bvh's query through the device's acceleration structure: every AABB candidate it
 * reports is primitive id k (vk_accel.c builds one AABB geometry in primitive order, each box
 * padded so that rounding in the device's box tests never drops a primitive the shared test
 * hits), or face k of the model of the instance whose custom index is one more than its own (the
 * ray moved into its space as trace_bvh moves it, not by the device's transform), tested with the shared test and kept by the tie rule, so the hit is trace_bvh's
 * whatever order the device reports boxes in. A nearer hit is committed at its distance, which
 * lets the device skip boxes beyond it: a box holding a hit at the same distance starts before
 * it by the padding, so ties to a lower index still arrive. With any_hit the first committed hit
 * ends the query (gl_RayFlagsTerminateOnFirstHitEXT). */
int trace_ray_query(vec3 o, vec3 d, int self, float tmax, bool any_hit, out float t_out) {
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    rayQueryEXT query;
    uint flags = any_hit ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT;
    ray_shear sh = shear_of(d);
    /* The ray in the space of the instance of the last candidate (-1: the scene's own). */
    int space = -1, offset = 0, first = 0; /* first: the primitive id of its model's face 0 */
    vec3 mo = o, md = d, minv;
    ray_shear msh = sh;
    rayQueryInitializeEXT(query, scene_accel, flags, 0xffu, o, tmin, d, min(tmax, RAY_QUERY_FAR));
    while (rayQueryProceedEXT(query)) {
        int k = rayQueryGetIntersectionPrimitiveIndexEXT(query, false);
        int instance = TZ_HAS_INSTANCES
                           ? rayQueryGetIntersectionInstanceCustomIndexEXT(query, false) - 1
                           : -1;
        if (instance != space) { /* the model's texel read once a run of its candidates */
            space = instance;
            mo = o, md = d, msh = sh, offset = 0, first = 0;
            if (instance >= 0) {
                uvec4 model = instance_model(instance);
                offset = instance_ray(instance, model, o, d, mo, md, minv, msh);
                first = int(frame.sphere_count + model.y);
            }
        }
        k += first;
        float t = primitive_distance(k, mo, md, msh, tmin, self - offset, best);
        bool nearer = t < best;
        keep_nearer(k + offset, t, best, id);
        if (nearer) rayQueryGenerateIntersectionEXT(query, t);
    }
    t_out = best;
    return id;
}
#endif

/* The walk of this module and ray: with TZ_SUBGROUP_WALK the subgroup's for coherent rays, where
 * the lanes visit much the same nodes; per invocation otherwise (a bounce's rays scatter, and the
 * union of the lanes' nodes would be many times one walk). */
int walk_bvh(vec3 o, vec3 d, int self, float tmax, bool any_hit, out float t_out) {
#ifdef TZ_SUBGROUP_WALK
    if (coherent_rays) return trace_bvh_cooperative(o, d, self, tmax, any_hit, t_out);
#endif
    return trace_bvh(o, d, self, tmax, any_hit, t_out);
}

/* Nearest sphere hit by o + t d with t > EPS, -1 on a miss; t_out is its distance. Through the
 * BVH when the scene has one, else over every sphere with the loop unrolled (sphere_count() a
 * specialization constant): trace_ray of the C back end. */
int integrator_nearest(vec3 o, vec3 d, int self, out float t_out) {
    rays_traced++;
#ifdef TZ_RAY_QUERY_WALK
    return trace_ray_query(o, d, self, TZ_INFINITY, false, t_out);
#else
#ifdef TZ_SUBGROUP_WALK
    coherent_rays = self < 0;
#endif
    if (use_bvh()) return walk_bvh(o, d, self, TZ_INFINITY, false, t_out);
    float tmin = ray_eps(o), best = TZ_INFINITY;
    int id = -1;
    [[unroll]] for (uint k = 0u; k < sphere_count(); k++)
        keep_nearer(int(k), sphere_distance_at(int(k), o, d, tmin, self), best, id);
    if (TZ_HAS_TRIANGLES) {
        ray_shear sh = shear_of(d);
        for (uint k = 0u; k < frame.triangle_count; k++) {
            int t = int(frame.sphere_count + k);
            keep_nearer(t, triangle_distance_at(t, o, sh, tmin, self, best), best, id);
        }
    }
    t_out = best;
    return id;
#endif
}

/* True when a sphere blocks o + t d for EPS < t < dist; glass blocks too, as in the seed. The
 * unrolled loop returns at the first blocker, with no tie rule to keep. */
bool integrator_occluded(vec3 o, vec3 d, float dist, int self) {
    rays_traced++;
    float t;
#ifdef TZ_RAY_QUERY_WALK
    return trace_ray_query(o, d, self, dist, true, t) >= 0;
#else
    if (use_bvh()) return walk_bvh(o, d, self, dist, true, t) >= 0;
    float tmin = ray_eps(o);
    [[unroll]] for (uint k = 0u; k < sphere_count();
                    k++) if (sphere_distance_at(int(k), o, d, tmin, self) < dist) return true;
    if (TZ_HAS_TRIANGLES) {
        ray_shear sh = shear_of(d);
        for (uint k = 0u; k < frame.triangle_count; k++) {
            int t = int(frame.sphere_count + k);
            if (triangle_distance_at(t, o, sh, tmin, self, dist) < dist) return true;
        }
    }
    return false;
#endif
}

#endif
