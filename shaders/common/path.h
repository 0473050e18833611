/* path.h: path mode's sample (DESIGN section 3.2), one text for C and GLSL (dialect.h), on the
 * steps of sampling.h, so that every back end draws the same numbers in the same order. The
 * includer provides the scene: TZ_FRAME, the accessors sphere_center_radius(), sphere_color_ks(),
 * sphere_params(), triangle_v0(), triangle_v1(), triangle_v2(), material_color_ks(),
 * material_params(), normals_n0(), normals_n1(), normals_n2(), light_position_power(),
 * light_color(), light_count(), emitter_emission_pick() and emitter_primitive_cdf(), and
 * integrator_nearest() and integrator_occluded(), each taking TZ_SCENE_ARG first (dialect.h). */
#ifndef TRAZADOR_COMMON_PATH_H
#define TRAZADOR_COMMON_PATH_H

#include "camera.h"
#include "dialect.h"
#include "emitter.h"
#include "lights.h"
#include "primitive.h"
#include "ray.h"
#include "sampler.h"
#include "sampling.h"
#include "shade.h"
#include "spherical_triangle.h"

/* Light from the emitter picked by ul and sampled by ua, ub at a diffuse vertex (primitive id at
 * surface sf, facing shading normal n and geometric normal ng, wo the way back, share the BSDF's
 * diffuse share), weighted by MIS, or alone; beta not applied. */
TZ_FN vec3 emitter_light(TZ_SCENE_PARAM int id, surface sf, vec3 n, vec3 ng, vec3 wo, float share,
                         float ul, float ua, float ub) {
    int slot = pick_emitter(TZ_SCENE_ARG ul);
    vec3 o = offset_origin(sf.pos, ng);
    emitter_sample es = emitter_sample_from(TZ_SCENE_ARG slot, id, sf.pos, n, o, ua, ub);
    if (!es.ok) return v3(0.0f, 0.0f, 0.0f);
    vec3 wi = es.wi;
    TZ_PRECISE float pdf = es.pdf;
    float t_light = es.t_light;
    float cos_i = v3_dot(n, wi);
    TZ_BOOL folds = folds_at(n, ng);
    /* rough glass lets light through from below both normals, its shadow ray leaving below */
    TZ_BOOL through =
        TZ_MICROFACET_ON && is_dielectric(sf.m.kind) && cos_i < 0.0f && v3_dot(ng, wi) < 0.0f;
    TZ_BOOL above = !(TZ_MICROFACET_ON && is_dielectric(sf.m.kind)) || cos_i > 0.0f;
    if (!through && (!(folds || cos_i > 0.0f) || !(v3_dot(ng, wi) > 0.0f) || !above))
        return v3(0.0f, 0.0f, 0.0f);
    if (!(pdf > 0.0f) || !(pdf < TZ_INFINITY)) return v3(0.0f, 0.0f, 0.0f);
    if (through) {
        o = offset_origin(sf.pos, v3_scale(ng, -1.0f));
        t_light = emitter_distance_from(TZ_SCENE_ARG slot, id, o, wi);
    }
    if (!(t_light < TZ_INFINITY) || integrator_occluded(TZ_SCENE_ARG o, wi, t_light, id))
        return v3(0.0f, 0.0f, 0.0f);
    bsdf_value bv = bsdf_eval(sf.m, share, n, ng, wi, wo);
    float b = bv.pdf;
    /* the MIS weight over the pdf and the sample count, or 1 / pdf with light sampling alone */
    float n_light = TZ_FLOAT(TZ_FRAME.light_samples);
    TZ_PRECISE float weight = (TZ_FRAME.flags & TZ_FLAG_LIGHTS_ONLY) != 0u
                                  ? 1.0f / (n_light * pdf)
                                  : light_mis_over_pdf(n_light, pdf, b);
    TZ_PRECISE vec3 l = v3_scale(v3_mul(bv.f, es.radiance), bv.f_scale * weight);
    return l;
}

/* A path between two of its vertices (path_sample's locals), so that a caller may run paths a
 * vertex at a time: trace.comp starts a pixel's next sample in a lane whose path has ended while
 * the other lanes of its batch go on. */
TZ_STRUCT(path_state) {
    sampler_state rng;
    vec3 o; /* the next ray */
    vec3 d;
    TZ_PRECISE vec3 beta;
    TZ_PRECISE vec3 radiance;
    path_vertex last;
    int self; /* the primitive the next ray leaves */
    TZ_BOOL specular;
    TZ_UINT k; /* the number of the next vertex, from 1; 0 once the path has ended */
}
TZ_STRUCT_END(path_state)

/* The path of sample `sample_index` of pixel (i, j), i to the right, j down, before its first
 * vertex. */
TZ_FN path_state path_start(TZ_SCENE_PARAM TZ_UINT i, TZ_UINT j, TZ_UINT sample_index) {
    path_state p;
    p.rng = sampler_start(TZ_FLAGS, TZ_FRAME.seed, j * TZ_FRAME.width + i, sample_index);
    next_ray camera = camera_ray(TZ_SCENE_ARG i, j, TZ_REF(p.rng));
    p.o = camera.o;
    p.d = camera.d;
    p.beta = v3(1.0f, 1.0f, 1.0f);
    p.radiance = v3(0.0f, 0.0f, 0.0f);
    p.self = -1;
    p.specular = TZ_TRUE;
    p.last.pos = p.o;
    p.last.n = p.d;
    p.last.origin = p.o;
    p.last.id = -1;
    p.last.bsdf_pdf = 0.0f;
    p.k = 1u;
    return p;
}

/* p after its next vertex: the light found there added to p.radiance, and p.k 0 where the path
 * ends. */
TZ_FN path_state path_step(TZ_SCENE_PARAM path_state p) {
    TZ_UINT flags = TZ_FLAGS;
    float t;
    int id = integrator_nearest(TZ_SCENE_ARG p.o, p.d, p.self, TZ_REF(t));
    if (id < 0) {
        environment_look e = environment_look_along(TZ_SCENE_ARG p.d);
        float w = environment_mis_weight(TZ_SCENE_ARG p.specular, p.last.bsdf_pdf, e.light_pdf);
        TZ_PRECISE vec3 seen = v3_scale(v3_mul(p.beta, e.radiance), w);
        p.radiance = v3_add(p.radiance, seen);
        if ((flags & TZ_FLAG_SUN_DISC) != 0u) {
            vec3 sun = sun_seen(TZ_SCENE_ARG p.specular, p.last.bsdf_pdf, p.d);
            p.radiance = v3_add(p.radiance, v3_mul(p.beta, sun));
        }
        p.k = 0u;
        return p;
    }
    surface sf = surface_at(TZ_SCENE_ARG id, p.o, p.d, t);
    sf.m.ior = bsdf_eta(sf.m.kind, sf.m.ior, sf.nout, p.d);
    bsdf_material m = sf.m;
    vec3 pos = sf.pos;
    vec3 nout = sf.nout;
    vec3 d = p.d;
    int slot = sf.emitter;
    if (slot >= 0) {
        TZ_BOOL full = p.specular || (flags & TZ_FLAG_BSDF_ONLY) != 0u;
        float w = full ? 1.0f
                  : (flags & TZ_FLAG_LIGHTS_ONLY) != 0u
                      ? 0.0f
                      : power_heuristic(p.last.bsdf_pdf,
                                        TZ_FLOAT(TZ_FRAME.light_samples) *
                                            light_pdf_at(TZ_SCENE_ARG p.last, id, pos, d));
        TZ_PRECISE vec3 emitted =
            v3_scale(v3_mul(p.beta, emitted_radiance(TZ_SCENE_ARG slot, id, p.o, p.d, pos)), w);
        p.radiance = v3_add(p.radiance, emitted);
    }
    if (p.k > TZ_FRAME.bounces) {
        p.k = 0u;
        return p;
    }
    if (!bsdf_is_delta(m.kind)) {
        vec3 n = facing_shading(sf, d);
        vec3 ng = facing_normal(nout, d);
        TZ_PRECISE vec3 wo = v3_scale(d, -1.0f);
        float share = bsdf_share(m);
        TZ_PRECISE vec3 direct = point_lights(TZ_SCENE_ARG sf, id, n, ng, wo);
        for (TZ_UINT l = 0u; TZ_FRAME.emitter_count > 0u && l < TZ_FRAME.light_samples; l++) {
            float ul = sample_1d(flags, TZ_REF(p.rng));
            float ua, ub;
            sample_2d(flags, TZ_REF(p.rng), TZ_REF(ua), TZ_REF(ub));
            if ((flags & TZ_FLAG_BSDF_ONLY) == 0u)
                direct = v3_add(direct,
                                emitter_light(TZ_SCENE_ARG id, sf, n, ng, wo, share, ul, ua, ub));
        }
        p.radiance = v3_add(p.radiance, v3_mul(p.beta, direct));
        float us = sample_1d(flags, TZ_REF(p.rng));
        float u1, u2;
        sample_2d(flags, TZ_REF(p.rng), TZ_REF(u1), TZ_REF(u2));
        if (share < 0.0f) {
            p.k = 0u;
            return p;
        }
        bsdf_sample bs = bsdf_sample_lobe(m, share, n, ng, wo, us, u1, u2);
        if (!bs.ok) {
            p.k = 0u;
            return p;
        }
        p.beta = v3_mul(p.beta, bs.weight);
        p.last.pos = pos;
        p.last.n = n;
        p.last.origin = offset_origin(pos, ng);
        p.last.id = id;
        p.last.bsdf_pdf = bs.pdf;
        p.specular = TZ_FALSE;
        p.o = bsdf_next_origin(pos, ng, bs.wi);
        p.d = bs.wi;
    } else {
        vec3 n = specular_normal(nout, sf.shading, d);
        float uf = 0.0f;
        if (bsdf_refracts(m.kind)) uf = sample_1d(flags, TZ_REF(p.rng));
        TZ_BOOL transmits = bsdf_delta_transmits(m, d, nout, n, uf);
        p.beta = v3_mul(p.beta, m.color);
        next_ray next = specular_next(pos, nout, n, d, transmits, m.ior);
        p.o = next.o;
        p.d = next.d;
        p.specular = TZ_TRUE;
    }
    p.self = id;
    if (p.k >= 4u && (flags & TZ_FLAG_ROULETTE) != 0u) {
        TZ_PRECISE float q = TZ_MIN(TZ_MAX(TZ_MAX(p.beta.x, p.beta.y), p.beta.z), 1.0f);
        if (sample_1d(flags, TZ_REF(p.rng)) >= q) {
            p.k = 0u;
            return p;
        }
        p.beta = v3_scale(p.beta, 1.0f / q);
    }
    p.k++;
    return p;
}

/* Radiance of path-mode sample `sample_index` of pixel (i, j), i to the right, j down. */
TZ_FN vec3 path_sample(TZ_SCENE_PARAM TZ_UINT i, TZ_UINT j, TZ_UINT sample_index) {
    path_state p = path_start(TZ_SCENE_ARG i, j, sample_index);
    while (p.k != 0u) p = path_step(TZ_SCENE_ARG p);
    return p.radiance;
}

#endif
