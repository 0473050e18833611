/* path_vertex_lanes.h: a vertex of path mode's paths over the LANES lanes of a packet build
 * (integrator_path_packet.c, which defines LANES and LANE_FN and includes packet_trace.h
 * first): the lanes' rays traced as one packet, the surface each lane hit, its
 * BSDF's lobe and pdf, and the light gathered there by next-event estimation (the point lights
 * and one emitter), each lane doing path.h's operations in its order. */
#ifndef TRAZADOR_RENDER_CPU_PATH_VERTEX_LANES_H
#define TRAZADOR_RENDER_CPU_PATH_VERTEX_LANES_H

/* What the lanes' rays hit: id[k] the sphere (-1 none), through the packet trace; a shadow ray
 * (any_hit) is blocked when id[k] >= 0, hint as packet_trace's. Lanes not in active get -1;
 * nothing is traced when no lane is active. Out of line: inlined at its four calls it was slower
 * (docs/PERF.md). */
static __attribute__((noinline)) void trace_lanes(const packed_scene *p, const lanes3 *o,
                                                  const lanes3 *d, const int *self,
                                                  const float *tmax, const int *active, int any_hit,
                                                  uint32_t *hint, int *id, float *t) {
    if (any_lane(active)) {
        packet_trace(p, o, d, self, tmax, active, any_hit, hint, id, t);
        return;
    }
    for (int k = 0; k < LANES; k++) {
        id[k] = -1;
        t[k] = INFINITY;
    }
}

/* environment_look_along of the lanes' directions d: the radiance rgb and light pdf of what each
 * finds where it meets nothing, in three loops, the texels' indices, their fetch and the pdfs,
 * so that the first and the last stay vector code. */
LANE_FN void lanes_environment_look(const packed_scene *scene, const lanes3 *d, lanes3 *rgb,
                                    float *light_pdf) {
    if (!(scene->frame.flags & TZ_FLAG_ENVIRONMENT)) {
        for (int k = 0; k < LANES; k++) {
            environment_look e = environment_look_along(scene, get3(d, k));
            set3(rgb, k, e.radiance);
            light_pdf[k] = e.light_pdf;
        }
        return;
    }
    lanes3 m;
    int texel[LANES];
    float density[LANES];
    for (int k = 0; k < LANES; k++) {
        set3(&m, k, environment_map_direction(scene, get3(d, k)));
        texel[k] = environment_texel_of(scene, get3(&m, k));
    }
    for (int k = 0; k < LANES; k++) {
        tz_vec4 t = environment_texel(scene, texel[k]);
        set3(rgb, k, xyz(t));
        density[k] = t.w;
    }
    for (int k = 0; k < LANES; k++)
        light_pdf[k] = environment_light_pdf(scene, get3(&m, k), density[k]);
}

/* A vertex of the lanes' paths: the hit and the hit primitive's surface (sphere 0's where none):
 * n and ng its shading and geometric normals facing the ray. */
typedef struct vertex_lanes {
    int id[LANES], diffuse[LANES], specular[LANES], material[LANES], slot[LANES];
    int microfacet[LANES], any_microfacet; /* diffuse lanes of a microfacet kind */
    int dielectric[LANES], any_dielectric; /* and of rough glass (ior its bsdf_eta) */
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

/* Lane k's material of the vertex (bsdf.h's). */
LANE_FN bsdf_material vertex_material(const vertex_lanes *v, int k) {
    bsdf_material m;
    m.kind = v->material[k];
    m.color = get3(&v->kd, k);
    m.ks = v->ks[k];
    m.alpha = v->alpha[k];
    m.ior = v->ior[k];
    return m;
}

/* The light of the point lights at the diffuse lanes' vertices into direct (point_lights). */
LANE_FN void lanes_point_lights(const packed_scene *scene, const vertex_lanes *v, lanes3 *direct) {
    lanes3 so;
    for (int k = 0; k < LANES; k++) set3(direct, k, v3(0.0f, 0.0f, 0.0f));
    if (light_count(scene) == 0u) return; /* path mode's usual case: emitters alone */
    for (uint32_t l = 0; l < light_count(scene); l++) {
        lanes3 wi, rad;
        float dist[LANES], t[LANES];
        int want[LANES], blocked[LANES];
        for (int k = 0; k < LANES; k++) {
            light_sample s =
                point_light(light_position_power(scene, (int)l), light_color(scene, (int)l),
                            light_shape(scene, (int)l), get3(&v->pos, k), get3(&v->n, k));
            vec3 ng = get3(&v->ng, k);
            set3(&wi, k, s.wi);
            set3(&rad, k, select3(s.cos_i < 0.0f, v3_scale(s.radiance, -1.0f), s.radiance));
            set3(&so, k, bsdf_next_origin(get3(&v->pos, k), ng, s.wi));
            dist[k] = s.dist;
            want[k] = v->diffuse[k] & point_light_reaches(v->material[k], s.cos_i, ng, s.wi);
        }
        trace_lanes(scene, &so, &wi, v->id, dist, want, 1, NULL, blocked, t);
        for (int k = 0; k < LANES; k++) {
            if (!want[k] || blocked[k] >= 0) continue;
            vec3 f = bsdf_f(vertex_material(v, k), get3(&v->n, k), get3(&wi, k), get3(&v->wo, k));
            set3(direct, k, v3_add(get3(direct, k), v3_mul(f, get3(&rad, k))));
        }
    }
}

/* fold_terms of the folded BSDF (sampling.h) for the lanes in folds, the direction in wi: fv,
 * f_scale and pdf (the BRDF, the factor that makes it f cos, and the pdf at wi alone) become the
 * sums over wi and its mirror image (fv f cos, f_scale 1). Out of line: only smooth faces need
 * it, and inlined it grew its callers past gcc's inlining of sphere_distance. */
static __attribute__((noinline)) void lanes_fold(const vertex_lanes *v, const int *folds,
                                                 const lanes3 *wi, const float *cos_i, lanes3 *fv,
                                                 float *f_scale, float *pdf) {
    float cos_m[LANES], xm[LANES], lobe_m[LANES];
    for (int k = 0; k < LANES; k++) {
        fold_mirror fm =
            fold_mirror_of(get3(&v->n, k), get3(&v->ng, k), get3(wi, k), get3(&v->wo, k));
        cos_m[k] = fm.cos_m;
        xm[k] = fm.xm;
    }
    lobe_lanes(xm, v->alpha, folds, lobe_m);
    for (int k = 0; k < LANES; k++) {
        if (!folds[k]) continue;
        folded_bsdf fb = fold_of_lobe(vertex_material(v, k), v->share[k], get3(fv, k), cos_i[k],
                                      pdf[k], cos_m[k], lobe_m[k]);
        set3(fv, k, fb.f_cos);
        f_scale[k] = 1.0f;
        pdf[k] = fb.pdf;
    }
}

/* bsdf_eval of the microfacet lanes in want at directions wi into fv, f_scale and pdf (the Phong
 * terms the other lanes computed). Out of line: most scenes have no such lane. */
static __attribute__((noinline)) void lanes_microfacet_eval(const vertex_lanes *v, const int *want,
                                                            const lanes3 *wi, lanes3 *fv,
                                                            float *f_scale, float *pdf) {
    for (int k = 0; k < LANES; k++) {
        if (!(want[k] & v->microfacet[k])) continue;
        bsdf_value bv =
            microfacet_eval(vertex_material(v, k), get3(&v->n, k), get3(wi, k), get3(&v->wo, k));
        set3(fv, k, bv.f);
        f_scale[k] = bv.f_scale;
        pdf[k] = bv.pdf;
    }
}

/* emitter_light of path.h itself for the rough glass lanes, whose light may come from below and
 * whose shadow rays then leave below: added to direct. Out of line: few scenes have such lanes. */
static __attribute__((noinline)) void lanes_dielectric_light(const packed_scene *scene,
                                                             const vertex_lanes *v, const float *ul,
                                                             const float *ua, const float *ub,
                                                             lanes3 *direct) {
    for (int k = 0; k < LANES; k++) {
        if (!v->dielectric[k]) continue;
        surface sf = surface_none();
        sf.pos = get3(&v->pos, k);
        sf.m = vertex_material(v, k);
        vec3 l = emitter_light(scene, v->id[k], sf, get3(&v->n, k), get3(&v->ng, k),
                               get3(&v->wo, k), v->share[k], ul[k], ua[k], ub[k]);
        set3(direct, k, v3_add(get3(direct, k), l));
    }
}

/* The shadow rays of lanes_emitter_light toward the lanes' light points, with what weighs them. */
typedef struct shadow_lanes {
    lanes3 origin, dir;
    float pdf[LANES], cos_i[LANES], t_light[LANES]; /* t_light: the light point's distance */
    int want[LANES];                                /* traced, and lit unless blocked */
} shadow_lanes;

/* Lane k of s: a ray from o along w to a light point at distance tl, drawn with pdf p, at cos_i
 * ci; wanted where ok and the ray meets the light. */
LANE_FN void shadow_lane_set(shadow_lanes *s, int k, vec3 o, vec3 w, float p, float ci, float tl,
                             int ok) {
    set3(&s->origin, k, o);
    set3(&s->dir, k, w);
    s->pdf[k] = p;
    s->cos_i[k] = ci;
    s->t_light[k] = tl;
    s->want[k] = ok & (tl < INFINITY);
}

/* solid_angle_light_direction out of line: inlined, it grew lanes_emitter_light enough to keep
 * the area sample's code from being inlined (8-12% slower where no lane took it). */
static __attribute__((noinline)) light_direction lanes_solid_angle(triangle_corners k, vec3 o,
                                                                   float ua, float ub,
                                                                   light_direction by_area) {
    return solid_angle_light_direction(k, o, ua, ub, by_area);
}

/* The radiance of the sphere and face emitters e (slots slot) the wanted lanes' shadow rays s
 * aim at, their maps looked up where the rays end (emitter_radiance_along, as
 * emitter_sample_from): out of line, so that the lanes' loops above stay vector code. */
static __attribute__((noinline)) void lanes_emitter_maps(const packed_scene *scene,
                                                         const vertex_lanes *v, const int *slot,
                                                         const int *e, const shadow_lanes *s,
                                                         lanes3 *emission) {
    for (int k = 0; k < LANES; k++) {
        int primitive = e[k] != (int)TZ_ENV_PRIMITIVE && e[k] != (int)TZ_SUN_PRIMITIVE;
        if (v->diffuse[k] && s->want[k] && primitive)
            set3(emission, k,
                 emitter_radiance_along(scene, slot[k], e[k], get3(&s->origin, k), get3(&s->dir, k),
                                        s->t_light[k]));
    }
}

/* emitter_light of path.h for the diffuse lanes (a sphere's strategies, sphere_cone_light and
 * sphere_area_light, both computed and one selected where some lane aims at a sphere, a
 * triangle's and the environment's direction lane by lane), the shadow rays traced together (hint
 * as packet_trace's), added to direct; ul, ua, ub the lanes' numbers. */
LANE_FN void lanes_emitter_light(const packed_scene *scene, const vertex_lanes *v, const float *ul,
                                 const float *ua, const float *ub, uint32_t *hint, lanes3 *direct) {
    int e[LANES], slot[LANES], triangle[LANES], env[LANES], sun[LANES], strategy[LANES];
    int blocked[LANES];
    float r[LANES], pick[LANES], cos_phi[LANES], sin_phi[LANES]; /* arrays of cos_sin: scalar */
    float t[LANES], x[LANES], lobe[LANES];
    int folds[LANES];
    lanes3 c, emission;
    shadow_lanes s;
    for (int k = 0; k < LANES; k++) folds[k] = folds_at(get3(&v->n, k), get3(&v->ng, k));
    int one_emitter = scene->frame.emitter_count == 1u; /* pick_emitter's 0, whatever ul */
    for (int k = 0; k < LANES; k++) { /* with one emitter, lane 0's look-ups serve every lane */
        slot[k] = v->diffuse[k] && !one_emitter ? pick_emitter(scene, ul[k]) : 0;
        if (one_emitter && k > 0) break;
        tz_vec4 emission_pick = emitter_emission_pick(scene, slot[k]);
        e[k] = (int)uint_bits(emitter_primitive_cdf(scene, slot[k]).x);
        env[k] = e[k] == (int)TZ_ENV_PRIMITIVE;
        sun[k] = e[k] == (int)TZ_SUN_PRIMITIVE;
        triangle[k] = (!env[k]) & (!sun[k]) & is_triangle(scene, e[k]);
        tz_vec4 cr = sphere_center_radius(scene, triangle[k] | env[k] | sun[k] ? 0 : e[k]);
        set3(&c, k, xyz(cr));
        r[k] = cr.w;
        set3(&emission, k, xyz(emission_pick));
        pick[k] = emission_pick.w;
    }
    for (int k = 1; one_emitter && k < LANES; k++) {
        slot[k] = 0, e[k] = e[0], triangle[k] = triangle[0], env[k] = env[0], r[k] = r[0];
        sun[k] = sun[0];
        pick[k] = pick[0];
        set3(&c, k, get3(&c, 0));
        set3(&emission, k, get3(&emission, 0));
    }
    int sphere[LANES];
    for (int k = 0; k < LANES; k++) sphere[k] = v->diffuse[k] & !(triangle[k] | env[k] | sun[k]);
    int any_sphere = any_lane(sphere);
    /* no lane aims at a sphere (the lights are faces, the map, the sun): none wanted yet */
    for (int k = 0; !any_sphere && k < LANES; k++)
        shadow_lane_set(&s, k, get3(&v->pos, k), get3(&v->n, k), 0.0f, 0.0f, INFINITY, 0);
    for (int k = 0; any_sphere && k < LANES; k++) {
        strategy[k] =
            light_strategy(get3(&v->pos, k), get3(&v->n, k), v->id[k], e[k], get3(&c, k), r[k]);
        cos_sin phi = cos_sin_turn(ub[k]);
        cos_phi[k] = phi.c;
        sin_phi[k] = phi.s;
    }
    for (int k = 0; any_sphere && k < LANES; k++) {
        vec3 pos = get3(&v->pos, k), n = get3(&v->n, k), ng = get3(&v->ng, k), ck = get3(&c, k);
        float rk = r[k];
        cos_sin phi;
        phi.c = cos_phi[k];
        phi.s = sin_phi[k];
        light_direction by_cone = sphere_cone_light(ck, rk, pos, ua[k], phi);
        light_direction by_area = sphere_area_light(ck, rk, pos, ua[k], phi);
        float cone_p = pick[k] * by_cone.pdf, area_p = pick[k] * by_area.pdf;
        int cone = strategy[k] == LIGHT_CONE;
        vec3 w = select3(cone, by_cone.wi, by_area.wi);
        float p = cone ? cone_p : area_p;
        float ci = v3_dot(n, w);
        int ok = v->diffuse[k] & (strategy[k] != LIGHT_NONE) & (folds[k] | (ci > 0.0f)) &
                 (v3_dot(ng, w) > 0.0f) & (p > 0.0f) & (p < INFINITY);
        vec3 o = offset_origin(pos, ng);
        float tl = sphere_distance(ck.x, ck.y, ck.z, rk, o, w, ray_eps(o), e[k] == v->id[k]);
        shadow_lane_set(&s, k, o, w, p, ci, tl, ok);
    }
    for (int k = 0; any_lane(triangle) && k < LANES; k++) {
        if (!(v->diffuse[k] & triangle[k])) continue;
        vec3 n = get3(&v->n, k), ng = get3(&v->ng, k), o = offset_origin(get3(&v->pos, k), ng);
        triangle_corners tk = corners_of(scene, e[k]);
        float area = emitter_primitive_cdf(scene, slot[k]).z;
        /* triangle_light_direction, the solid angle's rare case out of line */
        light_direction l = area_light_direction(tk, area, o, ua[k], ub[k]);
        if (near_triangle_plane(tk.a, tk.b, tk.c, o)) l = lanes_solid_angle(tk, o, ua[k], ub[k], l);
        vec3 w = l.wi;
        float p = pick[k] * l.pdf;
        float tl = triangle_light_distance(tk.a, tk.b, tk.c, o, w);
        float ci = v3_dot(n, w);
        int ok = (e[k] != v->id[k]) & (folds[k] | (ci > 0.0f)) & (v3_dot(ng, w) > 0.0f) &
                 (p > 0.0f) & (p < INFINITY);
        shadow_lane_set(&s, k, o, w, p, ci, tl, ok);
    }
    for (int k = 0; any_lane(env) && k < LANES; k++) {
        if (!(v->diffuse[k] & env[k])) continue;
        vec3 n = get3(&v->n, k), ng = get3(&v->ng, k), o = offset_origin(get3(&v->pos, k), ng);
        environment_sample es = environment_sample_at(scene, ua[k], ub[k]);
        float p = pick[k] * es.pdf;
        float ci = v3_dot(n, es.wi);
        int ok =
            (folds[k] | (ci > 0.0f)) & (v3_dot(ng, es.wi) > 0.0f) & (p > 0.0f) & (p < INFINITY);
        set3(&emission, k, es.radiance);
        shadow_lane_set(&s, k, o, es.wi, p, ci, TZ_ENV_DISTANCE, ok);
    }
    for (int k = 0; any_lane(sun) && k < LANES; k++) {
        if (!(v->diffuse[k] & sun[k])) continue;
        vec3 n = get3(&v->n, k), ng = get3(&v->ng, k), o = offset_origin(get3(&v->pos, k), ng);
        direction_sample ds =
            cone_direction(xyz(scene->frame.sun), scene->frame.sun.w, ua[k], ub[k]);
        float p = pick[k] * ds.pdf;
        float ci = v3_dot(n, ds.wi);
        int ok =
            (folds[k] | (ci > 0.0f)) & (v3_dot(ng, ds.wi) > 0.0f) & (p > 0.0f) & (p < INFINITY);
        shadow_lane_set(&s, k, o, ds.wi, p, ci, TZ_ENV_DISTANCE, ok);
    }
    for (int k = 0; v->any_dielectric && k < LANES; k++) s.want[k] &= !v->dielectric[k];
    if (TZ_HAS_TEXTURES_OF(scene)) lanes_emitter_maps(scene, v, slot, e, &s, &emission);
    trace_lanes(scene, &s.origin, &s.dir, v->id, s.t_light, s.want, 1, hint, blocked, t);
    int any_fold = 0;
    for (int k = 0; k < LANES; k++) {
        s.want[k] = s.want[k] & (blocked[k] < 0);
        x[k] = phong_lobe_cos(get3(&v->n, k), get3(&s.dir, k), get3(&v->wo, k));
        folds[k] = folds[k] & s.want[k];
        any_fold |= folds[k];
    }
    lobe_lanes(x, v->alpha, s.want, lobe);
    float b[LANES], f_scale[LANES];
    lanes3 f;
    for (int k = 0; k < LANES; k++) {
        b[k] = bsdf_pdf_of_lobe(v->share[k], v->alpha[k], s.cos_i[k], lobe[k]);
        set3(&f, k, bsdf_f_of_lobe(vertex_material(v, k), lobe[k]));
        f_scale[k] = s.cos_i[k];
    }
    if (any_fold) lanes_fold(v, folds, &s.dir, s.cos_i, &f, f_scale, b); /* emitter_light's */
    if (v->any_microfacet) lanes_microfacet_eval(v, s.want, &s.dir, &f, f_scale, b);
    int lights_only = (scene->frame.flags & TZ_FLAG_LIGHTS_ONLY) != 0u;
    float n_light = (float)scene->frame.light_samples;
    for (int k = 0; k < LANES; k++) {
        float weight =
            lights_only ? 1.0f / (n_light * s.pdf[k]) : light_mis_over_pdf(n_light, s.pdf[k], b[k]);
        vec3 l = v3_scale(v3_mul(get3(&f, k), get3(&emission, k)), f_scale[k] * weight);
        l = select3(s.want[k], l, v3(0.0f, 0.0f, 0.0f));
        vec3 dk = get3(direct, k);
        set3(direct, k, select3(v->diffuse[k], v3_add(dk, l), dk));
    }
    if (v->any_dielectric) lanes_dielectric_light(scene, v, ul, ua, ub, direct);
}

#endif
