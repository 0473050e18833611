/* report.h: report mode's sample (DESIGN section 3.1, the course report's model), one text for
 * C and GLSL (dialect.h) over the scene accessors that path.h names: the specular chain, the
 * point lights and the one indirect bounce, drawing the same numbers in the same order on every
 * back end. */
#ifndef TRAZADOR_COMMON_REPORT_H
#define TRAZADOR_COMMON_REPORT_H

#include "bsdf.h"
#include "camera.h"
#include "dialect.h"
#include "emitter.h"
#include "lights.h"
#include "primitive.h"
#include "ray.h"
#include "sampler.h"
#include "shade.h"

/* Where a ray led through mirrors and glass: id the diffuse primitive reached (-1 on a miss, -2
 * past the bounce limit), d the last ray's direction, weight the product of the tints, s the
 * surface hit, n and ng its shading and geometric normals facing the ray. */
TZ_STRUCT(specular_chain) {
    int id;
    vec3 d;
    vec3 weight;
    surface s;
    vec3 n;
    vec3 ng;
}
TZ_STRUCT_END(specular_chain)

/* Follows the ray o + t d (leaving primitive self) through mirrors and glass to a diffuse hit. */
TZ_FN specular_chain follow_specular(TZ_SCENE_PARAM vec3 o, vec3 d, int self) {
    specular_chain c;
    c.id = -1;
    c.s = surface_none();
    c.n = c.s.nout;
    c.ng = c.s.nout;
    /* Not precise: products alone cannot be fused, and glslang's propagation of precise back
     * through the surfaces of the loop grows without bound (past 20 GB). */
    vec3 weight = v3(1.0f, 1.0f, 1.0f);
    for (TZ_UINT chain = 0u;; chain++) {
        float t;
        int id = integrator_nearest(TZ_SCENE_ARG o, d, self, TZ_REF(t));
        c.d = d;
        c.weight = weight;
        if (id < 0) return c;
        surface s = surface_at(TZ_SCENE_ARG id, o, d, t);
        c.s = s;
        if (!bsdf_is_delta(s.m.kind)) {
            c.s.m.ior = bsdf_eta(s.m.kind, s.m.ior, s.nout, d);
            c.n = facing_shading(s, d);
            c.ng = facing_normal(s.nout, d);
            c.id = id;
            return c;
        }
        if (chain == TZ_FRAME.bounces) {
            c.id = -2;
            return c;
        }
        weight = v3_mul(weight, s.m.color);
        next_ray next = specular_next(s.pos, s.nout, specular_normal(s.nout, s.shading, d), d,
                                      bsdf_refracts(s.m.kind), s.m.ior);
        o = next.o;
        d = next.d;
        self = id;
    }
}

/* The radiance a chain ends with, before its tints: the environment's on a miss, black past the
 * bounce limit, else the point lights at its diffuse hit. */
TZ_FN vec3 chain_direct(TZ_SCENE_PARAM specular_chain c) {
    vec3 black = v3(0.0f, 0.0f, 0.0f);
    if (c.id == -1) return environment_radiance(TZ_SCENE_ARG c.d);
    if (c.id == -2) return black;
    return point_lights(TZ_SCENE_ARG c.s, c.id, c.n, c.ng, v3_scale(c.d, -1.0f));
}

/* One cosine-weighted bounce at the diffuse hit of chain c (wo the way back): theta =
 * acos(sqrt(1 - y1)), phi = 2 pi y2, pdf = cos(theta) / pi; returns f_r * L_direct * cos / pdf,
 * L_direct following mirrors and glass but adding no further bounce; nothing for a direction
 * below a triangle's face (its shading normal leans away from the geometric one). */
TZ_FN vec3 indirect_light(TZ_SCENE_PARAM specular_chain c, vec3 wo, float y1, float y2) {
    TZ_PRECISE float cos_t = TZ_SQRT(1.0f - y1);
    vec3 wi = cosine_direction(c.n, y1, y2);
    if (is_triangle(TZ_SCENE_ARG c.id) && !(v3_dot(c.ng, wi) > 0.0f)) return v3(0.0f, 0.0f, 0.0f);
    specular_chain next = follow_specular(TZ_SCENE_ARG offset_origin(c.s.pos, c.ng), wi, c.id);
    TZ_PRECISE vec3 incoming = v3_mul(next.weight, chain_direct(TZ_SCENE_ARG next));
    TZ_PRECISE float pdf = cos_t / TZ_PI;
    vec3 f = bsdf_f(c.s.m, c.n, wi, wo);
    TZ_PRECISE vec3 r = v3_mul(f, v3_scale(incoming, cos_t / pdf));
    return r;
}

/* Radiance of report-mode sample `sample_index` of pixel (i, j), i to the right, j down. */
TZ_FN vec3 report_sample(TZ_SCENE_PARAM TZ_UINT i, TZ_UINT j, TZ_UINT sample_index) {
    sampler_state rng =
        sampler_start(TZ_FLAGS, TZ_FRAME.seed, j * TZ_FRAME.width + i, sample_index);
    next_ray camera = camera_ray(TZ_SCENE_ARG i, j, TZ_REF(rng));
    specular_chain c = follow_specular(TZ_SCENE_ARG camera.o, camera.d, -1);
    TZ_PRECISE vec3 radiance = chain_direct(TZ_SCENE_ARG c);
    if (c.id >= 0 && (TZ_FLAGS & TZ_FLAG_INDIRECT) != 0u) {
        float y1, y2;
        sample_2d(TZ_FLAGS, TZ_REF(rng), TZ_REF(y1), TZ_REF(y2));
        radiance = v3_add(radiance, indirect_light(TZ_SCENE_ARG c, v3_scale(c.d, -1.0f), y1, y2));
    }
    TZ_PRECISE vec3 r = v3_mul(c.weight, radiance);
    return r;
}

#endif
