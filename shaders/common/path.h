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
#include "lights.h"
#include "primitive.h"
#include "ray.h"
#include "sampler.h"
#include "sampling.h"
#include "shade.h"
#include "spherical_triangle.h"

/* How light sampling serves a vertex at pos (facing normal n, on sphere id) for the emitter on
 * sphere e of centre c and radius r: by its cone from outside, by its area from inside (or on it
 * with n pointing in), not at all on it with n pointing out (it cannot light its own outside). */
#define LIGHT_NONE 0
#define LIGHT_CONE 1
#define LIGHT_AREA 2
TZ_FN int light_strategy(vec3 pos, vec3 n, int id, int e, vec3 c, float r) {
    TZ_PRECISE vec3 to_c = v3_sub(c, pos);
    TZ_PRECISE float d2 = v3_dot(to_c, to_c);
    int own = v3_dot(n, to_c) > 0.0f ? LIGHT_AREA : LIGHT_NONE;
    int other = d2 > r * r ? LIGHT_CONE : LIGHT_AREA;
    return id == e ? own : other;
}

/* A direction of light sampling from o to an emitter and its solid-angle pdf (the pick aside). */
TZ_STRUCT(light_direction) {
    vec3 wi;
    float pdf;
}
TZ_STRUCT_END(light_direction)

/* Light sampling's direction from pos to the sphere emitter of centre c and radius r, for
 * uniform ua and azimuth phi: uniform in the cone it subtends (LIGHT_CONE). */
TZ_LANE_FN light_direction sphere_cone_light(vec3 c, float r, vec3 pos, float ua, cos_sin phi) {
    TZ_PRECISE vec3 to_c = v3_sub(c, pos);
    TZ_PRECISE float d2 = v3_dot(to_c, to_c);
    TZ_PRECISE vec3 w = v3_scale(to_c, 1.0f / TZ_SQRT(d2));
    direction_sample ds = cone_direction_at(w, cone_one_minus_cos(r * r, d2), ua, phi);
    light_direction l;
    l.wi = ds.wi;
    l.pdf = ds.pdf;
    return l;
}

/* The same toward a point uniform on the sphere's area (LIGHT_AREA). */
TZ_LANE_FN light_direction sphere_area_light(vec3 c, float r, vec3 pos, float ua, cos_sin phi) {
    TZ_PRECISE vec3 q = v3_add(c, v3_scale(sphere_area_direction_at(ua, phi), r));
    TZ_PRECISE vec3 to_q = v3_sub(q, pos);
    TZ_PRECISE float dist2 = v3_dot(to_q, to_q);
    TZ_PRECISE vec3 w = v3_scale(to_q, 1.0f / TZ_SQRT(dist2));
    TZ_PRECISE vec3 nq = v3_scale(v3_sub(q, c), 1.0f / r);
    light_direction l;
    l.wi = w;
    l.pdf = area_pdf(r, dist2, v3_dot(nq, w));
    return l;
}

/* The first emitter whose cdf exceeds u: a binary search, the last cdf being 1. */
TZ_FN int pick_emitter(TZ_SCENE_PARAM float u) {
    int lo = 0, hi = TZ_INT(TZ_FRAME.emitter_count) - 1;
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (u < emitter_primitive_cdf(TZ_SCENE_ARG mid).y)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* What the last non-specular vertex leaves for the MIS weight of emission its BSDF ray finds. */
TZ_STRUCT(path_vertex) {
    vec3 pos;
    vec3 n;
    vec3 origin; /* where its rays left: offset_origin(pos, geometric normal) */
    int id;
    float bsdf_pdf;
}
TZ_STRUCT_END(path_vertex)

/* The solid-angle pdf of area sampling triangle k (of area `area`) for the point pos seen from
 * `from` along d: dist^2 / (area |cos at pos|). */
TZ_LANE_FN float triangle_area_pdf(triangle_corners k, float area, vec3 from, vec3 pos, vec3 d) {
    TZ_PRECISE vec3 to_hit = v3_sub(pos, from);
    TZ_PRECISE float pdf = v3_dot(to_hit, to_hit) / (area * TZ_ABS(v3_dot(triangle_normal(k), d)));
    return pdf;
}

/* The pdf of a direction uniform within a spherical triangle of solid angle omega. */
TZ_FN float solid_angle_pdf(float omega) {
    TZ_PRECISE float pdf = 1.0f / omega;
    return pdf;
}

/* The solid-angle pdf with which light sampling from `from` chooses the point pos of triangle k
 * (of area `area`), reached along d: by solid angle where the triangle is sampled that way (near
 * its plane and by_solid_angle), else by area. */
TZ_FN float triangle_light_pdf(triangle_corners k, float area, vec3 from, vec3 pos, vec3 d) {
    if (near_triangle_plane(k.a, k.b, k.c, from)) {
        spherical_triangle st = spherical_triangle_of(k.a, k.b, k.c, from);
        if (by_solid_angle(st.solid_angle)) return solid_angle_pdf(st.solid_angle);
    }
    return triangle_area_pdf(k, area, from, pos, d);
}

/* The direction to a point of triangle k (of area `area`) uniform by area for uniform ua, ub,
 * aimed from the shadow ray's own origin o so that it meets the point: aimed from the vertex, the
 * offset ray missed faces near their edges (0.1% dark in a furnace). */
TZ_LANE_FN light_direction area_light_direction(triangle_corners k, float area, vec3 o, float ua,
                                                float ub) {
    light_direction l;
    vec3 q = triangle_area_point(k.a, k.b, k.c, ua, ub);
    TZ_PRECISE vec3 to_q = v3_sub(q, o);
    l.wi = v3_normalize(to_q);
    l.pdf = triangle_area_pdf(k, area, o, q, l.wi);
    return l;
}

/* The direction uniform in the solid angle of triangle k from o for uniform ua, ub where it is
 * sampled so (by_solid_angle), else by_area: for the points near its plane. */
TZ_FN light_direction solid_angle_light_direction(triangle_corners k, vec3 o, float ua, float ub,
                                                  light_direction by_area) {
    spherical_triangle st = spherical_triangle_of(k.a, k.b, k.c, o);
    light_direction l = by_area;
    if (by_solid_angle(st.solid_angle)) {
        l.wi = spherical_triangle_direction(st, ua, ub);
        l.pdf = solid_angle_pdf(st.solid_angle);
    }
    return l;
}

/* Light sampling's direction from o to triangle k (of area `area`) for uniform ua, ub, with
 * triangle_light_pdf's pdf. */
TZ_FN light_direction triangle_light_direction(triangle_corners k, float area, vec3 o, float ua,
                                               float ub) {
    light_direction l = area_light_direction(k, area, o, ua, ub);
    if (near_triangle_plane(k.a, k.b, k.c, o)) l = solid_angle_light_direction(k, o, ua, ub, l);
    return l;
}

/* The solid-angle pdf (the pick included) with which light sampling at vertex v would have
 * chosen the point pos on emitter primitive id, reached along d (a triangle never lights
 * itself). */
TZ_FN float light_pdf_at(TZ_SCENE_PARAM path_vertex v, int id, vec3 pos, vec3 d) {
    if (is_triangle(TZ_SCENE_ARG id)) {
        int slot = emitter_of(TZ_SCENE_ARG id);
        float pick = emitter_emission_pick(TZ_SCENE_ARG slot).w;
        float area = emitter_primitive_cdf(TZ_SCENE_ARG slot).z;
        TZ_PRECISE float pdf =
            pick * triangle_light_pdf(corners_of(TZ_SCENE_ARG id), area, v.origin, pos, d);
        return v.id == id ? 0.0f : pdf;
    }
    TZ_VEC4 cr = sphere_center_radius(TZ_SCENE_ARG id);
    vec3 c = xyz(cr);
    float pick = emitter_emission_pick(TZ_SCENE_ARG emitter_of(TZ_SCENE_ARG id)).w;
    int strategy = light_strategy(v.pos, v.n, v.id, id, c, cr.w);
    TZ_PRECISE vec3 to_c = v3_sub(c, v.pos), to_hit = v3_sub(pos, v.pos);
    TZ_PRECISE vec3 nl = v3_scale(v3_sub(pos, c), 1.0f / cr.w);
    TZ_PRECISE float cone =
        pick / (2.0f * TZ_PI * cone_one_minus_cos(cr.w * cr.w, v3_dot(to_c, to_c)));
    TZ_PRECISE float area = pick * area_pdf(cr.w, v3_dot(to_hit, to_hit), v3_dot(nl, d));
    return strategy == LIGHT_CONE ? cone : strategy == LIGHT_AREA ? area : 0.0f;
}

/* Light from the emitter picked by ul and sampled by ua, ub at a diffuse vertex (primitive id at
 * surface sf, facing shading normal n and geometric normal ng, wo the way back, share the BSDF's
 * diffuse share), weighted by MIS, or alone; beta not applied. */
TZ_FN vec3 emitter_light(TZ_SCENE_PARAM int id, surface sf, vec3 n, vec3 ng, vec3 wo, float share,
                         float ul, float ua, float ub) {
    vec3 pos = sf.pos;
    int slot = pick_emitter(TZ_SCENE_ARG ul);
    TZ_VEC4 emission_pick = emitter_emission_pick(TZ_SCENE_ARG slot);
    TZ_VEC4 primitive_cdf = emitter_primitive_cdf(TZ_SCENE_ARG slot);
    int e = TZ_INT(uint_bits(primitive_cdf.x));
    vec3 wi;
    TZ_PRECISE float pdf;
    float t_light;
    vec3 o = offset_origin(pos, ng);
    if (is_triangle(TZ_SCENE_ARG e)) {
        if (e == id) return v3(0.0f, 0.0f, 0.0f);
        triangle_corners k = corners_of(TZ_SCENE_ARG e);
        light_direction l = triangle_light_direction(k, primitive_cdf.z, o, ua, ub);
        wi = l.wi;
        pdf = emission_pick.w * l.pdf;
        t_light = triangle_light_distance(k.a, k.b, k.c, o, wi);
    } else {
        TZ_VEC4 cr = sphere_center_radius(TZ_SCENE_ARG e);
        vec3 c = xyz(cr);
        float r = cr.w;
        int strategy = light_strategy(pos, n, id, e, c, r);
        if (strategy == LIGHT_NONE) return v3(0.0f, 0.0f, 0.0f);
        light_direction l;
        if (strategy == LIGHT_CONE)
            l = sphere_cone_light(c, r, pos, ua, cos_sin_turn(ub));
        else
            l = sphere_area_light(c, r, pos, ua, cos_sin_turn(ub));
        wi = l.wi;
        pdf = emission_pick.w * l.pdf;
        t_light = sphere_distance(c.x, c.y, c.z, r, o, wi, ray_eps(o), e == id);
    }
    float cos_i = v3_dot(n, wi);
    TZ_BOOL folds = folds_at(n, ng);
    if (!(folds || cos_i > 0.0f) || !(v3_dot(ng, wi) > 0.0f) || !(pdf > 0.0f) ||
        !(pdf < TZ_INFINITY))
        return v3(0.0f, 0.0f, 0.0f);
    if (!(t_light < TZ_INFINITY) || integrator_occluded(TZ_SCENE_ARG o, wi, t_light, id))
        return v3(0.0f, 0.0f, 0.0f);
    bsdf_value bv = bsdf_eval(sf.m, share, n, ng, wi, wo);
    float b = bv.pdf;
    /* the MIS weight over the pdf and the sample count, or 1 / pdf with light sampling alone */
    float n_light = TZ_FLOAT(TZ_FRAME.light_samples);
    TZ_PRECISE float weight = (TZ_FRAME.flags & TZ_FLAG_LIGHTS_ONLY) != 0u
                                  ? 1.0f / (n_light * pdf)
                                  : light_mis_over_pdf(n_light, pdf, b);
    TZ_PRECISE vec3 l = v3_scale(v3_mul(bv.f, xyz(emission_pick)), bv.f_scale * weight);
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
        p.radiance = v3_add(p.radiance, v3_mul(p.beta, xyz(TZ_FRAME.background)));
        p.k = 0u;
        return p;
    }
    surface sf = surface_at(TZ_SCENE_ARG id, p.o, p.d, t);
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
            v3_scale(v3_mul(p.beta, xyz(emitter_emission_pick(TZ_SCENE_ARG slot))), w);
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
        p.o = offset_origin(pos, ng);
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
