/* shade.glsl: the Phong BRDF, direct light, the specular chain and the one indirect bounce;
 * twin of the functions of the same names in src/integrator.c and src/integrator_steps.h (basis
 * and the bounce direction: cosine_direction()), in the same operation order and
 * drawing the same random numbers. The including shader declares `frame` and the sphere_*(),
 * light_*() accessors. */
#ifndef TRAZADOR_SHADE_GLSL
#define TRAZADOR_SHADE_GLSL

#include "intersect.glsl"
#include "rng.glsl"

/* Normalized Phong BRDF: kd/pi + ks (alpha+2)/(2 pi) max(0, wo.wr)^alpha, wr = 2(n.wi)n - wi. */
vec3 phong_brdf(int id, vec3 n, vec3 wi, vec3 wo) {
    vec4 color_ks = sphere_color_ks(id);
    float alpha = sphere_params(id).x;
    precise vec3 f = color_ks.xyz * (1.0 / TZ_PI);
    float ks = color_ks.w;
    if (ks > 0.0) {
        precise vec3 wr = n * (2.0 * v3_dot(n, wi)) - wi;
        float x = v3_dot(wo, wr);
        /* 0^alpha is taken as 0 (even for alpha 0) so both back ends agree on it. */
        float lobe = x > 0.0 ? pow(x, alpha) : 0.0;
        precise float spec = ks * (alpha + 2.0) / (2.0 * TZ_PI) * lobe;
        f = f + vec3(spec, spec, spec);
    }
    return f;
}

/* Direct light from every point light at pos (shading normal n, facing wo) on sphere id. */
vec3 direct_light(int id, vec3 pos, vec3 n, vec3 wo) {
    precise vec3 o = pos + n * ray_eps(pos);
    precise vec3 sum = vec3(0.0);
    [[unroll]] for (uint k = 0u; k < light_count(); k++) {
        vec4 position_power = light_position_power(int(k));
        /* Distance and angle from the true hit point; only the shadow ray starts off the
         * surface. */
        precise vec3 to_light = position_power.xyz - pos;
        precise float dist2 = v3_dot(to_light, to_light);
        precise float dist = sqrt(dist2);
        precise vec3 wi = to_light * (1.0 / dist);
        float cos_i = v3_dot(n, wi);
        if (cos_i <= 0.0 || integrator_occluded(o, wi, dist, id)) continue;
        vec3 f = phong_brdf(id, n, wi, wo);
        precise float scale = cos_i * position_power.w / dist2;
        sum = sum + f * (light_color(int(k)).xyz * scale);
    }
    return sum;
}

/* Duff et al. 2017 orthonormal basis (t, b) around unit n. */
void basis(vec3 n, out vec3 t, out vec3 b) {
    float sign = n.z >= 0.0 ? 1.0 : -1.0;
    precise float a = -1.0 / (sign + n.z);
    precise float c = n.x * n.y * a;
    precise vec3 tt = vec3(1.0 + sign * n.x * n.x * a, sign * c, -sign * n.x);
    precise vec3 bb = vec3(c, sign + n.y * n.y * a, -n.y);
    t = tt;
    b = bb;
}

/* Follows a ray through mirrors and glass to a diffuse hit. Returns the sphere id (-1 on a miss,
 * -2 past the bounce limit); o, d become the last ray, weight the product of the tints. */
int follow_specular(inout vec3 o, inout vec3 d, int self, inout vec3 weight, out vec3 pos,
                    out vec3 n) {
    uint bounces = frame.bounces;
    pos = vec3(0.0);
    n = vec3(0.0);
    for (uint chain = 0u;; chain++) {
        float t;
        int id = integrator_nearest(o, d, self, t);
        if (id < 0) return -1;
        vec4 cr = sphere_center_radius(id);
        precise vec3 hit = o + d * t;
        pos = hit;
        precise vec3 nout = (hit - cr.xyz) * (1.0 / cr.w);
        vec4 params = sphere_params(id);
        int material = int(params.z);
        if (material == TZ_MATERIAL_LAMBERTIAN || material == TZ_MATERIAL_PHONG) {
            /* Opaque surfaces are two-sided: shade with the normal facing the ray. */
            n = v3_dot(nout, d) < 0.0 ? nout : nout * -1.0;
            return id;
        }
        if (chain == bounces) return -2;
        precise vec3 tinted = weight * sphere_color_ks(id).xyz;
        weight = tinted;
        float eps = ray_eps(hit);
        bool entering = v3_dot(d, nout) < 0.0;
        precise vec3 side = entering ? nout : nout * -1.0; /* faces the incoming ray */
        /* Normalized, as in the C twin: errors of |d| would grow reflection by reflection. */
        precise vec3 reflected = v3_normalize(d - side * (2.0 * v3_dot(side, d)));
        precise vec3 next_o = hit + side * eps;
        precise vec3 next_d = reflected;
        if (material == TZ_MATERIAL_REFRACTIVE) {
            float ior = params.y;
            precise float eta = entering ? 1.0 / ior : ior;
            precise float c1 = -v3_dot(d, side);
            precise float k = 1.0 - eta * eta * (1.0 - c1 * c1);
            if (k >= 0.0) { /* otherwise total internal reflection: keep the reflected ray */
                next_d = v3_normalize(d * eta + side * (eta * c1 - sqrt(k)));
                next_o = hit - side * eps;
            }
        }
        o = next_o;
        d = next_d;
        self = id;
    }
}

/* Radiance along a ray: background on a miss, black past the bounce limit, else the direct
 * light of the diffuse surface it reaches through mirrors and glass, times their tints. */
vec3 radiance_direct_only(vec3 o, vec3 d, int self) {
    vec3 weight = vec3(1.0), pos, n;
    int id = follow_specular(o, d, self, weight, pos, n);
    precise vec3 r;
    if (id == -1) r = weight * frame.background.xyz;
    else if (id == -2) r = vec3(0.0);
    else r = weight * direct_light(id, pos, n, d * -1.0);
    return r;
}

/* One cosine-weighted bounce at a diffuse hit: theta = acos(sqrt(1 - y1)), phi = 2 pi y2,
 * pdf = cos(theta) / pi; returns f_r * L_direct * cos / pdf. */
vec3 indirect_light(int id, vec3 pos, vec3 n, vec3 wo, inout uint rng) {
    float y1 = rng_next(rng);
    float y2 = rng_next(rng);
    precise float cos_t = sqrt(1.0 - y1);
    precise float sin_t = sqrt(y1);
    precise float phi = 2.0 * TZ_PI * y2;
    vec3 t, b;
    basis(n, t, b);
    precise vec3 wi = t * (sin_t * cos(phi)) + b * (sin_t * sin(phi)) + n * cos_t;
    precise vec3 o = pos + n * ray_eps(pos);
    vec3 incoming = radiance_direct_only(o, wi, id);
    precise float pdf = cos_t / TZ_PI;
    vec3 f = phong_brdf(id, n, wi, wo);
    precise vec3 r = f * (incoming * (cos_t / pdf));
    return r;
}

#endif
