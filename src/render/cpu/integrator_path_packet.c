/* integrator_path_packet.c: path mode (DESIGN section 3.2) over a packet of LANES samples at once
 * (the same sample of a run of pixels in one row), each lane one pixel's path. The lanes go
 * vertex by vertex together, a lane whose path ended idling; each lane does the very operations
 * of path_sample (shaders/common/path.h) through the same shared steps and draws the same
 * numbers in the same order from its own stream, so the samples are bit-identical to
 * integrator_path_sample (tested); the rays of all lanes are traced as one packet. */
#include <math.h>
#include <string.h>

#include "render/cpu/path_accessors.h"

/* Built once per vector level (CMakeLists.txt): PACKET_LANES lanes, the entry point named
 * integrator_path_packet_<PACKET_VARIANT>; src/render/cpu/integrator_dispatch.c picks one. */
#ifndef PACKET_LANES
#define PACKET_LANES 8
#define PACKET_VARIANT baseline
#endif
#define LANES PACKET_LANES
#define PATH_ENTRY_NAME(variant) integrator_path_packet_##variant
#define PATH_ENTRY(variant) PATH_ENTRY_NAME(variant)

#include "render/cpu/packet_trace.h"

/* What the lanes' rays hit: id[k] the sphere (-1 none), through the packet trace; a shadow ray
 * (any_hit) is blocked when id[k] >= 0. Lanes not in active get -1; nothing is traced when no
 * lane is active. */
LANE_FN void trace_lanes(const packed_scene *p, const lanes3 *o, const lanes3 *d, const int *self,
                         const float *tmax, const int *active, int any_hit, int *id, float *t) {
    if (any_lane(active)) {
        packet_trace(p, o, d, self, tmax, active, any_hit, id, t);
        return;
    }
    for (int k = 0; k < LANES; k++) {
        id[k] = -1;
        t[k] = INFINITY;
    }
}

/* The state of the lanes' paths (the locals of path_sample). */
typedef struct path_lanes {
    uint32_t rng[LANES];
    int active[LANES], self[LANES], specular[LANES], last_id[LANES];
    float last_pdf[LANES];
    lanes3 o, d, beta, radiance, last_pos, last_n;
} path_lanes;

/* A vertex of the lanes' paths: the hit sphere's data and the hit. */
typedef struct vertex_lanes {
    int id[LANES], diffuse[LANES], specular[LANES];
    float t[LANES];
    lanes3 pos, nout, n, wo;
    float share[LANES];
} vertex_lanes;

/* The light of the point lights at the diffuse lanes' vertices into direct (point_lights). */
LANE_FN void lanes_point_lights(const packed_scene *scene, const vertex_lanes *v, lanes3 *direct) {
    lanes3 so;
    for (int k = 0; k < LANES; k++) {
        set3(&so, k, offset_origin(get3(&v->pos, k), get3(&v->n, k)));
        set3(direct, k, v3(0.0f, 0.0f, 0.0f));
    }
    for (uint32_t l = 0; l < light_count(scene); l++) {
        lanes3 wi, rad;
        float dist[LANES], t[LANES];
        int want[LANES], blocked[LANES];
        for (int k = 0; k < LANES; k++) {
            light_sample s =
                point_light(light_position_power(scene, (int)l), light_color(scene, (int)l),
                            get3(&v->pos, k), get3(&v->n, k));
            set3(&wi, k, s.wi);
            set3(&rad, k, s.radiance);
            dist[k] = s.dist;
            want[k] = v->diffuse[k] & !(s.cos_i <= 0.0f);
        }
        trace_lanes(scene, &so, &wi, v->id, dist, want, 1, blocked, t);
        for (int k = 0; k < LANES; k++) {
            if (!want[k] || blocked[k] >= 0) continue;
            vec3 f = sphere_brdf_at(scene, v->id[k],
                                    phong_lobe_cos(get3(&v->n, k), get3(&wi, k), get3(&v->wo, k)));
            set3(direct, k, v3_add(get3(direct, k), v3_mul(f, get3(&rad, k))));
        }
    }
}

/* emitter_light of path.h for the diffuse lanes, its shadow rays traced together, added to
 * direct; ul, ua, ub the lanes' numbers. */
LANE_FN void lanes_emitter_light(const packed_scene *scene, const vertex_lanes *v, const float *ul,
                                 const float *ua, const float *ub, lanes3 *direct) {
    lanes3 so, wi, emission;
    float pdf[LANES], cos_i[LANES], t_light[LANES], t[LANES];
    int want[LANES], blocked[LANES];
    for (int k = 0; k < LANES; k++) {
        want[k] = 0;
        if (!v->diffuse[k]) continue;
        int id = v->id[k];
        vec3 pos = get3(&v->pos, k), n = get3(&v->n, k);
        int slot = pick_emitter(scene, ul[k]);
        tz_vec4 emission_pick = emitter_emission_pick(scene, slot);
        int e = (int)uint_bits(emitter_sphere_cdf(scene, slot).x);
        tz_vec4 cr = sphere_center_radius(scene, e);
        vec3 c = xyz(cr);
        float r = cr.w;
        int strategy = light_strategy(pos, n, id, e, c, r);
        if (strategy == LIGHT_NONE) continue;
        vec3 w;
        float p;
        if (strategy == LIGHT_CONE) {
            vec3 to_c = v3_sub(c, pos);
            float d2 = v3_dot(to_c, to_c);
            vec3 axis = v3_scale(to_c, 1.0f / sqrtf(d2));
            direction_sample s = cone_direction(axis, cone_one_minus_cos(r * r, d2), ua[k], ub[k]);
            w = s.wi;
            p = emission_pick.w * s.pdf;
        } else {
            vec3 q = v3_add(c, v3_scale(sphere_area_direction(ua[k], ub[k]), r));
            vec3 to_q = v3_sub(q, pos);
            float dist2 = v3_dot(to_q, to_q);
            vec3 axis = v3_scale(to_q, 1.0f / sqrtf(dist2));
            vec3 nq = v3_scale(v3_sub(q, c), 1.0f / r);
            w = axis;
            p = emission_pick.w * area_pdf(r, dist2, v3_dot(nq, axis));
        }
        float ci = v3_dot(n, w);
        if (!(ci > 0.0f) || !(p > 0.0f) || !(p < INFINITY)) continue;
        vec3 o = offset_origin(pos, n);
        float tl = sphere_distance(c.x, c.y, c.z, r, o, w, ray_eps(o), e == id);
        if (!(tl < INFINITY)) continue;
        set3(&so, k, o);
        set3(&wi, k, w);
        set3(&emission, k, xyz(emission_pick));
        pdf[k] = p;
        cos_i[k] = ci;
        t_light[k] = tl;
        want[k] = 1;
    }
    trace_lanes(scene, &so, &wi, v->id, t_light, want, 1, blocked, t);
    uint32_t lights_only = scene->frame.flags & TZ_FLAG_LIGHTS_ONLY;
    for (int k = 0; k < LANES; k++) {
        if (!v->diffuse[k]) continue;
        vec3 l = v3(0.0f, 0.0f, 0.0f);
        if (want[k] && blocked[k] < 0) {
            int id = v->id[k];
            vec3 n = get3(&v->n, k), w = get3(&wi, k);
            float x = phong_lobe_cos(n, w, get3(&v->wo, k));
            float b = bsdf_pdf(v->share[k], sphere_params(scene, id).x, cos_i[k], x);
            float mis = pdf[k] / (pdf[k] * pdf[k] + b * b);
            float weight = lights_only != 0u ? 1.0f / pdf[k] : mis;
            l = v3_scale(v3_mul(sphere_brdf_at(scene, id, x), get3(&emission, k)),
                         cos_i[k] * weight);
        }
        set3(direct, k, v3_add(get3(direct, k), l));
    }
}

/* The lanes' next rays at diffuse vertices: the BSDF's sample, beta and the last vertex updated;
 * lanes whose path ends here are made inactive. */
LANE_FN void lanes_bsdf_bounce(const packed_scene *scene, const vertex_lanes *v, path_lanes *s,
                               const float *us, const float *u1, const float *u2) {
    for (int k = 0; k < LANES; k++) {
        if (!v->diffuse[k]) continue;
        int id = v->id[k];
        float share = v->share[k];
        if (share < 0.0f) {
            s->active[k] = 0;
            continue;
        }
        vec3 n = get3(&v->n, k), wo = get3(&v->wo, k);
        float alpha = sphere_params(scene, id).x;
        vec3 wi;
        if (us[k] < share) {
            float phi = 2.0f * TZ_PI * u2[k];
            wi = cosine_direction(n, u1[k], cosf(phi), sinf(phi));
        } else {
            vec3 wr = v3_sub(v3_scale(n, 2.0f * v3_dot(n, wo)), wo);
            wi = phong_lobe_direction(wr, alpha, u1[k], u2[k]);
        }
        float cos_i = v3_dot(n, wi), x = phong_lobe_cos(n, wi, wo);
        float pdf = bsdf_pdf(share, alpha, cos_i, x);
        if (!(cos_i > 0.0f) || !(pdf > 0.0f)) {
            s->active[k] = 0;
            continue;
        }
        vec3 f = v3_scale(sphere_brdf_at(scene, id, x), cos_i / pdf);
        set3(&s->beta, k, v3_mul(get3(&s->beta, k), f));
        set3(&s->last_pos, k, get3(&v->pos, k));
        set3(&s->last_n, k, n);
        s->last_id[k] = id;
        s->last_pdf[k] = pdf;
        s->specular[k] = 0;
        set3(&s->o, k, offset_origin(get3(&v->pos, k), n));
        set3(&s->d, k, wi);
    }
}

/* The lanes' next rays at mirror and glass vertices (glass draws its Fresnel number). */
LANE_FN void lanes_specular_bounce(const packed_scene *scene, const vertex_lanes *v,
                                   path_lanes *s) {
    for (int k = 0; k < LANES; k++) {
        if (!v->specular[k]) continue;
        tz_vec4 params = sphere_params(scene, v->id[k]);
        vec3 d = get3(&s->d, k), nout = get3(&v->nout, k);
        int refractive = (int)params.z == TZ_MATERIAL_REFRACTIVE;
        int transmits = refractive;
        if (refractive) {
            float uf = rng_next(&s->rng[k]);
            int entering = v3_dot(d, nout) < 0.0f;
            float eta = entering ? 1.0f / params.y : params.y;
            float c1 = entering ? -v3_dot(d, nout) : v3_dot(d, nout);
            float kk = 1.0f - eta * eta * (1.0f - c1 * c1);
            transmits = !(uf < fresnel_dielectric(eta, c1, kk));
        }
        set3(&s->beta, k, v3_mul(get3(&s->beta, k), xyz(sphere_color_ks(scene, v->id[k]))));
        next_ray next = specular_next(get3(&v->pos, k), nout, d, transmits, params.y);
        set3(&s->o, k, next.o);
        set3(&s->d, k, next.d);
        s->specular[k] = 1;
    }
}

/* One vertex of every active lane's path (an iteration of path_sample's loop, the k-th). */
LANE_FN void lanes_vertex(const packed_scene *scene, path_lanes *s, uint32_t vertex) {
    const struct gpu_frame *fr = &scene->frame;
    uint32_t flags = fr->flags;
    vertex_lanes v;
    float tmax[LANES];
    for (int k = 0; k < LANES; k++) tmax[k] = INFINITY;
    trace_lanes(scene, &s->o, &s->d, s->self, tmax, s->active, 0, v.id, v.t);
    vec3 background = xyz(fr->background);
    for (int k = 0; k < LANES; k++) {
        int id = v.id[k];
        v.diffuse[k] = v.specular[k] = 0;
        if (!s->active[k]) continue;
        if (id < 0) {
            set3(&s->radiance, k,
                 v3_add(get3(&s->radiance, k), v3_mul(get3(&s->beta, k), background)));
            s->active[k] = 0;
            continue;
        }
        tz_vec4 cr = sphere_center_radius(scene, id);
        vec3 o = get3(&s->o, k), d = get3(&s->d, k);
        vec3 pos = v3_add(o, v3_scale(d, v.t[k]));
        vec3 nout = v3_scale(v3_sub(pos, xyz(cr)), 1.0f / cr.w);
        set3(&v.pos, k, pos);
        set3(&v.nout, k, nout);
        int slot = emitter_of(scene, id);
        if (slot >= 0) {
            int full = s->specular[k] || (flags & TZ_FLAG_BSDF_ONLY) != 0u;
            path_vertex last;
            last.pos = get3(&s->last_pos, k);
            last.n = get3(&s->last_n, k);
            last.id = s->last_id[k];
            last.bsdf_pdf = s->last_pdf[k];
            float w = full ? 1.0f
                      : (flags & TZ_FLAG_LIGHTS_ONLY) != 0u
                          ? 0.0f
                          : power_heuristic(last.bsdf_pdf, light_pdf_at(scene, last, id, pos, d));
            vec3 emitted =
                v3_scale(v3_mul(get3(&s->beta, k), xyz(emitter_emission_pick(scene, slot))), w);
            set3(&s->radiance, k, v3_add(get3(&s->radiance, k), emitted));
        }
        if (vertex > fr->bounces) {
            s->active[k] = 0;
            continue;
        }
        int material = (int)sphere_params(scene, id).z;
        int diffuse = material == TZ_MATERIAL_LAMBERTIAN || material == TZ_MATERIAL_PHONG;
        v.diffuse[k] = diffuse;
        v.specular[k] = !diffuse;
        if (diffuse) {
            tz_vec4 color_ks = sphere_color_ks(scene, id);
            set3(&v.n, k, facing_normal(nout, d));
            set3(&v.wo, k, v3_scale(d, -1.0f));
            v.share[k] = diffuse_share(xyz(color_ks), color_ks.w);
        }
    }
    if (any_lane(v.diffuse)) {
        lanes3 direct;
        lanes_point_lights(scene, &v, &direct);
        if (fr->emitter_count > 0u) {
            float ul[LANES], ua[LANES], ub[LANES];
            for (int k = 0; k < LANES; k++) {
                if (!v.diffuse[k]) continue;
                ul[k] = rng_next(&s->rng[k]);
                ua[k] = rng_next(&s->rng[k]);
                ub[k] = rng_next(&s->rng[k]);
            }
            if ((flags & TZ_FLAG_BSDF_ONLY) == 0u)
                lanes_emitter_light(scene, &v, ul, ua, ub, &direct);
        }
        float us[LANES], u1[LANES], u2[LANES];
        for (int k = 0; k < LANES; k++) {
            if (!v.diffuse[k]) continue;
            set3(&s->radiance, k,
                 v3_add(get3(&s->radiance, k), v3_mul(get3(&s->beta, k), get3(&direct, k))));
            us[k] = rng_next(&s->rng[k]);
            u1[k] = rng_next(&s->rng[k]);
            u2[k] = rng_next(&s->rng[k]);
        }
        lanes_bsdf_bounce(scene, &v, s, us, u1, u2);
    }
    lanes_specular_bounce(scene, &v, s);
    for (int k = 0; k < LANES; k++) {
        if (!s->active[k]) continue;
        s->self[k] = v.id[k];
        if (vertex >= 4u && (flags & TZ_FLAG_ROULETTE) != 0u) {
            vec3 beta = get3(&s->beta, k);
            float q = TZ_MIN(TZ_MAX(TZ_MAX(beta.x, beta.y), beta.z), 1.0f);
            if (rng_next(&s->rng[k]) >= q) {
                s->active[k] = 0;
                continue;
            }
            set3(&s->beta, k, v3_scale(beta, 1.0f / q));
        }
    }
}

/* The packet_integrator sample function of this build (integrator.h), for path mode. */
void PATH_ENTRY(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                uint32_t sample_index, vec3 *out);

void PATH_ENTRY(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                uint32_t sample_index, vec3 *out) {
    const struct gpu_frame *fr = &p->frame;
    path_lanes s;
    for (int k = 0; k < LANES; k++) {
        uint32_t x = i + (uint32_t)k;
        s.active[k] = (uint32_t)k < lanes;
        s.rng[k] = rng_seed(fr->seed, j * fr->width + x, sample_index);
        float u = rng_next(&s.rng[k]), v = rng_next(&s.rng[k]);
        if ((fr->flags & TZ_FLAG_JITTER) == 0u) u = v = 0.5f;
        vec3 d = camera_direction(fr->right, fr->up, fr->forward, fr->origin.w, x, j, u, v);
        vec3 o = camera_origin(fr->origin, fr->near_distance, d);
        set3(&s.o, k, o);
        set3(&s.d, k, d);
        set3(&s.beta, k, v3(1.0f, 1.0f, 1.0f));
        set3(&s.radiance, k, v3(0.0f, 0.0f, 0.0f));
        set3(&s.last_pos, k, o);
        set3(&s.last_n, k, d);
        s.self[k] = -1;
        s.specular[k] = 1;
        s.last_id[k] = -1;
        s.last_pdf[k] = 0.0f;
    }
    for (uint32_t vertex = 1; any_lane(s.active); vertex++) lanes_vertex(p, &s, vertex);
    for (uint32_t k = 0; k < lanes; k++) out[k] = get3(&s.radiance, (int)k);
}
