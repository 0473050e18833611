/* integrator.c: the C reference integrator (DESIGN section 3). Every function here has a twin of
 * the same name in the shaders/ GLSL files; change both and a test in one commit. */
#include "integrator.h"

#include <math.h>
#include <string.h>

#include "rng.h"

/* The sphere loop in an AVX2 clone too, chosen at load time where the processor has it. */
#define SIMD_CLONES __attribute__((target_clones("avx2", "default")))

static vec3 xyz(tz_vec4 v) { return v3(v.x, v.y, v.z); }

/* Ray offset distance at a point: EPS scaled with the point's magnitude. */
static float ray_eps(vec3 p) {
    float m = v3_max_abs(p);
    return TZ_EPS * (m > 1.0f ? m : 1.0f);
}

/* Ray-sphere distances of spheres [begin, begin + SOA_LANES) into t[], INFINITY for a miss or past
 * end: the nearest root greater than tmin, after Haines et al., Ray Tracing Gems ch. 7: disc = r^2
 * - |oc - b d|^2 and q = -b - sign(b) sqrt(disc), roots c/q and q; c = |oc|^2 - r^2 is taken on the
 * largest component of oc, (|m| - r)(|m| + r) + the other two squared, exact when a huge wall
 * sphere's centre lies along an axis from the ray origin. The sphere `self` that the ray leaves is
 * its own origin: moving inward (b < 0) only its far root counts, moving outward it cannot be hit
 * again. Branch-free over SOA_LANES spheres of the padded structure-of-arrays (past `end`:
 * INFINITY), so that it compiles to 8-wide SIMD; each lane does the very operations of the shader's
 * sphere_hit, in the same order. */
SIMD_CLONES static void spheres_hit(const sphere_soa *sp, int begin, int end, vec3 o, vec3 d,
                                    float tmin, int self, float *restrict t) {
    for (int lane = 0; lane < SOA_LANES; lane++) { /* a fixed trip count: one AVX2 iteration */
        int k = begin + lane;
        float ocx = o.x - sp->cx[k], ocy = o.y - sp->cy[k], ocz = o.z - sp->cz[k];
        float r = sp->r[k];
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
        int is_self = k == self;
        int near_ok = (t0 > tmin) & !is_self, far_ok = (t1 > tmin) & (!is_self | (b < 0.0f));
        float near = near_ok ? t0 : far_ok ? t1 : INFINITY;
        int miss = ((c > 0.0f) & (b > 0.0f)) | (disc < 0.0f) | (q == 0.0f);
        t[lane] = (miss | (k >= end)) ? INFINITY : near;
    }
}

/* Tests spheres [begin, end) (at most SOA_LANES) and keeps the nearest hit below *best. An exact
 * tie goes to the lower index, so the order of visits never changes which sphere is seen (both
 * back ends store spheres in the same BVH order, --no-bvh too). */
static void leaf_hit(const packed_scene *p, uint32_t begin, uint32_t end, vec3 o, vec3 d,
                     float tmin, int self, float *best, int *id) {
    float t[SOA_LANES];
    spheres_hit(&p->soa, (int)begin, (int)end, o, d, tmin, self, t);
    for (int lane = 0; lane < SOA_LANES; lane++) {
        int k = (int)begin + lane;
        if (t[lane] < *best || (t[lane] == *best && *id >= 0 && k < *id)) {
            *best = t[lane];
            *id = k;
        }
    }
}

static uint32_t uint_bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* Distance at which the ray enters the node's box, INFINITY when it misses it or enters at or
 * beyond tmax (slab test; inv = 1/d with zero components replaced by 1e30, so no NaN). */
static float box_entry(const struct gpu_bvh_node *n, vec3 o, vec3 inv, float tmax) {
    float x1 = (n->lo.x - o.x) * inv.x, x2 = (n->hi.x - o.x) * inv.x;
    float y1 = (n->lo.y - o.y) * inv.y, y2 = (n->hi.y - o.y) * inv.y;
    float z1 = (n->lo.z - o.z) * inv.z, z2 = (n->hi.z - o.z) * inv.z;
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

/* Rays traced by this thread, for Mrays/s (render_cpu sums the threads'). */
static _Thread_local uint64_t rays_traced;

uint64_t integrator_rays_traced(void) { return rays_traced; }

/* Nearest sphere hit below tmax (*t = its distance), or with any_hit the first one found; -1 when
 * none. Walks the BVH nearer child first with a stack of TZ_BVH_MAX_DEPTH (each level pushes at
 * most one node), or, without a BVH, every sphere SOA_LANES at a time. */
static int trace_ray(const packed_scene *p, vec3 o, vec3 d, int self, float tmax, int any_hit,
                     float *t) {
    rays_traced++;
    float tmin = ray_eps(o), best = tmax;
    int id = -1;
    uint32_t count = p->frame.size.z, node_count = p->frame.settings.w;
    if (node_count == 0) {
        for (uint32_t begin = 0; begin < count && !(any_hit && id >= 0); begin += SOA_LANES)
            leaf_hit(p, begin, begin + SOA_LANES < count ? begin + SOA_LANES : count, o, d, tmin,
                     self, &best, &id);
        *t = best;
        return id;
    }
    vec3 inv = v3(d.x != 0.0f ? 1.0f / d.x : 1e30f, d.y != 0.0f ? 1.0f / d.y : 1e30f,
                  d.z != 0.0f ? 1.0f / d.z : 1e30f);
    uint32_t stack[TZ_BVH_MAX_DEPTH];
    float stack_t[TZ_BVH_MAX_DEPTH];
    int top = 0;
    /* The root's box holds every sphere: testing it would only repeat the leaves' work. */
    uint32_t node = 0;
    int go = 1;
    while (go) {
        const struct gpu_bvh_node *n = &p->nodes[node];
        uint32_t leaf_count = uint_bits(n->hi.w);
        if (leaf_count > 0) {
            uint32_t first = uint_bits(n->lo.w);
            leaf_hit(p, first, first + leaf_count, o, d, tmin, self, &best, &id);
            if (any_hit && id >= 0) break;
        } else {
            uint32_t left = node + 1, right = uint_bits(n->lo.w);
            float tl = box_entry(&p->nodes[left], o, inv, best);
            float tr = box_entry(&p->nodes[right], o, inv, best);
            if (tl < INFINITY || tr < INFINITY) {
                int left_first = tl <= tr;
                node = left_first ? left : right;
                float other_t = left_first ? tr : tl;
                if (other_t < INFINITY) {
                    stack[top] = left_first ? right : left;
                    stack_t[top++] = other_t;
                }
                continue;
            }
        }
        go = 0; /* pop the nearest pending node that can still hold a nearer hit */
        while (top > 0 && !go) {
            top--;
            node = stack[top];
            go = stack_t[top] < best;
        }
    }
    *t = best;
    return id;
}

int integrator_nearest(const packed_scene *p, vec3 o, vec3 d, int self, float *t_out) {
    return trace_ray(p, o, d, self, INFINITY, 0, t_out);
}

int integrator_occluded(const packed_scene *p, vec3 o, vec3 d, float dist, int self) {
    float t;
    return trace_ray(p, o, d, self, dist, 1, &t) >= 0;
}

/* Normalized Phong BRDF: kd/pi + ks (alpha+2)/(2 pi) max(0, wo.wr)^alpha, wr = 2(n.wi)n - wi. */
static vec3 phong_brdf(const struct gpu_sphere *s, vec3 n, vec3 wi, vec3 wo) {
    vec3 f = v3_scale(xyz(s->color_ks), 1.0f / TZ_PI);
    float ks = s->color_ks.w;
    if (ks > 0.0f) {
        vec3 wr = v3_sub(v3_scale(n, 2.0f * v3_dot(n, wi)), wi);
        float x = v3_dot(wo, wr);
        /* 0^alpha is taken as 0 (even for alpha 0) so both back ends agree on it. */
        float lobe = x > 0.0f ? powf(x, s->params.x) : 0.0f;
        float spec = ks * (s->params.x + 2.0f) / (2.0f * TZ_PI) * lobe;
        f = v3_add(f, v3(spec, spec, spec));
    }
    return f;
}

/* Direct light from every point light at p (shading normal n, facing wo) on sphere id. */
static vec3 direct_light(const packed_scene *p, int id, vec3 pos, vec3 n, vec3 wo) {
    const struct gpu_sphere *s = &p->spheres[id];
    vec3 o = v3_add(pos, v3_scale(n, ray_eps(pos)));
    vec3 sum = v3(0.0f, 0.0f, 0.0f);
    uint32_t count = p->frame.size.w;
    for (uint32_t k = 0; k < count; k++) {
        const struct gpu_light *l = &p->lights[k];
        /* Distance and angle from the true hit point; only the shadow ray starts off the surface.
         */
        vec3 to_light = v3_sub(xyz(l->position_power), pos);
        float dist2 = v3_dot(to_light, to_light);
        float dist = sqrtf(dist2);
        vec3 wi = v3_scale(to_light, 1.0f / dist);
        float cos_i = v3_dot(n, wi);
        if (cos_i <= 0.0f || integrator_occluded(p, o, wi, dist, id)) continue;
        vec3 f = phong_brdf(s, n, wi, wo);
        float scale = cos_i * l->position_power.w / dist2;
        sum = v3_add(sum, v3_mul(f, v3_scale(xyz(l->color), scale)));
    }
    return sum;
}

/* Duff et al. 2017 orthonormal basis (t, b) around unit n. */
static void basis(vec3 n, vec3 *t, vec3 *b) {
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + n.z);
    float c = n.x * n.y * a;
    *t = v3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    *b = v3(c, sign + n.y * n.y * a, -n.y);
}

/* Follows a ray through mirrors and glass to a diffuse hit. Returns the sphere id (-1 on a miss,
 * -2 when the chain exceeds the bounce limit); *o, *d become the last ray, *weight the tints. */
static int follow_specular(const packed_scene *p, vec3 *o, vec3 *d, int self, vec3 *weight,
                           vec3 *pos, vec3 *n) {
    uint32_t bounces = p->frame.settings.y;
    for (uint32_t chain = 0;; chain++) {
        float t;
        int id = integrator_nearest(p, *o, *d, self, &t);
        if (id < 0) return -1;
        const struct gpu_sphere *s = &p->spheres[id];
        *pos = v3_add(*o, v3_scale(*d, t));
        vec3 nout = v3_scale(v3_sub(*pos, xyz(s->center_radius)), 1.0f / s->center_radius.w);
        int material = (int)s->params.z;
        if (material == TZ_MATERIAL_LAMBERTIAN || material == TZ_MATERIAL_PHONG) {
            /* Opaque surfaces are two-sided: shade with the normal facing the ray. */
            *n = v3_dot(nout, *d) < 0.0f ? nout : v3_scale(nout, -1.0f);
            return id;
        }
        if (chain == bounces) return -2;
        *weight = v3_mul(*weight, xyz(s->color_ks));
        float eps = ray_eps(*pos);
        int entering = v3_dot(*d, nout) < 0.0f;
        vec3 side = entering ? nout : v3_scale(nout, -1.0f); /* faces the incoming ray */
        vec3 reflected = v3_sub(*d, v3_scale(side, 2.0f * v3_dot(side, *d)));
        vec3 next_o = v3_add(*pos, v3_scale(side, eps));
        vec3 next_d = reflected;
        if (material == TZ_MATERIAL_REFRACTIVE) {
            float eta = entering ? 1.0f / s->params.y : s->params.y;
            float c1 = -v3_dot(*d, side);
            float k = 1.0f - eta * eta * (1.0f - c1 * c1);
            if (k >= 0.0f) { /* otherwise total internal reflection: keep the reflected ray */
                next_d = v3_add(v3_scale(*d, eta), v3_scale(side, eta * c1 - sqrtf(k)));
                next_d = v3_normalize(next_d);
                next_o = v3_sub(*pos, v3_scale(side, eps));
            }
        }
        *o = next_o;
        *d = next_d;
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
    float cos_t = sqrtf(1.0f - y1), sin_t = sqrtf(y1), phi = 2.0f * TZ_PI * y2;
    vec3 t, b;
    basis(n, &t, &b);
    vec3 wi = v3_add(v3_add(v3_scale(t, sin_t * cosf(phi)), v3_scale(b, sin_t * sinf(phi))),
                     v3_scale(n, cos_t));
    vec3 o = v3_add(pos, v3_scale(n, ray_eps(pos)));
    vec3 incoming = radiance_direct_only(p, o, wi, id);
    float pdf = cos_t / TZ_PI;
    vec3 f = phong_brdf(&p->spheres[id], n, wi, wo);
    return v3_mul(f, v3_scale(incoming, cos_t / pdf));
}

/* Primary ray through the plane point of pixel (i, j) offset by (u, v) in pixels. */
static vec3 camera_direction(const struct gpu_frame *fr, uint32_t i, uint32_t j, float u, float v) {
    float pixel = fr->origin.w;
    float x = fr->right.w + ((float)i + u) * pixel;
    float y = fr->up.w - ((float)j + v) * pixel;
    vec3 d = v3_add(v3_add(v3_scale(xyz(fr->right), x), v3_scale(xyz(fr->up), y)),
                    v3_scale(xyz(fr->forward), fr->forward.w));
    return v3_normalize(d);
}

vec3 integrator_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index) {
    const struct gpu_frame *fr = &p->frame;
    uint32_t rng = rng_seed(fr->settings.x, j * fr->size.x + i, sample_index);
    /* Both jitter numbers are always drawn so the indirect numbers do not depend on the flag. */
    float u = rng_next(&rng), v = rng_next(&rng);
    if (!(fr->settings.z & TZ_FLAG_JITTER)) u = v = 0.5f;
    vec3 o = xyz(fr->origin), d = camera_direction(fr, i, j, u, v);
    vec3 weight = v3(1.0f, 1.0f, 1.0f), pos, n;
    int id = follow_specular(p, &o, &d, -1, &weight, &pos, &n);
    if (id == -1) return v3_mul(weight, xyz(fr->background));
    if (id == -2) return v3(0.0f, 0.0f, 0.0f);
    vec3 wo = v3_scale(d, -1.0f);
    vec3 radiance = direct_light(p, id, pos, n, wo);
    if (fr->settings.z & TZ_FLAG_INDIRECT)
        radiance = v3_add(radiance, indirect_light(p, id, pos, n, wo, &rng));
    return v3_mul(weight, radiance);
}
