/* integrator_path.c: path mode's integrator (DESIGN section 3.2) in C, one sample at a time: the
 * oracle of the shaders' path mode, drawing the same numbers in the same order. */
#include <math.h>

#include "render/cpu/integrator.h"
#include "render/cpu/integrator_steps.h"
#include "render/cpu/path_steps.h"
#include "render/rng.h"

/* What the last non-specular vertex left for the MIS weight of emission found by its BSDF ray. */
typedef struct last_vertex {
    vec3 pos, n;
    int id;
    float bsdf_pdf;
} last_vertex;

/* The emitter record of sphere id, NULL when it emits nothing. */
static const struct gpu_emitter *emitter_of(const packed_scene *p, int id) {
    uint32_t slot = (uint32_t)p->spheres[id].params.w;
    return slot > 0 ? &p->emitters[slot - 1] : NULL;
}

/* Whether area sampling (the point is inside emitter sphere e, or on it facing in) or cone sampling
 * serves a vertex at pos with facing normal n on sphere id; 0 when e cannot light it (on e,
 * facing out). */
enum { LIGHT_NONE, LIGHT_CONE, LIGHT_AREA };
static int light_strategy(vec3 pos, vec3 n, int id, int e_sphere, vec3 c, float r) {
    vec3 to_c = v3_sub(c, pos);
    if (id == e_sphere) return v3_dot(n, to_c) > 0.0f ? LIGHT_AREA : LIGHT_NONE;
    return v3_dot(to_c, to_c) > r * r ? LIGHT_CONE : LIGHT_AREA;
}

/* The solid-angle pdf (pick included) with which light sampling at the last vertex would have
 * chosen the point hit at pos on emitter sphere id, reached along d. */
static float light_pdf_at(const packed_scene *p, const last_vertex *v, int id, vec3 pos, vec3 d) {
    const struct gpu_emitter *e = emitter_of(p, id);
    const struct gpu_sphere *s = &p->spheres[id];
    vec3 c = xyz(s->center_radius);
    float r = s->center_radius.w;
    int strategy = light_strategy(v->pos, v->n, v->id, id, c, r);
    if (strategy == LIGHT_NONE) return 0.0f;
    if (strategy == LIGHT_CONE) {
        vec3 to_c = v3_sub(c, v->pos);
        float omc = cone_one_minus_cos(r * r, v3_dot(to_c, to_c));
        return e->emission_pick.w / (2.0f * TZ_PI * omc);
    }
    vec3 to_hit = v3_sub(pos, v->pos);
    vec3 nl = v3_scale(v3_sub(pos, c), 1.0f / r);
    return e->emission_pick.w * area_pdf(r, v3_dot(to_hit, to_hit), v3_dot(nl, d));
}

/* The first emitter whose cdf exceeds u (binary search; the last cdf is 1). */
static uint32_t pick_emitter(const packed_scene *p, float u) {
    uint32_t lo = 0, hi = p->emitter_count - 1;
    while (lo < hi) {
        uint32_t mid = (lo + hi) / 2;
        if (u < p->emitters[mid].sphere_cdf.y)
            hi = mid;
        else
            lo = mid + 1;
    }
    return lo;
}

/* The Phong BRDF of sphere s at the lobe cosine x. */
static vec3 brdf(const struct gpu_sphere *s, float x) {
    float ks = s->color_ks.w, alpha = s->params.x;
    float lobe = ks > 0.0f ? phong_lobe(x, alpha) : 0.0f;
    return phong_from_lobe(xyz(s->color_ks), ks, alpha, lobe);
}

/* Light from one emitter picked by ul and sampled by ua, ub at a diffuse vertex, MIS-weighted
 * against the BSDF (beta not applied). */
static vec3 emitter_light(const packed_scene *p, int id, vec3 pos, vec3 n, vec3 wo, float share,
                          float ul, float ua, float ub) {
    vec3 none = v3(0.0f, 0.0f, 0.0f);
    const struct gpu_emitter *e = &p->emitters[pick_emitter(p, ul)];
    int e_sphere = (int)uint_bits(e->sphere_cdf.x);
    const struct gpu_sphere *es = &p->spheres[e_sphere];
    vec3 c = xyz(es->center_radius);
    float r = es->center_radius.w, pick = e->emission_pick.w;
    int strategy = light_strategy(pos, n, id, e_sphere, c, r);
    if (strategy == LIGHT_NONE) return none;
    vec3 wi;
    float pdf;
    if (strategy == LIGHT_CONE) {
        vec3 to_c = v3_sub(c, pos);
        float d2 = v3_dot(to_c, to_c);
        direction_sample ds =
            cone_direction(v3_scale(to_c, 1.0f / sqrtf(d2)), cone_one_minus_cos(r * r, d2), ua, ub);
        wi = ds.wi;
        pdf = pick * ds.pdf;
    } else {
        vec3 q = v3_add(c, v3_scale(sphere_area_direction(ua, ub), r));
        vec3 to_q = v3_sub(q, pos);
        float dist2 = v3_dot(to_q, to_q);
        wi = v3_scale(to_q, 1.0f / sqrtf(dist2));
        pdf = pick * area_pdf(r, dist2, v3_dot(v3_scale(v3_sub(q, c), 1.0f / r), wi));
    }
    float cos_i = v3_dot(n, wi);
    if (!(cos_i > 0.0f) || !(pdf > 0.0f) || !(pdf < INFINITY)) return none;
    vec3 o = offset_origin(pos, n);
    float t_light = sphere_distance(c.x, c.y, c.z, r, o, wi, ray_eps(o), e_sphere == id);
    if (!(t_light < INFINITY) || integrator_occluded(p, o, wi, t_light, id)) return none;
    const struct gpu_sphere *s = &p->spheres[id];
    float x = phong_lobe_cos(n, wi, wo);
    float b = bsdf_pdf(share, s->params.x, cos_i, x);
    /* the MIS weight over the pdf, or 1 / pdf with light sampling alone */
    float weight = p->frame.settings.z & TZ_FLAG_LIGHTS_ONLY ? 1.0f / pdf : pdf / (pdf * pdf + b * b);
    return v3_scale(v3_mul(brdf(s, x), xyz(e->emission_pick)), cos_i * weight);
}

/* Point lights at a diffuse vertex, as seed mode's direct light (beta not applied). */
static vec3 point_lights(const packed_scene *p, int id, vec3 pos, vec3 n, vec3 wo) {
    vec3 o = offset_origin(pos, n), sum = v3(0.0f, 0.0f, 0.0f);
    const struct gpu_sphere *s = &p->spheres[id];
    for (uint32_t k = 0; k < p->frame.size.w; k++) {
        vec3 wi;
        float dist, cos_i;
        vec3 light = point_light(&p->lights[k], pos, n, &wi, &dist, &cos_i);
        if (cos_i <= 0.0f || integrator_occluded(p, o, wi, dist, id)) continue;
        sum = v3_add(sum, v3_mul(brdf(s, phong_lobe_cos(n, wi, wo)), light));
    }
    return sum;
}

vec3 integrator_path_sample(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index) {
    const struct gpu_frame *fr = &p->frame;
    uint32_t rng = rng_seed(fr->settings.x, j * fr->size.x + i, sample_index);
    float u = rng_next(&rng), v = rng_next(&rng);
    if (!(fr->settings.z & TZ_FLAG_JITTER)) u = v = 0.5f;
    vec3 d = camera_direction(fr, i, j, u, v);
    vec3 o = v3_add(xyz(fr->origin), v3_scale(d, fr->background.w));
    vec3 beta = v3(1.0f, 1.0f, 1.0f), radiance = v3(0.0f, 0.0f, 0.0f);
    uint32_t bounces = fr->settings.y;
    int self = -1, specular = 1;
    last_vertex last = {0};
    for (uint32_t k = 1;; k++) {
        float t;
        int id = integrator_nearest(p, o, d, self, &t);
        if (id < 0) {
            radiance = v3_add(radiance, v3_mul(beta, xyz(fr->background)));
            break;
        }
        const struct gpu_sphere *s = &p->spheres[id];
        vec3 pos = v3_add(o, v3_scale(d, t));
        vec3 nout = v3_scale(v3_sub(pos, xyz(s->center_radius)), 1.0f / s->center_radius.w);
        const struct gpu_emitter *e = emitter_of(p, id);
        if (e) {
            float w = specular || (fr->settings.z & TZ_FLAG_BSDF_ONLY) ? 1.0f
                      : fr->settings.z & TZ_FLAG_LIGHTS_ONLY
                          ? 0.0f
                          : power_heuristic(last.bsdf_pdf, light_pdf_at(p, &last, id, pos, d));
            radiance = v3_add(radiance, v3_scale(v3_mul(beta, xyz(e->emission_pick)), w));
        }
        if (k > bounces) break;
        int material = (int)s->params.z;
        if (material == TZ_MATERIAL_LAMBERTIAN || material == TZ_MATERIAL_PHONG) {
            vec3 n = facing_normal(nout, d), wo = v3_scale(d, -1.0f);
            float share = diffuse_share(xyz(s->color_ks), s->color_ks.w);
            vec3 direct = point_lights(p, id, pos, n, wo);
            if (p->emitter_count > 0) {
                float ul = rng_next(&rng), ua = rng_next(&rng), ub = rng_next(&rng);
                if (!(fr->settings.z & TZ_FLAG_BSDF_ONLY))
                    direct = v3_add(direct, emitter_light(p, id, pos, n, wo, share, ul, ua, ub));
            }
            radiance = v3_add(radiance, v3_mul(beta, direct));
            float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
            if (share < 0.0f) break;
            vec3 wi;
            if (us < share) {
                float phi = 2.0f * TZ_PI * u2;
                wi = cosine_direction(n, u1, cosf(phi), sinf(phi));
            } else {
                vec3 wr = v3_sub(v3_scale(n, 2.0f * v3_dot(n, wo)), wo);
                wi = phong_lobe_direction(wr, s->params.x, u1, u2);
            }
            float cos_i = v3_dot(n, wi), x = phong_lobe_cos(n, wi, wo);
            float pdf = bsdf_pdf(share, s->params.x, cos_i, x);
            if (!(cos_i > 0.0f) || !(pdf > 0.0f)) break;
            beta = v3_mul(beta, v3_scale(brdf(s, x), cos_i / pdf));
            last = (last_vertex){pos, n, id, pdf};
            specular = 0;
            o = offset_origin(pos, n);
            d = wi;
        } else {
            int refractive = material == TZ_MATERIAL_REFRACTIVE;
            int reflect = !refractive;
            if (refractive) {
                float uf = rng_next(&rng);
                int entering = v3_dot(d, nout) < 0.0f;
                float ior = s->params.y, eta = entering ? 1.0f / ior : ior;
                float c1 = entering ? -v3_dot(d, nout) : v3_dot(d, nout);
                float kk = 1.0f - eta * eta * (1.0f - c1 * c1);
                reflect = uf < fresnel_dielectric(eta, c1, kk);
            }
            beta = v3_mul(beta, xyz(s->color_ks));
            specular_next(pos, nout, d, refractive && !reflect, s->params.y, &o, &d);
            specular = 1;
        }
        self = id;
        if (k >= 4 && (fr->settings.z & TZ_FLAG_ROULETTE)) {
            float q = beta.x > beta.y ? beta.x : beta.y;
            q = q > beta.z ? q : beta.z;
            q = q < 1.0f ? q : 1.0f;
            if (rng_next(&rng) >= q) break;
            beta = v3_scale(beta, 1.0f / q);
        }
    }
    return radiance;
}
