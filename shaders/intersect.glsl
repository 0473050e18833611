/* intersect.glsl: ray offsets, ray/sphere intersection, nearest-hit and shadow queries over the
 * sphere buffer; twin of the functions of the same names in src/integrator.c. The including
 * shader declares `frame` and `spheres`. */
#ifndef TRAZADOR_INTERSECT_GLSL
#define TRAZADOR_INTERSECT_GLSL

#include "vec3.glsl"

#define TZ_INFINITY uintBitsToFloat(0x7f800000u)

/* Ray offset distance at a point: EPS scaled with the point's magnitude. */
float ray_eps(vec3 p) {
    precise float r = TZ_EPS * max(1.0, v3_max_abs(p));
    return r;
}

/* |oc|^2 - r^2 without cancellation: the largest component carries r. */
float sphere_c(vec3 oc, float r) {
    float ax = abs(oc.x), ay = abs(oc.y), az = abs(oc.z);
    precise float c;
    if (ax >= ay && ax >= az) c = (ax - r) * (ax + r) + oc.y * oc.y + oc.z * oc.z;
    else if (ay >= az) c = (ay - r) * (ay + r) + oc.x * oc.x + oc.z * oc.z;
    else c = (az - r) * (az + r) + oc.x * oc.x + oc.y * oc.y;
    return c;
}

/* Nearest root of sphere k greater than tmin (the far one only when far_only), or infinity;
 * Haines et al., Ray Tracing Gems ch. 7. */
float sphere_hit(uint k, vec3 o, vec3 d, float tmin, bool far_only) {
    vec4 cr = spheres[k].center_radius;
    precise vec3 oc = o - cr.xyz;
    float r = cr.w;
    precise float b = v3_dot(oc, d);
    precise float c = sphere_c(oc, r);
    if (c > 0.0 && b > 0.0) return TZ_INFINITY; /* outside and moving away */
    precise float l = v3_length(oc - d * b);
    precise float disc = (r - l) * (r + l);
    if (disc < 0.0) return TZ_INFINITY;
    precise float q = b > 0.0 ? -b - sqrt(disc) : -b + sqrt(disc);
    if (q == 0.0) return TZ_INFINITY;
    precise float cq = c / q;
    float t0 = min(cq, q), t1 = max(cq, q);
    if (!far_only && t0 > tmin) return t0;
    return t1 > tmin ? t1 : TZ_INFINITY;
}

/* For the sphere the ray leaves: -1 to skip it (outward ray), 1 far root only, 0 normal. */
int self_mode(int k, int self, vec3 o, vec3 d) {
    if (k != self) return 0;
    precise vec3 n = o - spheres[k].center_radius.xyz;
    return v3_dot(n, d) < 0.0 ? 1 : -1;
}

/* Nearest sphere hit by o + t d with t > EPS, -1 on a miss; t_out is its distance. */
int integrator_nearest(vec3 o, vec3 d, int self, out float t_out) {
    float tmin = ray_eps(o), best = TZ_INFINITY;
    int id = -1;
    uint count = frame.size.z;
    for (uint k = 0u; k < count; k++) {
        int mode = self_mode(int(k), self, o, d);
        if (mode < 0) continue;
        float t = sphere_hit(k, o, d, tmin, mode == 1);
        if (t < best) {
            best = t;
            id = int(k);
        }
    }
    t_out = best;
    return id;
}

/* True when a sphere blocks o + t d for EPS < t < dist; glass blocks too, as in the seed. */
bool occluded(vec3 o, vec3 d, float dist, int self) {
    float tmin = ray_eps(o);
    uint count = frame.size.z;
    for (uint k = 0u; k < count; k++) {
        int mode = self_mode(int(k), self, o, d);
        if (mode < 0) continue;
        if (sphere_hit(k, o, d, tmin, mode == 1) < dist) return true;
    }
    return false;
}

#endif
