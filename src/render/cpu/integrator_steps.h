/* integrator_steps.h: the per-ray steps of the C integrator, shared by the one-sample integrator
 * (integrator.c) and the packet integrator (integrator_packet.c), so that both do the very same
 * floating-point operations in the same order. The ray and shading steps have twins in the
 * shaders/ GLSL files (named at each); the small vector helpers are written inline there. */
#ifndef TRAZADOR_INTEGRATOR_STEPS_H
#define TRAZADOR_INTEGRATOR_STEPS_H

#include <math.h>
#include <stdint.h>
#include <string.h>

#include "shared_layout.h"
#include "util/vec3.h"

/* xyz of a packed vec4. */
static inline vec3 xyz(tz_vec4 v) { return v3(v.x, v.y, v.z); }

/* a where c is true, else b, component by component (selects, not branches: SIMD-friendly). */
static inline vec3 select3(int c, vec3 a, vec3 b) {
    return v3(c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z);
}

/* Ray offset distance at a point: EPS scaled with the point's magnitude. */
static inline float ray_eps(vec3 p) {
    float m = v3_max_abs(p);
    return TZ_EPS * (m > 1.0f ? m : 1.0f);
}

/* Distance to the sphere (centre c, radius r) along o + t d: the nearest root greater than tmin,
 * INFINITY for a miss; after Haines et al., Ray Tracing Gems ch. 7: disc = r^2 - |oc - b d|^2 and
 * q = -b - sign(b) sqrt(disc), roots c/q and q; c = |oc|^2 - r^2 is taken on the largest
 * component of oc, (|m| - r)(|m| + r) + the other two squared, exact when a huge wall sphere's
 * centre lies along an axis from the ray origin. When the ray leaves this very sphere (is_self),
 * moving inward (b < 0) only its far root counts, moving outward it cannot be hit again.
 * Branch-free, so that loops over spheres or rays compile to SIMD; the operations of the shader's
 * sphere_hit in the same order. */
static inline float sphere_distance(float cx, float cy, float cz, float r, vec3 o, vec3 d,
                                    float tmin, int is_self) {
    float ocx = o.x - cx, ocy = o.y - cy, ocz = o.z - cz;
    float b = ocx * d.x + ocy * d.y + ocz * d.z;
    float ax = ocx < 0.0f ? -ocx : ocx, ay = ocy < 0.0f ? -ocy : ocy;
    float az = ocz < 0.0f ? -ocz : ocz;
    float xx = ocx * ocx, yy = ocy * ocy, zz = ocz * ocz;
    int x_big = (ax >= ay) & (ax >= az), y_big = !x_big & (ay >= az);
    float big = x_big ? ax : y_big ? ay : az;
    float other1 = x_big ? yy : xx, other2 = x_big | y_big ? zz : yy;
    float c = (big - r) * (big + r) + other1 + other2;
    float fx = ocx - b * d.x, fy = ocy - b * d.y, fz = ocz - b * d.z;
    float l = sqrtf(fx * fx + fy * fy + fz * fz);
    float disc = (r - l) * (r + l);
    float root = sqrtf(disc < 0.0f ? 0.0f : disc);
    float q = b > 0.0f ? -b - root : -b + root;
    float cq = c / q;
    float t0 = cq < q ? cq : q, t1 = cq < q ? q : cq;
    int near_ok = (t0 > tmin) & !is_self, far_ok = (t1 > tmin) & (!is_self | (b < 0.0f));
    float near = near_ok ? t0 : far_ok ? t1 : INFINITY;
    int miss = ((c > 0.0f) & (b > 0.0f)) | (disc < 0.0f) | (q == 0.0f);
    return miss ? INFINITY : near;
}

/* The origin of a ray leaving surface point p on the side its normal n points to. */
static inline vec3 offset_origin(vec3 p, vec3 n) { return v3_add(p, v3_scale(n, ray_eps(p))); }

/* 1 when sphere k at distance t replaces the nearest hit so far (id at best): nearer, or as near
 * with a lower index, so the order of visits never changes which sphere is seen. */
static inline int nearer_hit(float t, int k, float best, int id) {
    return (t < best) | ((t == best) & (id >= 0) & (k < id));
}

/* The bits of a float (the BVH stores indices in floats' places). */
static inline uint32_t uint_bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* The sphere count of a child reference (0: an inner node) and its index (node or first sphere).
 */
static inline uint32_t child_count(uint32_t ref) { return ref >> TZ_BVH_COUNT_SHIFT; }
static inline uint32_t child_index(uint32_t ref) { return ref & TZ_BVH_INDEX_MASK; }

/* 1/d with zero components of d replaced by 1e30 first, so the slab test has no NaN. */
static inline vec3 inverse_direction(vec3 d) {
    return v3(d.x != 0.0f ? 1.0f / d.x : 1e30f, d.y != 0.0f ? 1.0f / d.y : 1e30f,
              d.z != 0.0f ? 1.0f / d.z : 1e30f);
}

/* Distance at which the ray enters the box lo..hi, INFINITY when it misses it or enters at or
 * beyond tmax (slab test; inv from inverse_direction). */
static inline float box_entry(const tz_vec4 *lo, const tz_vec4 *hi, vec3 o, vec3 inv, float tmax) {
    float x1 = (lo->x - o.x) * inv.x, x2 = (hi->x - o.x) * inv.x;
    float y1 = (lo->y - o.y) * inv.y, y2 = (hi->y - o.y) * inv.y;
    float z1 = (lo->z - o.z) * inv.z, z2 = (hi->z - o.z) * inv.z;
    float near = x1 < x2 ? x1 : x2, far = x1 < x2 ? x2 : x1;
    float ny = y1 < y2 ? y1 : y2, fy = y1 < y2 ? y2 : y1;
    float nz = z1 < z2 ? z1 : z2, fz = z1 < z2 ? z2 : z1;
    near = near > ny ? near : ny;
    near = near > nz ? near : nz;
    near = near > 0.0f ? near : 0.0f;
    far = far < fy ? far : fy;
    far = far < fz ? far : fz;
    return near <= far && near < tmax ? near : INFINITY;
}

/* Normal of an opaque (two-sided) surface facing the ray d, from the outward normal. */
static inline vec3 facing_normal(vec3 nout, vec3 d) {
    return select3(v3_dot(nout, d) < 0.0f, nout, v3_scale(nout, -1.0f));
}

/* The ray leaving a mirror or glass hit at pos (outward normal nout, incoming d): the mirror ray,
 * or with refractive the refracted one (Snell's law; total internal reflection keeps the mirror
 * ray); *next_o is offset by eps to the side the ray leaves on. */
static inline void specular_next(vec3 pos, vec3 nout, vec3 d, int refractive, float ior,
                                 vec3 *next_o, vec3 *next_d) {
    float eps = ray_eps(pos);
    int entering = v3_dot(d, nout) < 0.0f;
    vec3 side = select3(entering, nout, v3_scale(nout, -1.0f)); /* faces the incoming ray */
    /* Normalized: nout is unit only to rounding, and the error of an unnormalized mirror ray
     * grows with each reflection until a ray escapes a closed mirror (the sphere test assumes
     * |d| = 1). */
    vec3 mirror_d = v3_normalize(v3_sub(d, v3_scale(side, 2.0f * v3_dot(side, d))));
    float eta = entering ? 1.0f / ior : ior;
    float c1 = -v3_dot(d, side);
    float k = 1.0f - eta * eta * (1.0f - c1 * c1);
    /* k < 0: total internal reflection, the mirror ray (the refracted one is NaN, unused). */
    int refracts = refractive & (k >= 0.0f);
    vec3 refracted_d = v3_normalize(v3_add(v3_scale(d, eta), v3_scale(side, eta * c1 - sqrtf(k))));
    *next_d = select3(refracts, refracted_d, mirror_d);
    *next_o = v3_add(pos, v3_scale(side, refracts ? -eps : eps));
}

/* Cosine of the Phong lobe angle: wo . wr with wr = 2(n.wi)n - wi. */
static inline float phong_lobe_cos(vec3 n, vec3 wi, vec3 wo) {
    vec3 wr = v3_sub(v3_scale(n, 2.0f * v3_dot(n, wi)), wi);
    return v3_dot(wo, wr);
}

/* Normalized Phong BRDF kd/pi + ks (alpha+2)/(2 pi) lobe, lobe = max(0, wo.wr)^alpha (0^alpha
 * taken as 0, even for alpha 0, so both back ends agree on it); ks 0 is Lambertian. */
static inline vec3 phong_from_lobe(vec3 kd, float ks, float alpha, float lobe) {
    vec3 f = v3_scale(kd, 1.0f / TZ_PI);
    float spec = ks * (alpha + 2.0f) / (2.0f * TZ_PI) * lobe;
    return ks > 0.0f ? v3_add(f, v3(spec, spec, spec)) : f;
}

/* The lobe of phong_from_lobe: x^alpha for x > 0, else 0. */
static inline float phong_lobe(float x, float alpha) { return x > 0.0f ? powf(x, alpha) : 0.0f; }

/* Light arriving from a point light at pos (power/dist^2 times its colour, times cos_i), before
 * the BRDF; *wi the unit direction to it, *dist its distance, *cos_i = n . wi. */
static inline vec3 point_light(const struct gpu_light *l, vec3 pos, vec3 n, vec3 *wi, float *dist,
                               float *cos_i) {
    vec3 to_light = v3_sub(xyz(l->position_power), pos);
    float dist2 = v3_dot(to_light, to_light);
    *dist = sqrtf(dist2);
    *wi = v3_scale(to_light, 1.0f / *dist);
    *cos_i = v3_dot(n, *wi);
    return v3_scale(xyz(l->color), *cos_i * l->position_power.w / dist2);
}

/* Cosine-weighted direction around unit n for uniform numbers y1 (cos = sqrt(1 - y1)) and the
 * cosine and sine of phi = 2 pi y2; tangent frame after Duff et al. 2017. */
static inline vec3 cosine_direction(vec3 n, float y1, float cos_phi, float sin_phi) {
    float cos_t = sqrtf(1.0f - y1), sin_t = sqrtf(y1);
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float c = n.x * n.y * a;
    vec3 t = v3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    vec3 b = v3(c, sign + n.y * n.y * a, -n.y);
    return v3_add(v3_add(v3_scale(t, sin_t * cos_phi), v3_scale(b, sin_t * sin_phi)),
                  v3_scale(n, cos_t));
}

/* Primary ray direction through the plane point of pixel (i, j) offset by (u, v) pixels. */
static inline vec3 camera_direction(const struct gpu_frame *fr, uint32_t i, uint32_t j, float u,
                                    float v) {
    float pixel = fr->origin.w;
    float x = fr->right.w + ((float)i + u) * pixel;
    float y = fr->up.w - ((float)j + v) * pixel;
    vec3 d = v3_add(v3_add(v3_scale(xyz(fr->right), x), v3_scale(xyz(fr->up), y)),
                    v3_scale(xyz(fr->forward), fr->forward.w));
    return v3_normalize(d);
}

#endif
