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
 * integrator_path_packet_<PACKET_BUILD>; src/render/cpu/integrator_dispatch.c picks one. */
#ifndef PACKET_LANES
#define PACKET_LANES 8
#define PACKET_BUILD baseline
#endif
#define LANES PACKET_LANES
#define PATH_ENTRY_NAME(build) integrator_path_packet_##build
#define PATH_ENTRY(build) PATH_ENTRY_NAME(build)
#define PATH_RUN_NAME(build) integrator_path_samples_##build
#define PATH_RUN(build) PATH_RUN_NAME(build)

#include "render/cpu/packet_trace.h"
#include "render/cpu/path_vertex_lanes.h"
#include "render/cpu/sampler_lanes.h"

/* The state of the lanes' paths (the locals of path_sample). */
typedef struct path_lanes {
    sampler_lanes rng;
    uint32_t vertex[LANES]; /* path_sample's k */
    int job[LANES];         /* the sample the lane runs (out's index), -1 none */
    int active[LANES], self[LANES], specular[LANES], last_id[LANES];
    uint32_t blocker; /* the sphere that last blocked every shadow ray of the lanes */
    float last_pdf[LANES];
    lanes3 o, d, beta, radiance, last_pos, last_n, last_origin;
} path_lanes;

/* bsdf_sample_lobe's direction and terms for the microfacet lanes in go (the Phong ones the other
 * lanes computed): wi, cos_i, fv, f_scale and pdf as lanes_bsdf_bounce's; their lobes do not
 * fold (folds cleared). */
static __attribute__((noinline)) void lanes_microfacet_sample(
    const vertex_lanes *v, const int *go, const float *us, const float *u1, const float *u2,
    lanes3 *wi, float *cos_i, lanes3 *fv, float *f_scale, float *pdf, int *folds) {
    for (int k = 0; k < LANES; k++) {
        if (!(go[k] & v->microfacet[k])) continue;
        bsdf_material m = vertex_material(v, k);
        vec3 n = get3(&v->n, k), wo = get3(&v->wo, k);
        vec3 w = microfacet_direction(m, n, wo, us[k], u1[k], u2[k]);
        bsdf_value bv = microfacet_eval(m, n, w, wo);
        set3(wi, k, w);
        cos_i[k] = bv.cos_i;
        set3(fv, k, bv.f);
        f_scale[k] = bv.f_scale;
        pdf[k] = bv.pdf;
        folds[k] = 0;
    }
}

/* The lanes' next rays at diffuse vertices: the BSDF's sample, beta and the last vertex updated;
 * lanes whose path ends here are made inactive. */
LANE_FN void lanes_bsdf_bounce(const vertex_lanes *v, path_lanes *s, const float *us,
                               const float *u1, const float *u2) {
    float cos_i[LANES], x[LANES], lobe[LANES], pdf[LANES], f_scale[LANES];
    int cosine[LANES], go[LANES], folds[LANES], any_lobe = 0, any_fold = 0;
    lanes3 lobe_wi, wi, fv;
    for (int k = 0; k < LANES; k++) {
        go[k] = v->diffuse[k] & !(v->share[k] < 0.0f);
        cosine[k] = us[k] < v->share[k];
        any_lobe |= go[k] & !cosine[k];
        set3(&lobe_wi, k, v3(0.0f, 0.0f, 0.0f));
        folds[k] = go[k] & folds_at(get3(&v->n, k), get3(&v->ng, k));
        any_fold |= folds[k];
    }
    for (int k = 0; any_lobe && k < LANES; k++) {
        vec3 n = get3(&v->n, k), wo = get3(&v->wo, k);
        set3(&lobe_wi, k, phong_lobe_direction(phong_lobe_axis(n, wo), v->alpha[k], u1[k], u2[k]));
    }
    for (int k = 0; k < LANES; k++) {
        vec3 n = get3(&v->n, k);
        set3(&wi, k, select3(cosine[k], cosine_direction(n, u1[k], u2[k]), get3(&lobe_wi, k)));
    }
    for (int k = 0; any_fold && k < LANES; k++) { /* path_sample's fold below a smooth face */
        vec3 w = get3(&wi, k), ng = get3(&v->ng, k);
        if (folds[k] && !(v3_dot(ng, w) > 0.0f)) set3(&wi, k, mirror_in_plane(w, ng));
    }
    for (int k = 0; k < LANES; k++) {
        vec3 n = get3(&v->n, k), wo = get3(&v->wo, k), w = get3(&wi, k);
        cos_i[k] = v3_dot(n, w);
        x[k] = phong_lobe_cos(n, w, wo);
    }
    lobe_lanes(x, v->alpha, go, lobe);
    for (int k = 0; k < LANES; k++) {
        pdf[k] = bsdf_pdf_of_lobe(v->share[k], v->alpha[k], cos_i[k], lobe[k]);
        set3(&fv, k, bsdf_f_of_lobe(vertex_material(v, k), lobe[k]));
        f_scale[k] = cos_i[k];
    }
    if (any_fold) lanes_fold(v, folds, &wi, cos_i, &fv, f_scale, pdf);
    if (v->any_microfacet)
        lanes_microfacet_sample(v, go, us, u1, u2, &wi, cos_i, &fv, f_scale, pdf, folds);
    for (int k = 0; k < LANES; k++) {
        vec3 n = get3(&v->n, k), ng = get3(&v->ng, k), pos = get3(&v->pos, k);
        /* On a face that does not fold, a direction below it ends the path. */
        int ok = go[k] & bsdf_goes_on(v->material[k], folds[k], cos_i[k], ng, get3(&wi, k), pdf[k]);
        vec3 f = v3_scale(get3(&fv, k), f_scale[k] / pdf[k]);
        vec3 o = offset_origin(pos, ng), next_o = bsdf_next_origin(pos, ng, get3(&wi, k));
        set3(&s->beta, k, select3(ok, v3_mul(get3(&s->beta, k), f), get3(&s->beta, k)));
        set3(&s->last_pos, k, select3(ok, pos, get3(&s->last_pos, k)));
        set3(&s->last_n, k, select3(ok, n, get3(&s->last_n, k)));
        set3(&s->last_origin, k, select3(ok, o, get3(&s->last_origin, k)));
        s->last_id[k] = ok ? v->id[k] : s->last_id[k];
        s->last_pdf[k] = ok ? pdf[k] : s->last_pdf[k];
        s->specular[k] = ok ? 0 : s->specular[k];
        set3(&s->o, k, select3(ok, next_o, get3(&s->o, k)));
        set3(&s->d, k, select3(ok, get3(&wi, k), get3(&s->d, k)));
        s->active[k] = v->diffuse[k] ? ok : s->active[k];
    }
}

/* The lanes' next rays at mirror and glass vertices (glass draws its Fresnel number). */
LANE_FN void lanes_specular_bounce(uint32_t flags, const vertex_lanes *v, path_lanes *s) {
    int refractive[LANES];
    float uf[LANES];
    for (int k = 0; k < LANES; k++) refractive[k] = v->specular[k] & bsdf_refracts(v->material[k]);
    draw_lanes_1d(flags, &s->rng, refractive, uf);
    for (int k = 0; k < LANES; k++) {
        vec3 d = get3(&s->d, k), nout = get3(&v->nout, k);
        vec3 n = specular_normal(nout, get3(&v->shading, k), d);
        bsdf_material m = vertex_material(v, k);
        int transmits = bsdf_delta_transmits(m, d, nout, n, uf[k]);
        int on = v->specular[k];
        vec3 beta = get3(&s->beta, k);
        set3(&s->beta, k, select3(on, v3_mul(beta, m.color), beta));
        next_ray next = specular_next(get3(&v->pos, k), nout, n, d, transmits, m.ior);
        set3(&s->o, k, select3(on, next.o, get3(&s->o, k)));
        set3(&s->d, k, select3(on, next.d, d));
        s->specular[k] = on ? 1 : s->specular[k];
    }
}

/* emitted_radiance of lane k's hit, its maps looked up: out of line, so that the texture lookup
 * does not weigh on the inlining of the lanes' code. */
static __attribute__((noinline)) vec3 lane_emitted(const packed_scene *scene, const vertex_lanes *v,
                                                   const path_lanes *s, int k) {
    return emitted_radiance(scene, v->slot[k], v->id[k], get3(&s->o, k), get3(&s->d, k),
                            get3(&v->pos, k));
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
                      : power_heuristic(last.bsdf_pdf,
                                        (float)scene->frame.light_samples *
                                            light_pdf_at(scene, last, v->id[k], get3(&v->pos, k),
                                                         get3(&s->d, k)));
        vec3 le = TZ_HAS_TEXTURES_OF(scene) ? lane_emitted(scene, v, s, k)
                                            : emitter_radiance(scene, v->slot[k]);
        vec3 emitted = v3_scale(v3_mul(get3(&s->beta, k), le), w);
        set3(&s->radiance, k, v3_add(get3(&s->radiance, k), emitted));
    }
}

/* The fields of a scene's spheres that a hit reads, one array each, where the scene has at most
 * SMALL_SPHERES of them: a hit's are then picked for all lanes by vector permutes, not loaded
 * lane by lane from the sphere array. */
#define SMALL_SPHERES (2 * LANES)
typedef struct small_spheres {
    float cx[SMALL_SPHERES], cy[SMALL_SPHERES], cz[SMALL_SPHERES], r[SMALL_SPHERES];
    float kr[SMALL_SPHERES], kg[SMALL_SPHERES], kb[SMALL_SPHERES], ks[SMALL_SPHERES];
    float alpha[SMALL_SPHERES], ior[SMALL_SPHERES], material[SMALL_SPHERES], slot[SMALL_SPHERES];
} small_spheres;

/* Fills t from the scene's spheres; false (t unused) when it has more than SMALL_SPHERES. */
LANE_FN int small_spheres_of(const packed_scene *scene, small_spheres *t) {
    uint32_t count = scene->frame.sphere_count;
    if (count > SMALL_SPHERES) return 0;
    memset(t, 0, sizeof *t);
    for (uint32_t k = 0; k < count; k++) {
        const struct gpu_sphere *g = &scene->spheres[k];
        tz_vec4 color_ks = sphere_color_ks(scene, (int)k), params = sphere_params(scene, (int)k);
        t->cx[k] = g->center_radius.x, t->cy[k] = g->center_radius.y;
        t->cz[k] = g->center_radius.z, t->r[k] = g->center_radius.w;
        t->kr[k] = color_ks.x, t->kg[k] = color_ks.y, t->kb[k] = color_ks.z;
        t->ks[k] = color_ks.w, t->alpha[k] = params.x, t->ior[k] = params.y;
        t->material[k] = params.z, t->slot[k] = params.w;
    }
    return 1;
}

/* out[k] = table[index[k]] for index[k] < SMALL_SPHERES: GCC's two-vector shuffle, a few
 * permutes (vpermps and a blend with AVX2, vpermt2ps with AVX-512). */
LANE_FN void lanes_pick(const float *table, const int *index, float *out) {
#if defined(__GNUC__) && !defined(__clang__)
    float_lanes low, high, picked;
    int_lanes i;
    memcpy(&low, table, sizeof low);
    memcpy(&high, table + LANES, sizeof high);
    memcpy(&i, index, sizeof i);
    picked = __builtin_shuffle(low, high, i);
    memcpy(out, &picked, sizeof picked);
#else
    for (int k = 0; k < LANES; k++) out[k] = table[index[k]];
#endif
}

/* The gather of lanes_vertex from a small_spheres table: sphere index[k]'s fields. */
LANE_FN void lanes_pick_spheres(const small_spheres *t, const int *index, vertex_lanes *v) {
    float material[LANES], slot[LANES];
    lanes_pick(t->cx, index, v->c.x);
    lanes_pick(t->cy, index, v->c.y);
    lanes_pick(t->cz, index, v->c.z);
    lanes_pick(t->r, index, v->r);
    lanes_pick(t->kr, index, v->kd.x);
    lanes_pick(t->kg, index, v->kd.y);
    lanes_pick(t->kb, index, v->kd.z);
    lanes_pick(t->ks, index, v->ks);
    lanes_pick(t->alpha, index, v->alpha);
    lanes_pick(t->ior, index, v->ior);
    lanes_pick(t->material, index, material);
    lanes_pick(t->slot, index, slot);
    for (int k = 0; k < LANES; k++) {
        v->material[k] = (int)material[k];
        v->slot[k] = (int)slot[k] - 1;
    }
}

/* What the lanes in miss, whose rays left the scene, see there: the environment (with its MIS
 * weight) and the sun's disc, times beta, added to their radiance. Apart from the vertex's loop,
 * which most packets run with no lane missing. */
static __attribute__((noinline)) void lanes_environment(const packed_scene *scene, const int *miss,
                                                        path_lanes *s) {
    lanes3 rgb;
    float light_pdf[LANES];
    lanes_environment_look(scene, &s->d, &rgb, light_pdf);
    for (int k = 0; k < LANES; k++) {
        vec3 radiance = get3(&s->radiance, k), d = get3(&s->d, k);
        float w = environment_mis_weight(scene, s->specular[k], s->last_pdf[k], light_pdf[k]);
        vec3 seen = v3_scale(v3_mul(get3(&s->beta, k), get3(&rgb, k)), w);
        vec3 with_sun = v3_add(radiance, seen);
        if (scene->frame.flags & TZ_FLAG_SUN_DISC)
            with_sun = v3_add(with_sun, v3_mul(get3(&s->beta, k),
                                               sun_seen(scene, s->specular[k], s->last_pdf[k], d)));
        set3(&s->radiance, k, select3(miss[k], with_sun, radiance));
    }
}

/* One vertex of every active lane's path (an iteration of path_sample's loop); small the
 * scene's small_spheres table, or NULL. */
LANE_FN void lanes_vertex(const packed_scene *scene, const small_spheres *small, path_lanes *s) {
    const struct gpu_frame *fr = &scene->frame;
    uint32_t flags = fr->flags;
    vertex_lanes v;
    float tmax[LANES];
    int emit[LANES], any_emit = 0;
    for (int k = 0; k < LANES; k++) tmax[k] = INFINITY;
    trace_lanes(scene, &s->o, &s->d, s->self, tmax, s->active, 0, NULL, v.id, v.t);
    int triangle[LANES];
    for (int k = 0; k < LANES; k++) triangle[k] = v.id[k] >= 0 && is_triangle(scene, v.id[k]);
    if (small) {
        int index[LANES];
        for (int k = 0; k < LANES; k++) index[k] = v.id[k] >= 0 && !triangle[k] ? v.id[k] : 0;
        lanes_pick_spheres(small, index, &v);
    }
    for (int k = 0; !small && k < LANES; k++) { /* gather the hit spheres */
        int sk = v.id[k] >= 0 && !triangle[k] ? v.id[k] : 0;
        const struct gpu_sphere *g = &scene->spheres[sk];
        tz_vec4 color_ks = sphere_color_ks(scene, sk), params = sphere_params(scene, sk);
        set3(&v.c, k, xyz(g->center_radius));
        v.r[k] = g->center_radius.w;
        set3(&v.kd, k, xyz(color_ks));
        v.ks[k] = color_ks.w;
        v.alpha[k] = params.x;
        v.ior[k] = params.y;
        v.material[k] = (int)params.z;
        v.slot[k] = (int)params.w - 1;
    }
    for (int k = 0; k < LANES; k++) { /* surface_at of a sphere */
        vec3 pos = ray_point(get3(&s->o, k), get3(&s->d, k), v.t[k]);
        vec3 nout = sphere_normal(get3(&v.c, k), v.r[k], pos);
        set3(&v.pos, k, pos);
        set3(&v.nout, k, nout);
        set3(&v.shading, k, nout);
    }
    for (int k = 0; TZ_HAS_TEXTURES_OF(scene) && k < LANES; k++) { /* a textured sphere's */
        if (v.id[k] < 0 || triangle[k]) continue;
        surface sf = {.pos = get3(&v.pos, k),
                      .nout = get3(&v.nout, k),
                      .shading = get3(&v.shading, k),
                      .m = {.kind = v.material[k],
                            .color = get3(&v.kd, k),
                            .ks = v.ks[k],
                            .alpha = v.alpha[k],
                            .ior = v.ior[k]}};
        sf = sphere_textured(scene, v.id[k], sf);
        set3(&v.shading, k, sf.shading);
        set3(&v.kd, k, sf.m.color);
        v.ks[k] = sf.m.ks;
        v.alpha[k] = sf.m.alpha;
    }
    for (int k = 0; any_lane(triangle) && k < LANES; k++) { /* and of a triangle */
        if (!triangle[k]) continue;
        surface sf =
            triangle_surface(scene, v.id[k], get3(&v.pos, k), get3(&s->o, k), get3(&s->d, k));
        set3(&v.pos, k, sf.pos);
        set3(&v.nout, k, sf.nout);
        set3(&v.shading, k, sf.shading);
        set3(&v.kd, k, sf.m.color);
        v.ks[k] = sf.m.ks;
        v.alpha[k] = sf.m.alpha;
        v.ior[k] = sf.m.ior;
        v.material[k] = sf.m.kind;
        v.slot[k] = sf.emitter;
    }
    int miss[LANES], any_miss = 0;
    for (int k = 0; k < LANES; k++) {
        miss[k] = s->active[k] & (v.id[k] < 0);
        any_miss |= miss[k];
    }
    if (any_miss) lanes_environment(scene, miss, s);
    for (int k = 0; k < LANES; k++) {
        int hit = s->active[k] & (v.id[k] >= 0);
        vec3 d = get3(&s->d, k), nout = get3(&v.nout, k), shading = get3(&v.shading, k);
        emit[k] = hit & (v.slot[k] >= 0);
        any_emit |= emit[k];
        int go = hit & !(s->vertex[k] > fr->bounces); /* else the path ends at this hit */
        int diffuse = go & !bsdf_is_delta(v.material[k]);
        v.diffuse[k] = diffuse;
        v.ior[k] = bsdf_eta(v.material[k], v.ior[k], nout, d);
        v.dielectric[k] = diffuse & is_dielectric(v.material[k]);
        v.specular[k] = go & !diffuse;
        /* facing_shading and facing_normal of primitive.h and shade.h */
        set3(&v.n, k, select3(v3_dot(nout, d) < 0.0f, shading, v3_scale(shading, -1.0f)));
        set3(&v.ng, k, facing_normal(nout, d));
        set3(&v.wo, k, v3_scale(d, -1.0f));
        v.share[k] = bsdf_share(vertex_material(&v, k));
        v.microfacet[k] = diffuse & is_microfacet(v.material[k]);
        s->active[k] = go;
    }
    v.any_microfacet = any_lane(v.microfacet);
    v.any_dielectric = any_lane(v.dielectric);
    if (any_emit) lanes_emission(scene, &v, emit, s);
    if (any_lane(v.diffuse)) {
        lanes3 direct;
        lanes_point_lights(scene, &v, &direct);
        for (uint32_t l = 0; fr->emitter_count > 0u && l < fr->light_samples; l++) {
            float ul[LANES], ua[LANES], ub[LANES];
            draw_lanes_1d(flags, &s->rng, v.diffuse, ul);
            draw_lanes_2d(flags, &s->rng, v.diffuse, ua, ub);
            if ((flags & TZ_FLAG_BSDF_ONLY) == 0u)
                lanes_emitter_light(scene, &v, ul, ua, ub, &s->blocker, &direct);
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

/* The first rays of LANES consecutive samples of a run (path_start's costly part: the sampler's
 * start and the camera's draw and ray), made at once; a lane whose path ended then takes the
 * next one from it alone, so that a restart costs no vector pass of its own. */
typedef struct start_batch {
    sampler_lanes rng;
    lanes3 o, d;
} start_batch;

/* Fills b with samples first, first + 1, ... (first a multiple of LANES, slot n its sample
 * first + n) of the run over pixels (i + m % lanes, y), sample sample0 + m / lanes of each. */
LANE_FN void start_batch_make(const packed_scene *p, start_batch *b, uint32_t first, uint32_t i,
                              uint32_t y, uint32_t lanes, uint32_t sample0) {
    const struct gpu_frame fr = p->frame; /* a copy: the loop below then compiles to SIMD */
    uint32_t x[LANES], sample[LANES];
    for (int k = 0; k < LANES; k++) {
        x[k] = i + (first + (uint32_t)k) % lanes;
        sample[k] = sample0 + (first + (uint32_t)k) / lanes;
    }
    for (int k = 0; k < LANES; k++) {
        sampler_state rng = sampler_start(fr.flags, fr.seed, y * fr.width + x[k], sample[k]);
        camera_numbers c = camera_draw(fr.flags, &rng);
        next_ray ray = camera_ray_through(fr.flags, fr.origin, fr.right, fr.up, fr.forward,
                                          fr.near_distance, fr.lens, x[k], y, c);
        lane_sampler_set(&b->rng, k, 1, rng);
        set3(&b->o, k, ray.o);
        set3(&b->d, k, ray.d);
    }
}

/* Lane k begins the path of slot n of b (path_start). */
LANE_FN void lane_start(path_lanes *s, int k, const start_batch *b, int n) {
    vec3 o = get3(&b->o, n), d = get3(&b->d, n);
    lane_sampler_set(&s->rng, k, 1, lane_sampler(&b->rng, n));
    s->active[k] = 1;
    s->vertex[k] = 1u;
    set3(&s->o, k, o);
    set3(&s->d, k, d);
    set3(&s->beta, k, v3(1.0f, 1.0f, 1.0f));
    set3(&s->radiance, k, v3(0.0f, 0.0f, 0.0f));
    set3(&s->last_pos, k, o);
    set3(&s->last_n, k, d);
    set3(&s->last_origin, k, o);
    s->self[k] = -1;
    s->specular[k] = 1;
    s->last_id[k] = -1;
    s->last_pdf[k] = 0.0f;
}

/* Samples [first, first + count) of pixels (i + k, j), k < lanes, into out[s * lanes + k]: each
 * lane takes the next sample as soon as its path ends, so that the lanes stay busy. */
LANE_FN void run_samples(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                         uint32_t first, uint32_t count, vec3 *out) {
    path_lanes s;
    start_batch batch;
    small_spheres table;
    const small_spheres *small = small_spheres_of(p, &table) ? &table : NULL;
    memset(&s, 0, sizeof s);
    uint32_t next = 0, total = lanes * count;
    for (int k = 0; k < LANES; k++) s.job[k] = -1;
    for (;;) {
        for (int k = 0; k < LANES; k++) {
            if (s.active[k]) continue;
            if (s.job[k] >= 0) out[s.job[k]] = get3(&s.radiance, k);
            s.job[k] = -1;
            if (next < total) {
                if (next % LANES == 0u) start_batch_make(p, &batch, next, i, j, lanes, first);
                s.job[k] = (int)next;
                lane_start(&s, k, &batch, (int)(next % LANES));
                next++;
            }
        }
        if (!any_lane(s.active)) return;
        lanes_vertex(p, small, &s);
    }
}

/* The packet_integrator sample function of this build (integrator.h), for path mode. */
void PATH_ENTRY(PACKET_BUILD)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                              uint32_t sample_index, vec3 *out);

void PATH_ENTRY(PACKET_BUILD)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                              uint32_t sample_index, vec3 *out) {
    run_samples(p, i, j, lanes, sample_index, 1, out);
}

/* The packet_integrator samples function of this build (integrator.h). */
void PATH_RUN(PACKET_BUILD)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                            uint32_t first, uint32_t count, vec3 *out);

void PATH_RUN(PACKET_BUILD)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                            uint32_t first, uint32_t count, vec3 *out) {
    run_samples(p, i, j, lanes, first, count, out);
}
