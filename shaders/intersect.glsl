/* intersect.glsl: ray offsets, ray/sphere intersection, nearest-hit and shadow queries over the
 * spheres; twin of the functions of the same names in src/integrator.c. The including shader
 * declares `frame`, sphere_center_radius() and sphere_count(). */
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
 * of spheres_hit() in src/integrator.c in the same order, with one read of the sphere. */
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

/* Nearest sphere hit by o + t d with t > EPS, -1 on a miss; t_out is its distance. An exact tie
 * goes to the sphere written first in the scene (params.w), as in leaf_hit() of the C integrator,
 * whatever order the spheres are stored or visited in. [[unroll]] takes effect when
 * sphere_count() is a specialization constant. */
int integrator_nearest(vec3 o, vec3 d, int self, out float t_out) {
    float tmin = ray_eps(o), best = TZ_INFINITY;
    float best_written = -1.0; /* below every index: a miss never wins a tie at infinity */
    int id = -1;
    [[unroll]] for (uint k = 0u; k < sphere_count(); k++) {
        float t = sphere_hit(int(k), o, d, tmin, self);
        float written = sphere_params(int(k)).w;
        /* Selects, not branches: lavapipe runs both sides of a branch for the whole subgroup. */
        bool take = t < best || (t == best && written < best_written);
        best = take ? t : best;
        id = take ? int(k) : id;
        best_written = take ? written : best_written;
    }
    t_out = best;
    return id;
}

/* True when a sphere blocks o + t d for EPS < t < dist; glass blocks too, as in the seed. */
bool occluded(vec3 o, vec3 d, float dist, int self) {
    float tmin = ray_eps(o);
    [[unroll]] for (uint k = 0u; k < sphere_count(); k++)
        if (sphere_hit(int(k), o, d, tmin, self) < dist) return true;
    return false;
}

#endif
