/* integrator_path_packet.c: path mode (DESIGN section 3.2) over a packet of LANES samples at once
 * (samples of a run of pixels in one row), each lane one pixel's path. The lanes go vertex by
 * vertex together, a lane whose path ended taking the run's next sample (or idling); each lane does
 * the very operations of path_sample (shaders/common/path.h) through the same shared steps and
 * draws the same numbers in the same order from its own stream, so the samples are bit-identical to
 * integrator_path_sample (tested); the rays of all lanes are traced as one packet. */
#include <math.h>
#include <string.h>

#include "render/cpu/scene_accessors.h"

/* The shared text calls the accessors above. */
#include "common/path.h"

/* Built once per vector level (CMakeLists.txt): PACKET_LANES lanes, the entry point named
 * integrator_path_packet_<PACKET_VARIANT>; src/render/cpu/integrator_dispatch.c picks one. */
#ifndef PACKET_LANES
#define PACKET_LANES 8
#define PACKET_VARIANT baseline
#endif
#define LANES PACKET_LANES
#define PATH_ENTRY_NAME(variant) integrator_path_packet_##variant
#define PATH_ENTRY(variant) PATH_ENTRY_NAME(variant)
#define PATH_RUN_NAME(variant) integrator_path_samples_##variant
#define PATH_RUN(variant) PATH_RUN_NAME(variant)

#include "render/cpu/packet_trace.h"
#include "render/cpu/sampler_lanes.h"

/* What the lanes' rays hit: id[k] the sphere (-1 none), through the packet trace; a shadow ray
 * (any_hit) is blocked when id[k] >= 0. Lanes not in active get -1; nothing is traced when no
 * lane is active. Out of line: inlined at its four calls it was slower (docs/PERF.md). */
static __attribute__((noinline)) void trace_lanes(const packed_scene *p, const lanes3 *o,
                                                  const lanes3 *d, const int *self,
                                                  const float *tmax, const int *active, int any_hit,
                                                  int *id, float *t) {
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
    sampler_lanes rng;
    uint32_t vertex[LANES]; /* path_sample's k */
    int job[LANES];         /* the sample the lane runs (out's index), -1 none */
    int active[LANES], self[LANES], specular[LANES], last_id[LANES];
    float last_pdf[LANES];
    lanes3 o, d, beta, radiance, last_pos, last_n, last_origin;
} path_lanes;

/* A vertex of the lanes' paths: the hit and the hit primitive's surface (sphere 0's where none):
 * n and ng its shading and geometric normals facing the ray. */
typedef struct vertex_lanes {
    int id[LANES], diffuse[LANES], specular[LANES], material[LANES], slot[LANES];
    float t[LANES], r[LANES], ks[LANES], alpha[LANES], ior[LANES], share[LANES];
    lanes3 pos, nout, shading, n, ng, wo, c, kd;
} vertex_lanes;

/* phong_lobe(x, alpha) where want[k], else 0: pow_unit lane by lane where alpha is not 0 (x^0 is
 * 1 for every normal x, so Lambertian lanes need none; pow_unit's selects keep gcc from
 * vectorizing it). */
LANE_FN void lobe_lanes(const float *x, const float *alpha, const int *want, float *lobe) {
    int pow_lane[LANES], any_pow = 0;
    for (int k = 0; k < LANES; k++) {
        int normal = want[k] & (x[k] >= TZ_FLT_MIN);
        lobe[k] = normal ? 1.0f : 0.0f;
        pow_lane[k] = normal & (alpha[k] != 0.0f);
        any_pow |= pow_lane[k];
    }
    for (int k = 0; any_pow && k < LANES; k++)
        if (pow_lane[k]) lobe[k] = pow_unit(x[k], alpha[k]);
}

/* bsdf_pdf of sampling.h with its phong_lobe(lobe_cos, alpha) given as lobe. */
LANE_FN float bsdf_pdf_of_lobe(float share, float alpha, float cos_i, float lobe) {
    float diffuse = cos_i * (1.0f / TZ_PI);
    float l = (alpha + 1.0f) * (1.0f / (2.0f * TZ_PI)) * lobe;
    return share * (cos_i > 0.0f ? diffuse : 0.0f) + (1.0f - share) * l;
}

/* brdf_at of lights.h for lane k of the vertex, phong_lobe(x, alpha) given as lobe. */
LANE_FN vec3 brdf_of_lobe(const vertex_lanes *v, int k, float lobe) {
    return phong_from_lobe(get3(&v->kd, k), v->ks[k], v->alpha[k], v->ks[k] > 0.0f ? lobe : 0.0f);
}

/* The light of the point lights at the diffuse lanes' vertices into direct (point_lights). */
LANE_FN void lanes_point_lights(const packed_scene *scene, const vertex_lanes *v, lanes3 *direct) {
    lanes3 so;
    for (int k = 0; k < LANES; k++) {
        set3(&so, k, offset_origin(get3(&v->pos, k), get3(&v->ng, k)));
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
            want[k] = v->diffuse[k] & !(s.cos_i <= 0.0f) & !(v3_dot(get3(&v->ng, k), s.wi) <= 0.0f);
        }
        trace_lanes(scene, &so, &wi, v->id, dist, want, 1, blocked, t);
        for (int k = 0; k < LANES; k++) {
            if (!want[k] || blocked[k] >= 0) continue;
            float x = phong_lobe_cos(get3(&v->n, k), get3(&wi, k), get3(&v->wo, k));
            vec3 f = brdf_of_lobe(v, k, phong_lobe(x, v->alpha[k]));
            set3(direct, k, v3_add(get3(direct, k), v3_mul(f, get3(&rad, k))));
        }
    }
}

/* emitter_light of path.h for the diffuse lanes (a sphere's strategies both computed and one
 * selected, a triangle's point lane by lane), the shadow rays traced together, added to direct;
 * ul, ua, ub the lanes' numbers. */
LANE_FN void lanes_emitter_light(const packed_scene *scene, const vertex_lanes *v, const float *ul,
                                 const float *ua, const float *ub, lanes3 *direct) {
    int e[LANES], slot[LANES], triangle[LANES], strategy[LANES], want[LANES], blocked[LANES];
    float r[LANES], pick[LANES], cos_phi[LANES], sin_phi[LANES]; /* arrays of cos_sin: scalar */
    float pdf[LANES], cos_i[LANES], t_light[LANES], t[LANES], x[LANES], lobe[LANES];
    lanes3 c, emission, so, wi;
    int one_emitter = scene->frame.emitter_count == 1u; /* pick_emitter's 0, whatever ul */
    for (int k = 0; k < LANES; k++) {
        slot[k] = v->diffuse[k] && !one_emitter ? pick_emitter(scene, ul[k]) : 0;
        tz_vec4 emission_pick = emitter_emission_pick(scene, slot[k]);
        e[k] = (int)uint_bits(emitter_primitive_cdf(scene, slot[k]).x);
        triangle[k] = is_triangle(scene, e[k]);
        tz_vec4 cr = sphere_center_radius(scene, triangle[k] ? 0 : e[k]);
        set3(&c, k, xyz(cr));
        r[k] = cr.w;
        set3(&emission, k, xyz(emission_pick));
        pick[k] = emission_pick.w;
    }
    for (int k = 0; k < LANES; k++) {
        strategy[k] =
            light_strategy(get3(&v->pos, k), get3(&v->n, k), v->id[k], e[k], get3(&c, k), r[k]);
        cos_sin phi = cos_sin_turn(ub[k]);
        cos_phi[k] = phi.c;
        sin_phi[k] = phi.s;
    }
    for (int k = 0; k < LANES; k++) {
        vec3 pos = get3(&v->pos, k), n = get3(&v->n, k), ng = get3(&v->ng, k), ck = get3(&c, k);
        float rk = r[k];
        cos_sin phi;
        phi.c = cos_phi[k];
        phi.s = sin_phi[k];
        /* the cone (cone_direction) */
        vec3 to_c = v3_sub(ck, pos);
        float d2 = v3_dot(to_c, to_c);
        vec3 axis = v3_scale(to_c, 1.0f / TZ_SQRT(d2));
        float omc = cone_one_minus_cos(rk * rk, d2);
        float xc = ua[k] * omc;
        float sin2 = xc * (2.0f - xc);
        float cone_pdf = 1.0f / (2.0f * TZ_PI * omc);
        vec3 cone_wi = direction_about(axis, 1.0f - xc, TZ_SQRT(TZ_MAX(sin2, 0.0f)), phi);
        float cone_p = pick[k] * cone_pdf;
        /* the area (sphere_area_direction) */
        float z = 1.0f - 2.0f * ua[k];
        float rho = TZ_SQRT(TZ_MAX(1.0f - z * z, 0.0f));
        vec3 dir = v3(rho * phi.c, rho * phi.s, z);
        vec3 q = v3_add(ck, v3_scale(dir, rk));
        vec3 to_q = v3_sub(q, pos);
        float dist2 = v3_dot(to_q, to_q);
        vec3 area_wi = v3_scale(to_q, 1.0f / TZ_SQRT(dist2));
        vec3 nq = v3_scale(v3_sub(q, ck), 1.0f / rk);
        float area_p = pick[k] * area_pdf(rk, dist2, v3_dot(nq, area_wi));
        int cone = strategy[k] == LIGHT_CONE;
        vec3 w = select3(cone, cone_wi, area_wi);
        float p = cone ? cone_p : area_p;
        float ci = v3_dot(n, w);
        int ok = v->diffuse[k] & (strategy[k] != LIGHT_NONE) & (ci > 0.0f) &
                 (v3_dot(ng, w) > 0.0f) & (p > 0.0f) & (p < INFINITY);
        vec3 o = offset_origin(pos, ng);
        float tl = sphere_distance(ck.x, ck.y, ck.z, rk, o, w, ray_eps(o), e[k] == v->id[k]);
        set3(&so, k, o);
        set3(&wi, k, w);
        pdf[k] = p;
        cos_i[k] = ci;
        t_light[k] = tl;
        want[k] = ok & (tl < INFINITY);
    }
    for (int k = 0; any_lane(triangle) && k < LANES; k++) {
        if (!(v->diffuse[k] & triangle[k])) continue;
        vec3 n = get3(&v->n, k), ng = get3(&v->ng, k), o = offset_origin(get3(&v->pos, k), ng);
        triangle_corners tk = corners_of(scene, e[k]);
        vec3 q = triangle_area_point(tk.a, tk.b, tk.c, ua[k], ub[k]);
        vec3 w = v3_normalize(v3_sub(q, o));
        float area = emitter_primitive_cdf(scene, slot[k]).z;
        float p = pick[k] * triangle_area_pdf(tk, area, o, q, w);
        float tl = triangle_distance(tk.a, tk.b, tk.c, o, w, ray_eps(o), TZ_FALSE);
        float ci = v3_dot(n, w);
        int ok =
            (e[k] != v->id[k]) & (ci > 0.0f) & (v3_dot(ng, w) > 0.0f) & (p > 0.0f) & (p < INFINITY);
        set3(&so, k, o);
        set3(&wi, k, w);
        pdf[k] = p;
        cos_i[k] = ci;
        t_light[k] = tl;
        want[k] = ok & (tl < INFINITY);
    }
    trace_lanes(scene, &so, &wi, v->id, t_light, want, 1, blocked, t);
    for (int k = 0; k < LANES; k++) {
        want[k] = want[k] & (blocked[k] < 0);
        x[k] = phong_lobe_cos(get3(&v->n, k), get3(&wi, k), get3(&v->wo, k));
    }
    lobe_lanes(x, v->alpha, want, lobe);
    int lights_only = (scene->frame.flags & TZ_FLAG_LIGHTS_ONLY) != 0u;
    for (int k = 0; k < LANES; k++) {
        float b = bsdf_pdf_of_lobe(v->share[k], v->alpha[k], cos_i[k], lobe[k]);
        float mis = pdf[k] / (pdf[k] * pdf[k] + b * b);
        float weight = lights_only ? 1.0f / pdf[k] : mis;
        vec3 l =
            v3_scale(v3_mul(brdf_of_lobe(v, k, lobe[k]), get3(&emission, k)), cos_i[k] * weight);
        l = select3(want[k], l, v3(0.0f, 0.0f, 0.0f));
        vec3 dk = get3(direct, k);
        set3(direct, k, select3(v->diffuse[k], v3_add(dk, l), dk));
    }
}

/* The lanes' next rays at diffuse vertices: the BSDF's sample, beta and the last vertex updated;
 * lanes whose path ends here are made inactive. */
LANE_FN void lanes_bsdf_bounce(const vertex_lanes *v, path_lanes *s, const float *us,
                               const float *u1, const float *u2) {
    float cos_i[LANES], x[LANES], lobe[LANES];
    int cosine[LANES], go[LANES], any_lobe = 0;
    lanes3 lobe_wi, wi;
    for (int k = 0; k < LANES; k++) {
        go[k] = v->diffuse[k] & !(v->share[k] < 0.0f);
        cosine[k] = us[k] < v->share[k];
        any_lobe |= go[k] & !cosine[k];
        set3(&lobe_wi, k, v3(0.0f, 0.0f, 0.0f));
    }
    for (int k = 0; any_lobe && k < LANES; k++) {
        vec3 n = get3(&v->n, k), wo = get3(&v->wo, k);
        vec3 wr = v3_sub(v3_scale(n, 2.0f * v3_dot(n, wo)), wo);
        set3(&lobe_wi, k, phong_lobe_direction(wr, v->alpha[k], u1[k], u2[k]));
    }
    for (int k = 0; k < LANES; k++) {
        vec3 n = get3(&v->n, k), wo = get3(&v->wo, k);
        vec3 w = select3(cosine[k], cosine_direction(n, u1[k], u2[k]), get3(&lobe_wi, k));
        set3(&wi, k, w);
        cos_i[k] = v3_dot(n, w);
        x[k] = phong_lobe_cos(n, w, wo);
    }
    lobe_lanes(x, v->alpha, go, lobe);
    for (int k = 0; k < LANES; k++) {
        float pdf = bsdf_pdf_of_lobe(v->share[k], v->alpha[k], cos_i[k], lobe[k]);
        vec3 n = get3(&v->n, k), ng = get3(&v->ng, k), pos = get3(&v->pos, k);
        /* A direction below the face (a shading normal leaning away) ends the path. */
        int ok = go[k] & (cos_i[k] > 0.0f) & (v3_dot(ng, get3(&wi, k)) > 0.0f) & (pdf > 0.0f);
        vec3 f = v3_scale(brdf_of_lobe(v, k, lobe[k]), cos_i[k] / pdf);
        vec3 o = offset_origin(pos, ng);
        set3(&s->beta, k, select3(ok, v3_mul(get3(&s->beta, k), f), get3(&s->beta, k)));
        set3(&s->last_pos, k, select3(ok, pos, get3(&s->last_pos, k)));
        set3(&s->last_n, k, select3(ok, n, get3(&s->last_n, k)));
        set3(&s->last_origin, k, select3(ok, o, get3(&s->last_origin, k)));
        s->last_id[k] = ok ? v->id[k] : s->last_id[k];
        s->last_pdf[k] = ok ? pdf : s->last_pdf[k];
        s->specular[k] = ok ? 0 : s->specular[k];
        set3(&s->o, k, select3(ok, o, get3(&s->o, k)));
        set3(&s->d, k, select3(ok, get3(&wi, k), get3(&s->d, k)));
        s->active[k] = v->diffuse[k] ? ok : s->active[k];
    }
}

/* The lanes' next rays at mirror and glass vertices (glass draws its Fresnel number). */
LANE_FN void lanes_specular_bounce(uint32_t flags, const vertex_lanes *v, path_lanes *s) {
    int refractive[LANES];
    float uf[LANES];
    for (int k = 0; k < LANES; k++)
        refractive[k] = v->specular[k] & (v->material[k] == TZ_MATERIAL_REFRACTIVE);
    draw_lanes_1d(flags, &s->rng, refractive, uf);
    for (int k = 0; k < LANES; k++) {
        vec3 d = get3(&s->d, k), nout = get3(&v->nout, k);
        float ior = v->ior[k];
        int entering = v3_dot(d, nout) < 0.0f;
        float eta = entering ? 1.0f / ior : ior;
        float c1 = entering ? -v3_dot(d, nout) : v3_dot(d, nout);
        float kk = 1.0f - eta * eta * (1.0f - c1 * c1);
        int transmits = refractive[k] & !(uf[k] < fresnel_dielectric(eta, c1, kk));
        int on = v->specular[k];
        vec3 beta = get3(&s->beta, k);
        set3(&s->beta, k, select3(on, v3_mul(beta, get3(&v->kd, k)), beta));
        next_ray next = specular_next(get3(&v->pos, k), nout, d, transmits, ior);
        set3(&s->o, k, select3(on, next.o, get3(&s->o, k)));
        set3(&s->d, k, select3(on, next.d, d));
        s->specular[k] = on ? 1 : s->specular[k];
    }
}

/* The emission of the emitters the lanes hit (emit[k]), weighted by MIS, added to radiance. */
LANE_FN void lanes_emission(const packed_scene *scene, const vertex_lanes *v, const int *emit,
                            path_lanes *s) {
    uint32_t flags = scene->frame.flags;
    for (int k = 0; k < LANES; k++) {
        if (!emit[k]) continue;
        int full = s->specular[k] || (flags & TZ_FLAG_BSDF_ONLY) != 0u;
        path_vertex last;
        last.pos = get3(&s->last_pos, k);
        last.n = get3(&s->last_n, k);
        last.origin = get3(&s->last_origin, k);
        last.id = s->last_id[k];
        last.bsdf_pdf = s->last_pdf[k];
        float w = full ? 1.0f
                  : (flags & TZ_FLAG_LIGHTS_ONLY) != 0u
                      ? 0.0f
                      : power_heuristic(
                            last.bsdf_pdf,
                            light_pdf_at(scene, last, v->id[k], get3(&v->pos, k), get3(&s->d, k)));
        vec3 emitted =
            v3_scale(v3_mul(get3(&s->beta, k), xyz(emitter_emission_pick(scene, v->slot[k]))), w);
        set3(&s->radiance, k, v3_add(get3(&s->radiance, k), emitted));
    }
}

/* One vertex of every active lane's path (an iteration of path_sample's loop). */
LANE_FN void lanes_vertex(const packed_scene *scene, path_lanes *s) {
    const struct gpu_frame *fr = &scene->frame;
    uint32_t flags = fr->flags;
    vertex_lanes v;
    float tmax[LANES];
    int emit[LANES], any_emit = 0;
    for (int k = 0; k < LANES; k++) tmax[k] = INFINITY;
    trace_lanes(scene, &s->o, &s->d, s->self, tmax, s->active, 0, v.id, v.t);
    int triangle[LANES];
    for (int k = 0; k < LANES; k++) { /* gather the hit spheres */
        triangle[k] = v.id[k] >= 0 && is_triangle(scene, v.id[k]);
        const struct gpu_sphere *g = &scene->spheres[v.id[k] >= 0 && !triangle[k] ? v.id[k] : 0];
        set3(&v.c, k, xyz(g->center_radius));
        v.r[k] = g->center_radius.w;
        set3(&v.kd, k, xyz(g->color_ks));
        v.ks[k] = g->color_ks.w;
        v.alpha[k] = g->params.x;
        v.ior[k] = g->params.y;
        v.material[k] = (int)g->params.z;
        v.slot[k] = (int)g->params.w - 1;
    }
    for (int k = 0; k < LANES; k++) { /* surface_at of a sphere */
        vec3 pos = v3_add(get3(&s->o, k), v3_scale(get3(&s->d, k), v.t[k]));
        vec3 nout = v3_scale(v3_sub(pos, get3(&v.c, k)), 1.0f / v.r[k]);
        set3(&v.pos, k, pos);
        set3(&v.nout, k, nout);
        set3(&v.shading, k, nout);
    }
    for (int k = 0; any_lane(triangle) && k < LANES; k++) { /* and of a triangle */
        if (!triangle[k]) continue;
        surface sf =
            triangle_surface(scene, v.id[k], get3(&v.pos, k), get3(&s->o, k), get3(&s->d, k));
        set3(&v.nout, k, sf.nout);
        set3(&v.shading, k, sf.shading);
        set3(&v.kd, k, xyz(sf.color_ks));
        v.ks[k] = sf.color_ks.w;
        v.alpha[k] = sf.params.x;
        v.ior[k] = sf.params.y;
        v.material[k] = (int)sf.params.z;
        v.slot[k] = (int)sf.params.w - 1;
    }
    vec3 background = xyz(fr->background);
    for (int k = 0; k < LANES; k++) {
        int hit = s->active[k] & (v.id[k] >= 0), miss = s->active[k] & (v.id[k] < 0);
        vec3 radiance = get3(&s->radiance, k);
        set3(&s->radiance, k,
             select3(miss, v3_add(radiance, v3_mul(get3(&s->beta, k), background)), radiance));
        vec3 d = get3(&s->d, k), nout = get3(&v.nout, k), shading = get3(&v.shading, k);
        emit[k] = hit & (v.slot[k] >= 0);
        any_emit |= emit[k];
        int go = hit & !(s->vertex[k] > fr->bounces); /* else the path ends at this hit */
        int diffuse =
            go & ((v.material[k] == TZ_MATERIAL_LAMBERTIAN) | (v.material[k] == TZ_MATERIAL_PHONG));
        v.diffuse[k] = diffuse;
        v.specular[k] = go & !diffuse;
        /* facing_shading and facing_normal of primitive.h and shade.h */
        set3(&v.n, k, select3(v3_dot(nout, d) < 0.0f, shading, v3_scale(shading, -1.0f)));
        set3(&v.ng, k, facing_normal(nout, d));
        set3(&v.wo, k, v3_scale(d, -1.0f));
        v.share[k] = diffuse_share(get3(&v.kd, k), v.ks[k]);
        s->active[k] = go;
    }
    if (any_emit) lanes_emission(scene, &v, emit, s);
    if (any_lane(v.diffuse)) {
        lanes3 direct;
        lanes_point_lights(scene, &v, &direct);
        if (fr->emitter_count > 0u) {
            float ul[LANES], ua[LANES], ub[LANES];
            draw_lanes_1d(flags, &s->rng, v.diffuse, ul);
            draw_lanes_2d(flags, &s->rng, v.diffuse, ua, ub);
            if ((flags & TZ_FLAG_BSDF_ONLY) == 0u)
                lanes_emitter_light(scene, &v, ul, ua, ub, &direct);
        }
        float us[LANES], u1[LANES], u2[LANES];
        for (int k = 0; k < LANES; k++) {
            vec3 radiance = get3(&s->radiance, k);
            set3(&s->radiance, k,
                 select3(v.diffuse[k],
                         v3_add(radiance, v3_mul(get3(&s->beta, k), get3(&direct, k))), radiance));
        }
        draw_lanes_1d(flags, &s->rng, v.diffuse, us);
        draw_lanes_2d(flags, &s->rng, v.diffuse, u1, u2);
        lanes_bsdf_bounce(&v, s, us, u1, u2);
    }
    if (any_lane(v.specular)) lanes_specular_bounce(flags, &v, s);
    for (int k = 0; k < LANES; k++) s->self[k] = s->active[k] ? v.id[k] : s->self[k];
    if ((flags & TZ_FLAG_ROULETTE) != 0u) {
        float u[LANES];
        int take[LANES];
        for (int k = 0; k < LANES; k++) take[k] = s->active[k] & (s->vertex[k] >= 4u);
        draw_lanes_1d(flags, &s->rng, take, u);
        float q[LANES];
        for (int k = 0; k < LANES; k++) {
            /* TZ_MIN(TZ_MAX(TZ_MAX(x, y), z), 1) of path_sample, one select at a time: nested,
             * the selects kept the loop from compiling to SIMD */
            float x = s->beta.x[k], y = s->beta.y[k], z = s->beta.z[k];
            float xy = TZ_MAX(x, y);
            float xyz = TZ_MAX(xy, z);
            q[k] = TZ_MIN(xyz, 1.0f);
        }
        for (int k = 0; k < LANES; k++) {
            int survives = !(u[k] >= q[k]);
            vec3 beta = get3(&s->beta, k);
            set3(&s->beta, k, select3(take[k] & survives, v3_scale(beta, 1.0f / q[k]), beta));
            s->active[k] = take[k] ? survives : s->active[k];
        }
    }
    for (int k = 0; k < LANES; k++) s->vertex[k]++;
}

/* The lanes of start begin sample sample[k] of pixel (x[k], y) (path_sample's start); the other
 * lanes are left as they are. */
LANE_FN void lanes_start(const packed_scene *p, path_lanes *s, const int *start, const uint32_t *x,
                         uint32_t y, const uint32_t *sample) {
    const struct gpu_frame fr = p->frame; /* a copy: the loop below then compiles to SIMD */
    int jitter = (fr.flags & TZ_FLAG_JITTER) != 0u;
    for (int k = 0; k < LANES; k++) {
        int on = start[k];
        sampler_state rng = sampler_start(fr.flags, fr.seed, y * fr.width + x[k], sample[k]);
        float u, v;
        sample_2d(fr.flags, &rng, &u, &v);
        u = jitter ? u : 0.5f;
        v = jitter ? v : 0.5f;
        vec3 d = camera_direction(fr.right, fr.up, fr.forward, fr.origin.w, x[k], y, u, v);
        vec3 o = camera_origin(fr.origin, fr.near_distance, d);
        lane_sampler_set(&s->rng, k, on, rng);
        s->active[k] = on ? 1 : s->active[k];
        s->vertex[k] = on ? 1u : s->vertex[k];
        set3(&s->o, k, select3(on, o, get3(&s->o, k)));
        set3(&s->d, k, select3(on, d, get3(&s->d, k)));
        set3(&s->beta, k, select3(on, v3(1.0f, 1.0f, 1.0f), get3(&s->beta, k)));
        set3(&s->radiance, k, select3(on, v3(0.0f, 0.0f, 0.0f), get3(&s->radiance, k)));
        set3(&s->last_pos, k, select3(on, o, get3(&s->last_pos, k)));
        set3(&s->last_n, k, select3(on, d, get3(&s->last_n, k)));
        set3(&s->last_origin, k, select3(on, o, get3(&s->last_origin, k)));
        s->self[k] = on ? -1 : s->self[k];
        s->specular[k] = on ? 1 : s->specular[k];
        s->last_id[k] = on ? -1 : s->last_id[k];
        s->last_pdf[k] = on ? 0.0f : s->last_pdf[k];
    }
}

/* Samples [first, first + count) of pixels (i + k, j), k < lanes, into out[s * lanes + k]: each
 * lane takes the next sample as soon as its path ends, so that the lanes stay busy. */
LANE_FN void run_samples(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                         uint32_t first, uint32_t count, vec3 *out) {
    path_lanes s;
    memset(&s, 0, sizeof s);
    uint32_t next = 0, total = lanes * count;
    for (int k = 0; k < LANES; k++) s.job[k] = -1;
    for (;;) {
        int start[LANES], any_start = 0;
        uint32_t x[LANES], sample[LANES];
        for (int k = 0; k < LANES; k++) {
            start[k] = 0;
            x[k] = i;
            sample[k] = first;
            if (s.active[k]) continue;
            if (s.job[k] >= 0) out[s.job[k]] = get3(&s.radiance, k);
            s.job[k] = -1;
            if (next < total) {
                s.job[k] = (int)next;
                x[k] = i + next % lanes;
                sample[k] = first + next / lanes;
                start[k] = any_start = 1;
                next++;
            }
        }
        if (any_start) lanes_start(p, &s, start, x, j, sample);
        if (!any_lane(s.active)) return;
        lanes_vertex(p, &s);
    }
}

/* The packet_integrator sample function of this build (integrator.h), for path mode. */
void PATH_ENTRY(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                uint32_t sample_index, vec3 *out);

void PATH_ENTRY(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                uint32_t sample_index, vec3 *out) {
    run_samples(p, i, j, lanes, sample_index, 1, out);
}

/* The packet_integrator samples function of this build (integrator.h). */
void PATH_RUN(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                              uint32_t first, uint32_t count, vec3 *out);

void PATH_RUN(PACKET_VARIANT)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                              uint32_t first, uint32_t count, vec3 *out) {
    run_samples(p, i, j, lanes, first, count, out);
}
