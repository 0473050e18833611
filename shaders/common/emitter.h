/* emitter.h: path mode's lights as one interface, one text for C and GLSL (dialect.h) over the
 * scene accessors (path.h lists them): an emitter (a sphere or a triangle of the table of
 * gpu_emitter) is picked (pick_emitter), sampled from a vertex (emitter_sample_from: a direction,
 * its pdf, where the shadow ray ends and the radiance), its pdf for a direction found otherwise
 * (light_pdf_at) and the radiance seen along a ray (emitter_radiance); the environment, what a
 * ray that meets nothing sees (a map or the constant background), is evaluated through
 * environment_radiance at every miss in report mode, and in path mode through
 * environment_look_along (radiance and light pdf from one look-up) with its MIS weight
 * (environment_mis_weight).
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
#include "transcendental.h"

/* The environment map (TZ_BINDING_ENVIRONMENT; DESIGN section 3.7): equirectangular, rows from
 * +y (v = 0) down to -y, the map's direction m at u = 1/2 + atan2(m.x, m.z) / (2 pi), v =
 * theta / pi, theta its angle from +y, so that its centre column faces +z and +x lies to its
 * right, seen from inside; world directions turn into the map's by the frame's rows env_x,
 * env_y, env_z. */

/* Constants as float literals: a C compiler folds 2.0f * TZ_PI * TZ_PI in float, glslang in
 * double, and the two differed in the last bit. */
#define TZ_TWO_PI_SQUARED 19.7392088f
#define TZ_ONE_OVER_TWO_PI 0.159154943f
#define TZ_ONE_OVER_PI 0.318309886f

/* The direction of the map that world direction d meets. */
TZ_LANE_FN vec3 environment_map_direction(TZ_SCENE_PARAM vec3 d) {
    vec3 m = v3(v3_dot(xyz(TZ_FRAME.env_x), d), v3_dot(xyz(TZ_FRAME.env_y), d),
                v3_dot(xyz(TZ_FRAME.env_z), d));
    return m;
}

/* The column or row, in [0, size - 1], that coordinate c (texels from the map's edge) falls in;
 * a NaN or an out-of-range c (the packet builds' idle lanes carry any direction) clamps, in
 * float, as converting it to int would be undefined. */
TZ_LANE_FN int environment_index_of(float c, int size) {
    float last = TZ_FLOAT(size - 1);
    float inside = c >= 0.0f ? c : 0.0f;
    return TZ_INT(inside < last ? inside : last);
}

/* The index of the map's texel that map direction m falls in. Only sums of products are precise
 * (the rest cannot be contracted into fused operations): glslang's propagation of precise took
 * minutes and gigabytes over this file's precise values (a product alone needs none). */
TZ_LANE_FN int environment_texel_of(TZ_SCENE_PARAM vec3 m) {
    TZ_PRECISE float rho = TZ_SQRT(m.x * m.x + m.z * m.z);
    float theta = angle_of(rho, m.y);
    /* along the axis (rho 0) there is no azimuth: the centre column's, not angle_of's NaN */
    float z = rho > 0.0f ? m.z : 1.0f;
    float side = m.x < 0.0f ? -1.0f : 1.0f;
    float azimuth = angle_of(TZ_ABS(m.x), z);
    TZ_PRECISE float u = 0.5f + side * (azimuth * TZ_ONE_OVER_TWO_PI);
    float x = u * TZ_FLOAT(TZ_FRAME.env_width);
    float y = theta * TZ_ONE_OVER_PI * TZ_FLOAT(TZ_FRAME.env_height);
    int w = TZ_INT(TZ_FRAME.env_width), h = TZ_INT(TZ_FRAME.env_height);
    return environment_index_of(y, h) * w + environment_index_of(x, w);
}

/* The radiance the environment sends along direction d to a ray that meets nothing: the map's
 * texel, or the constant background without a map (report mode's look-up). */
TZ_LANE_FN vec3 environment_radiance(TZ_SCENE_PARAM vec3 d) {
    vec3 seen = xyz(TZ_FRAME.background);
    if ((TZ_FLAGS & TZ_FLAG_ENVIRONMENT) != 0u) {
        vec3 m = environment_map_direction(TZ_SCENE_ARG d);
        seen = xyz(environment_texel(TZ_SCENE_ARG environment_texel_of(TZ_SCENE_ARG m)));
    }
    return seen;
}

/* The solid-angle pdf (the pick included) with which light sampling draws map direction m, whose
 * texel's pdf over the map's unit square is density: 0 where the environment is not sampled
 * (report mode, a black map). */
TZ_LANE_FN float environment_light_pdf(TZ_SCENE_PARAM vec3 m, float density) {
    float pdf = 0.0f;
    if (TZ_FRAME.env_slot > 0u) {
        TZ_PRECISE float sin_theta = TZ_SQRT(m.x * m.x + m.z * m.z);
        float pick = emitter_emission_pick(TZ_SCENE_ARG TZ_INT(TZ_FRAME.env_slot) - 1).w;
        float p = pick * density / (TZ_TWO_PI_SQUARED * sin_theta);
        pdf = sin_theta > 0.0f ? p : 0.0f;
    }
    return pdf;
}

/* What a ray along d that meets nothing finds in path mode, from one look-up of the map: the
 * environment's radiance (environment_radiance's) and the pdf with which light sampling draws d
 * (environment_light_pdf's; 0 for the constant background). */
TZ_STRUCT(environment_look) {
    vec3 radiance;
    float light_pdf;
}
TZ_STRUCT_END(environment_look)
TZ_LANE_FN environment_look environment_look_along(TZ_SCENE_PARAM vec3 d) {
    environment_look l;
    l.radiance = xyz(TZ_FRAME.background);
    l.light_pdf = 0.0f;
    if ((TZ_FLAGS & TZ_FLAG_ENVIRONMENT) != 0u) {
        vec3 m = environment_map_direction(TZ_SCENE_ARG d);
        TZ_VEC4 texel = environment_texel(TZ_SCENE_ARG environment_texel_of(TZ_SCENE_ARG m));
        l.radiance = xyz(texel);
        l.light_pdf = environment_light_pdf(TZ_SCENE_ARG m, texel.w);
    }
    return l;
}

/* The MIS weight of the environment's radiance found by a ray the BSDF drew with pdf bsdf_pdf
 * (specular: a camera ray or a mirror's or glass's, which light sampling cannot draw) along a
 * direction light sampling draws with pdf light_pdf (environment_look_along's): the power
 * heuristic, 1 where light sampling never draws it or BSDF sampling is alone, 0 where light
 * sampling is. */
TZ_LANE_FN float environment_mis_weight(TZ_SCENE_PARAM TZ_BOOL specular, float bsdf_pdf,
                                        float light_pdf) {
    float n_light = TZ_FLOAT(TZ_FRAME.light_samples);
    TZ_BOOL bsdf_only = (TZ_FRAME.flags & TZ_FLAG_BSDF_ONLY) != 0u;
    TZ_BOOL full = specular TZ_OR !(light_pdf > 0.0f) TZ_OR bsdf_only;
    float mis = (TZ_FRAME.flags & TZ_FLAG_LIGHTS_ONLY) != 0u
                    ? 0.0f
                    : power_heuristic(bsdf_pdf, n_light * light_pdf);
    return full ? 1.0f : mis;
}

/* The sun disc's radiance along d weighed by MIS, for a ray the BSDF drew with pdf bsdf_pdf that
 * met nothing (TZ_FLAG_SUN_DISC): 0 outside its cone; inside, the power heuristic against its
 * light pdf, pick / (2 pi (1 - cos)), 1 after a specular event or with BSDF sampling alone, 0
 * with light sampling alone. */
TZ_LANE_FN vec3 sun_seen(TZ_SCENE_PARAM TZ_BOOL specular, float bsdf_pdf, vec3 d) {
    TZ_VEC4 sun = TZ_FRAME.sun;
    TZ_VEC4 emission_pick = emitter_emission_pick(TZ_SCENE_ARG TZ_INT(TZ_FRAME.sun_slot) - 1);
    TZ_PRECISE float outside = 1.0f - v3_dot(d, xyz(sun));
    TZ_PRECISE float light_pdf = emission_pick.w / (2.0f * TZ_PI * sun.w);
    float n_light = TZ_FLOAT(TZ_FRAME.light_samples);
    TZ_BOOL bsdf_only = (TZ_FRAME.flags & TZ_FLAG_BSDF_ONLY) != 0u;
    TZ_BOOL full = specular TZ_OR bsdf_only;
    float mis = (TZ_FRAME.flags & TZ_FLAG_LIGHTS_ONLY) != 0u
                    ? 0.0f
                    : power_heuristic(bsdf_pdf, n_light * light_pdf);
    float w = outside <= sun.w ? (full ? 1.0f : mis) : 0.0f;
    return v3_scale(xyz(emission_pick), w);
}

/* The first index k of `count` whose next entry of the table at `first` exceeds u (the cdf
 * table's entries first..first + count, from 0 to 1), and u's place between the two in [0, 1):
 * from the entry its guide (`count` entries at `guide`, environment_pack.c) names for u, a step
 * down while u lies below it (a guide rounded up) and up while the next entry does not exceed
 * u; the first such k whatever the start, so a binary search's. */
TZ_STRUCT(table_pick) {
    int k;
    float within;
}
TZ_STRUCT_END(table_pick)
TZ_FN table_pick environment_table_pick(TZ_SCENE_PARAM int first, int count, int guide, float u) {
    int j = environment_index_of(u * TZ_FLOAT(count), count);
    int k = TZ_INT(environment_float(TZ_SCENE_ARG guide + j));
    while (k > 0 && u < environment_float(TZ_SCENE_ARG first + k)) k--;
    while (k < count - 1 && !(u < environment_float(TZ_SCENE_ARG first + k + 1))) k++;
    float below = environment_float(TZ_SCENE_ARG first + k);
    float above = environment_float(TZ_SCENE_ARG first + k + 1);
    float within = (u - below) / (above - below);
    table_pick t;
    t.k = k;
    t.within = TZ_MIN(TZ_MAX(within, 0.0f), 0.99999994f);
    return t;
}

/* A direction toward the environment drawn by importance for uniform ua, ub: a row of the map
 * by the marginal table, a texel of it by its conditional one, a point uniform in the texel;
 * its solid-angle pdf (the pick aside) and the texel's radiance. */
TZ_STRUCT(environment_sample) {
    vec3 wi;
    float pdf;
    vec3 radiance;
}
TZ_STRUCT_END(environment_sample)
TZ_FN environment_sample environment_sample_at(TZ_SCENE_PARAM float ua, float ub) {
    int w = TZ_INT(TZ_FRAME.env_width), h = TZ_INT(TZ_FRAME.env_height);
    int guides = (h + 1) + h * (w + 1);
    table_pick row = environment_table_pick(TZ_SCENE_ARG 0, h, guides, ua);
    table_pick column =
        environment_table_pick(TZ_SCENE_ARG h + 1 + row.k * (w + 1), w, guides + h + row.k * w, ub);
    float u = (TZ_FLOAT(column.k) + column.within) / TZ_FLOAT(w);
    float v = (TZ_FLOAT(row.k) + row.within) / TZ_FLOAT(h);
    cos_sin theta = cos_sin_turn(v * 0.5f);
    cos_sin phi = cos_sin_turn(u); /* the map's azimuth is 2 pi u - pi: both signs turn */
    vec3 m = v3(-theta.s * phi.s, theta.c, -theta.s * phi.c);
    TZ_PRECISE vec3 wi =
        v3_add(v3_add(v3_scale(xyz(TZ_FRAME.env_x), m.x), v3_scale(xyz(TZ_FRAME.env_y), m.y)),
               v3_scale(xyz(TZ_FRAME.env_z), m.z));
    TZ_VEC4 texel = environment_texel(TZ_SCENE_ARG row.k * w + column.k);
    environment_sample s;
    s.wi = wi;
    float pdf = texel.w / (TZ_TWO_PI_SQUARED * theta.s);
    s.pdf = theta.s > 0.0f ? pdf : 0.0f;
    s.radiance = xyz(texel);
    return s;
}

/* The radiance emitter slot sends along any ray that meets it (both sides of a face, a
 * sphere seen from inside too). */
TZ_LANE_FN vec3 emitter_radiance(TZ_SCENE_PARAM int slot) {
    return xyz(emitter_emission_pick(TZ_SCENE_ARG slot));
}

/* The radiance emitter slot of primitive id sends along the ray o + t d that meets it at pos:
 * emitter_radiance times its material's emission map (each channel at least 0) at the point's
 * UV, a face's from the ray's edge functions (face_uv_along), a sphere's sphere_uv; so light
 * sampling and a BSDF ray that meet one point see one radiance. */
TZ_FN vec3 emitted_radiance(TZ_SCENE_PARAM int slot, int id, vec3 o, vec3 d, vec3 pos) {
    vec3 radiance = emitter_radiance(TZ_SCENE_ARG slot);
    if (TZ_HAS_TEXTURES) {
        TZ_BOOL face = is_triangle(TZ_SCENE_ARG id);
        int t = id - TZ_INT(TZ_FRAME.sphere_count);
        int material = face ? TZ_INT(uint_bits(triangle_v0(TZ_SCENE_ARG t).w))
                            : sphere_material_index(TZ_SCENE_ARG id);
        TZ_UINT map = map_slot(material_maps(TZ_SCENE_ARG material), TZ_MAP_EMISSION);
        if (map != 0u) {
            tex_uv uv;
            if (face) {
                uv = face_uv_along(TZ_SCENE_ARG corners_of(TZ_SCENE_ARG id),
                                   uint_bits(triangle_v1(TZ_SCENE_ARG t).w), o, shear_of(d));
            } else {
                TZ_VEC4 cr = sphere_center_radius(TZ_SCENE_ARG id);
                uv = sphere_uv(sphere_normal(xyz(cr), cr.w, pos));
            }
            vec3 c = texture_sample(TZ_SCENE_ARG map - 1u, uv).rgb;
            radiance =
                v3_mul(radiance, v3(TZ_MAX(c.x, 0.0f), TZ_MAX(c.y, 0.0f), TZ_MAX(c.z, 0.0f)));
        }
    }
    return radiance;
}

/* The radiance a light sample of emitter slot (primitive id) brings along the shadow ray o + t d
 * that ends on it at t_light: emitted_radiance's there, none where the face is cut away
 * (face_cut), as a BSDF ray along it would pass through. */
TZ_FN vec3 emitter_radiance_along(TZ_SCENE_PARAM int slot, int id, vec3 o, vec3 d, float t_light) {
    vec3 radiance = emitted_radiance(TZ_SCENE_ARG slot, id, o, d, ray_point(o, d, t_light));
    if (TZ_HAS_CUTOUTS && is_triangle(TZ_SCENE_ARG id) &&
        face_cut(TZ_SCENE_ARG id, corners_of(TZ_SCENE_ARG id), o, shear_of(d)))
        radiance = v3(0.0f, 0.0f, 0.0f);
    return radiance;
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
    if ((TZ_FLAGS & TZ_FLAG_ENVIRONMENT) != 0u && uint_bits(primitive_cdf.x) == TZ_ENV_PRIMITIVE) {
        environment_sample es = environment_sample_at(TZ_SCENE_ARG ua, ub);
        s.wi = es.wi;
        s.pdf = emission_pick.w * es.pdf;
        s.radiance = es.radiance;
        s.t_light = TZ_ENV_DISTANCE;
    } else if ((TZ_FLAGS & TZ_FLAG_SUN_DISC) != 0u &&
               uint_bits(primitive_cdf.x) == TZ_SUN_PRIMITIVE) {
        direction_sample ds = cone_direction(xyz(TZ_FRAME.sun), TZ_FRAME.sun.w, ua, ub);
        TZ_PRECISE float pdf = emission_pick.w * ds.pdf;
        s.wi = ds.wi;
        s.pdf = pdf;
        s.t_light = TZ_ENV_DISTANCE;
    } else if (is_triangle(TZ_SCENE_ARG e)) {
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
    /* a sphere or a face (the environment and the sun are no primitives): its maps, once */
    if (TZ_HAS_TEXTURES && uint_bits(primitive_cdf.x) < TZ_SUN_PRIMITIVE)
        s.radiance = emitter_radiance_along(TZ_SCENE_ARG slot, e, o, s.wi, s.t_light);
    s.ok = TZ_TRUE;
    return s;
}

/* Where a shadow ray from o along wi toward emitter slot ends (emitter_sample_from's t_light),
 * for a ray that leaves another origin than the sample's: rough glass's light from below. */
TZ_FN float emitter_distance_from(TZ_SCENE_PARAM int slot, int id, vec3 o, vec3 wi) {
    TZ_UINT e_bits = uint_bits(emitter_primitive_cdf(TZ_SCENE_ARG slot).x);
    int e = TZ_INT(e_bits);
    if (e_bits == TZ_ENV_PRIMITIVE || e_bits == TZ_SUN_PRIMITIVE) return TZ_ENV_DISTANCE;
    if (is_triangle(TZ_SCENE_ARG e)) {
        triangle_corners k = corners_of(TZ_SCENE_ARG e);
        return triangle_light_distance(k.a, k.b, k.c, o, wi);
    }
    TZ_VEC4 cr = sphere_center_radius(TZ_SCENE_ARG e);
    return sphere_distance(cr.x, cr.y, cr.z, cr.w, o, wi, ray_eps(o), e == id);
}

#endif
