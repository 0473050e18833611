/* shade.glsl: the GLSL back end's path of a sample after its camera ray: the specular chain,
 * direct light and the one indirect bounce, on the shared steps of common/shade.h and
 * common/rng.h. The C back end's are the functions of the same names in
 * src/render/cpu/integrator.c; both draw the same random numbers in the same order. The
 * including shader declares `frame` and the sphere_*(), light_*() accessors. */
#ifndef TRAZADOR_SHADE_GLSL
#define TRAZADOR_SHADE_GLSL

#include "common/rng.h"
#include "common/shade.h"
#include "intersect.glsl"

/* The Phong BRDF of sphere id (phong_brdf). */
vec3 sphere_brdf(int id, vec3 n, vec3 wi, vec3 wo) {
    vec4 color_ks = sphere_color_ks(id);
    return phong_brdf(color_ks.xyz, color_ks.w, sphere_params(id).x, n, wi, wo);
}

/* Direct light from every point light at pos (shading normal n, facing wo) on sphere id. */
vec3 direct_light(int id, vec3 pos, vec3 n, vec3 wo) {
    vec3 o = offset_origin(pos, n);
    precise vec3 sum = vec3(0.0);
    [[unroll]] for (uint k = 0u; k < light_count(); k++) {
        light_sample l = point_light(light_position_power(int(k)), light_color(int(k)), pos, n);
        if (l.cos_i <= 0.0 || integrator_occluded(o, l.wi, l.dist, id)) continue;
        sum = sum + sphere_brdf(id, n, l.wi, wo) * l.radiance;
    }
    return sum;
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
            n = facing_normal(nout, d);
            return id;
        }
        if (chain == bounces) return -2;
        precise vec3 tinted = weight * sphere_color_ks(id).xyz;
        weight = tinted;
        next_ray next = specular_next(hit, nout, d, material == TZ_MATERIAL_REFRACTIVE, params.y);
        o = next.o;
        d = next.d;
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
    precise float phi = 2.0 * TZ_PI * y2;
    precise float cos_phi = cos(phi), sin_phi = sin(phi);
    vec3 wi = cosine_direction(n, y1, cos_phi, sin_phi);
    vec3 o = offset_origin(pos, n);
    vec3 incoming = radiance_direct_only(o, wi, id);
    precise float pdf = cos_t / TZ_PI;
    vec3 f = sphere_brdf(id, n, wi, wo);
    precise vec3 r = f * (incoming * (cos_t / pdf));
    return r;
}

#endif
