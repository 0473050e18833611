/* emitter.h: path mode's lights as one interface, one text for C and GLSL (dialect.h) over the
 * scene accessors (path.h lists them): an emitter (a sphere or a triangle of the table of
 * gpu_emitter) is picked (pick_emitter), sampled from a vertex (emitter_sample_from: a direction,
 * its pdf, where the shadow ray ends and the radiance), its pdf for a direction found otherwise
 * (light_pdf_at) and the radiance seen along a ray (emitter_radiance); the environment, what a
 * ray that meets nothing sees (today the scene's constant background), is evaluated through
 * environment_radiance at every miss, with its MIS weight in path mode (environment_mis_weight).
 * A new kind of light is a branch of emitter_sample_from and light_pdf_at and its packing in
 * src/render/scene_pack.c. */
#ifndef TRAZADOR_COMMON_EMITTER_H
#define TRAZADOR_COMMON_EMITTER_H

#include "dialect.h"
#include "primitive.h"
#include "ray.h"
#include "sampling.h"
#include "shade.h"
#include "spherical_triangle.h"

/* The radiance the environment sends along direction d to a ray that meets nothing: the scene's
 * background, the same in every direction. */
TZ_LANE_FN vec3 environment_radiance(TZ_SCENE_PARAM vec3 d) {
    TZ_UNUSED(d);
    return xyz(TZ_FRAME.background);
}

/* The solid-angle pdf with which light sampling draws direction d toward the environment: 0,
 * the constant background is not sampled as a light. */
TZ_LANE_FN float environment_pdf(TZ_SCENE_PARAM vec3 d) {
    TZ_UNUSED(TZ_SCENE_ONLY);
    TZ_UNUSED(d);
    return 0.0f;
}

/* The MIS weight of the environment's radiance found along d by a ray the BSDF drew with pdf
 * bsdf_pdf (specular: a camera ray or a mirror's or glass's, which light sampling cannot draw):
 * the power heuristic against environment_pdf, 1 where light sampling never draws d. */
TZ_LANE_FN float environment_mis_weight(TZ_SCENE_PARAM TZ_BOOL specular, float bsdf_pdf, vec3 d) {
    float light_pdf = environment_pdf(TZ_SCENE_ARG d);
    float n_light = TZ_FLOAT(TZ_FRAME.light_samples);
    return (specular TZ_OR !(light_pdf > 0.0f)) ? 1.0f
                                                : power_heuristic(bsdf_pdf, n_light * light_pdf);
}

/* The radiance emitter slot sends along any ray that meets it (both sides of a face, a
 * sphere seen from inside too). */
TZ_LANE_FN vec3 emitter_radiance(TZ_SCENE_PARAM int slot) {
    return xyz(emitter_emission_pick(TZ_SCENE_ARG slot));
}

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

/* A light sample of one emitter from a vertex: the direction wi, its solid-angle pdf (the pick
 * included), where the shadow ray toward it ends (t_light; infinity where it misses it), the
 * radiance it brings, and whether the emitter can light the vertex at all (ok). */
TZ_STRUCT(emitter_sample) {
    vec3 wi;
    float pdf;
    float t_light;
    vec3 radiance;
    TZ_BOOL ok;
}
TZ_STRUCT_END(emitter_sample)

/* Samples emitter slot for uniform ua, ub from the vertex at pos (primitive id, facing shading
 * normal n) whose shadow rays leave o: a sphere by its cone from outside and its area from
 * inside (light_strategy), a triangle by solid angle or area (triangle_light_direction), never
 * the vertex's own face. */
TZ_FN emitter_sample emitter_sample_from(TZ_SCENE_PARAM int slot, int id, vec3 pos, vec3 n, vec3 o,
                                         float ua, float ub) {
    TZ_VEC4 emission_pick = emitter_emission_pick(TZ_SCENE_ARG slot);
    TZ_VEC4 primitive_cdf = emitter_primitive_cdf(TZ_SCENE_ARG slot);
    int e = TZ_INT(uint_bits(primitive_cdf.x));
    emitter_sample s;
    s.radiance = xyz(emission_pick);
    s.ok = TZ_FALSE;
    s.wi = v3(0.0f, 0.0f, 0.0f);
    s.pdf = 0.0f;
    s.t_light = TZ_INFINITY;
    if (is_triangle(TZ_SCENE_ARG e)) {
        if (e == id) return s;
        triangle_corners k = corners_of(TZ_SCENE_ARG e);
        light_direction l = triangle_light_direction(k, primitive_cdf.z, o, ua, ub);
        TZ_PRECISE float pdf = emission_pick.w * l.pdf;
        s.wi = l.wi;
        s.pdf = pdf;
        s.t_light = triangle_light_distance(k.a, k.b, k.c, o, l.wi);
    } else {
        TZ_VEC4 cr = sphere_center_radius(TZ_SCENE_ARG e);
        vec3 c = xyz(cr);
        float r = cr.w;
        int strategy = light_strategy(pos, n, id, e, c, r);
        if (strategy == LIGHT_NONE) return s;
        light_direction l;
        if (strategy == LIGHT_CONE)
            l = sphere_cone_light(c, r, pos, ua, cos_sin_turn(ub));
        else
            l = sphere_area_light(c, r, pos, ua, cos_sin_turn(ub));
        TZ_PRECISE float pdf = emission_pick.w * l.pdf;
        s.wi = l.wi;
        s.pdf = pdf;
        s.t_light = sphere_distance(c.x, c.y, c.z, r, o, l.wi, ray_eps(o), e == id);
    }
    s.ok = TZ_TRUE;
    return s;
}

#endif
