/* integrator_packet.c: the C integrator over a packet of PACKET_LANES samples at once (the same
 * sample of a run of pixels in one row). Each lane does the very operations of integrator.c,
 * through the shared steps of shaders/common/, so the images are bit-identical to it (tested);
 * the loops over lanes compile to SIMD, the lanes' diverging paths become selects. */
#include <math.h>
#include <string.h>

#include "render/cpu/scene_accessors.h"

/* The shared text calls the accessors above. */
#include "common/bsdf.h"
#include "common/camera.h"
#include "common/emitter.h"
#include "common/primitive.h"
#include "common/ray.h"
#include "common/shade.h"
#include "render/cpu/integrator.h"

/* Built once per vector level (CMakeLists.txt): PACKET_LANES lanes, the entry point named
 * integrator_sample_packet_<PACKET_BUILD>; src/render/cpu/integrator_dispatch.c picks one at run
 * time. */
#ifndef PACKET_LANES
#define PACKET_LANES 8
#define PACKET_BUILD baseline
#endif
#define LANES PACKET_LANES
#define PACKET_ENTRY_NAME(build) integrator_sample_packet_##build
#define PACKET_ENTRY(build) PACKET_ENTRY_NAME(build)

#include "render/cpu/packet_trace.h"
#include "render/cpu/sampler_lanes.h"

/* The material of each lane's diffuse hit, gathered once for all the BRDF evaluations there. */
typedef struct phong_lanes {
    lanes3 kd;
    float ks[LANES], alpha[LANES], ior[LANES];
    int material[LANES];
} phong_lanes;

/* Lane k's material of m (bsdf.h's). */
LANE_FN bsdf_material phong_lane(const phong_lanes *m, int k) {
    bsdf_material b;
    b.kind = m->material[k];
    b.color = get3(&m->kd, k);
    b.ks = m->ks[k];
    b.alpha = m->alpha[k];
    b.ior = m->ior[k];
    return b;
}

/* Where the lanes' rays meet primitives id[k] at t[k] (surface_at, sphere 0's surface where
 * none): pos, nout, shading and the material's tint (kd), ks, alpha, ior and kind. */
typedef struct hit_lanes {
    lanes3 pos, nout, shading, kd;
    float ks[LANES], alpha[LANES], ior[LANES];
    int material[LANES];
} hit_lanes;

LANE_FN void packet_surfaces(const packed_scene *p, const lanes3 *o, const lanes3 *d, const int *id,
                             const float *t, hit_lanes *h) {
    int triangle[LANES];
    for (int k = 0; k < LANES; k++) { /* spheres, in SIMD */
        triangle[k] = id[k] >= 0 && is_triangle(p, id[k]);
        int sk = id[k] >= 0 && !triangle[k] ? id[k] : 0;
        const struct gpu_sphere *s = &p->spheres[sk];
        tz_vec4 color_ks = sphere_color_ks(p, sk), params = sphere_params(p, sk);
        vec3 pk = ray_point(get3(o, k), get3(d, k), t[k]);
        vec3 nk = sphere_normal(xyz(s->center_radius), s->center_radius.w, pk);
        set3(&h->pos, k, pk);
        set3(&h->nout, k, nk);
        set3(&h->shading, k, nk);
        set3(&h->kd, k, xyz(color_ks));
        h->ks[k] = color_ks.w;
        h->alpha[k] = params.x;
        h->ior[k] = params.y;
        h->material[k] = (int)params.z;
    }
    for (int k = 0; TZ_HAS_TEXTURES_OF(p) && k < LANES; k++) { /* textured spheres: surface_at's */
        if (id[k] < 0 || triangle[k]) continue;
        surface sf = {.pos = get3(&h->pos, k),
                      .nout = get3(&h->nout, k),
                      .shading = get3(&h->shading, k),
                      .m = {.kind = h->material[k],
                            .color = get3(&h->kd, k),
                            .ks = h->ks[k],
                            .alpha = h->alpha[k],
                            .ior = h->ior[k]}};
        sf = sphere_textured(p, id[k], sf);
        set3(&h->shading, k, sf.shading);
        set3(&h->kd, k, sf.m.color);
        h->ks[k] = sf.m.ks;
        h->alpha[k] = sf.m.alpha;
    }
    for (int k = 0; any_lane(triangle) && k < LANES; k++) { /* triangles, lane by lane */
        if (!triangle[k]) continue;
        surface sf = triangle_surface(p, id[k], get3(&h->pos, k), get3(o, k), get3(d, k));
        set3(&h->pos, k, sf.pos);
        set3(&h->nout, k, sf.nout);
        set3(&h->shading, k, sf.shading);
        set3(&h->kd, k, sf.m.color);
        h->ks[k] = sf.m.ks;
        h->alpha[k] = sf.m.alpha;
        h->ior[k] = sf.m.ior;
        h->material[k] = sf.m.kind;
    }
}

/* A packet's rays followed through mirrors and glass (follow_specular of report.h, lane by
 * lane): result[k] the diffuse primitive reached, -1 on a miss, -2 past the bounce limit (-1 for
 * inactive lanes); o, d become the last rays, weight the tints, pos the diffuse hits, n and ng
 * their shading and geometric normals facing the ray, m their materials. */
LANE_FN void packet_follow_specular(const packed_scene *p, lanes3 *o, lanes3 *d, int *self,
                                    const int *active_in, lanes3 *weight, lanes3 *pos, lanes3 *n,
                                    lanes3 *ng, phong_lanes *m, int *result) {
    uint32_t bounces = p->frame.bounces;
    int active[LANES];
    float tmax[LANES];
    for (int k = 0; k < LANES; k++) {
        active[k] = active_in[k];
        tmax[k] = INFINITY;
        result[k] = -1;
        set3(pos, k, v3(0.0f, 0.0f, 0.0f));
        set3(n, k, v3(0.0f, 0.0f, 0.0f));
        set3(ng, k, v3(0.0f, 0.0f, 0.0f));
        set3(&m->kd, k, v3(0.0f, 0.0f, 0.0f));
        m->ks[k] = m->alpha[k] = 0.0f;
        m->ior[k] = 1.0f;
        m->material[k] = TZ_MATERIAL_LAMBERTIAN;
    }
    for (uint32_t chain = 0; any_lane(active); chain++) {
        int id[LANES];
        float t[LANES];
        hit_lanes h;
        packet_trace(p, o, d, self, tmax, active, 0, NULL, id, t);
        packet_surfaces(p, o, d, id, t, &h);
        int onward[LANES];
        for (int k = 0; k < LANES; k++) {
            vec3 dk = get3(d, k), nk = get3(&h.nout, k), sk = get3(&h.shading, k);
            int hit = active[k] & (id[k] >= 0);
            int diffuse = hit & !bsdf_is_delta(h.material[k]);
            onward[k] = hit & !diffuse & (chain != bounces);
            int done = active[k] & !onward[k];
            result[k] = done ? (diffuse ? id[k] : hit ? -2 : -1) : result[k];
            set3(pos, k, select3(diffuse, get3(&h.pos, k), get3(pos, k)));
            /* facing_shading of primitive.h */
            vec3 facing = select3(v3_dot(nk, dk) < 0.0f, sk, v3_scale(sk, -1.0f));
            set3(n, k, select3(diffuse, facing, get3(n, k)));
            set3(ng, k, select3(diffuse, facing_normal(nk, dk), get3(ng, k)));
            set3(&m->kd, k, select3(diffuse, get3(&h.kd, k), get3(&m->kd, k)));
            m->ks[k] = diffuse ? h.ks[k] : m->ks[k];
            m->alpha[k] = diffuse ? h.alpha[k] : m->alpha[k];
            m->ior[k] = diffuse ? bsdf_eta(h.material[k], h.ior[k], nk, dk) : m->ior[k];
            m->material[k] = diffuse ? h.material[k] : m->material[k];
        }
        for (int k = 0; k < LANES; k++) { /* mirror and glass lanes go on */
            vec3 nk = get3(&h.nout, k), dk = get3(d, k);
            next_ray next =
                specular_next(get3(&h.pos, k), nk, specular_normal(nk, get3(&h.shading, k), dk), dk,
                              bsdf_refracts(h.material[k]), h.ior[k]);
            set3(weight, k,
                 select3(onward[k], v3_mul(get3(weight, k), get3(&h.kd, k)), get3(weight, k)));
            set3(o, k, select3(onward[k], next.o, get3(o, k)));
            set3(d, k, select3(onward[k], next.d, get3(d, k)));
            self[k] = onward[k] ? id[k] : self[k];
            active[k] = onward[k];
        }
    }
}

/* The BRDF per lane (bsdf_f of bsdf.h, its pow lane by lane where ks > 0; a microfacet lane's
 * bsdf_f itself). */
LANE_FN void packet_phong(const phong_lanes *m, const lanes3 *n, const lanes3 *wi, const lanes3 *wo,
                          const int *active, lanes3 *f) {
    float x[LANES], lobe[LANES];
    int microfacet[LANES];
    for (int k = 0; k < LANES; k++) x[k] = phong_lobe_cos(get3(n, k), get3(wi, k), get3(wo, k));
    for (int k = 0; k < LANES; k++) {
        microfacet[k] = active[k] & is_microfacet(m->material[k]);
        lobe[k] =
            active[k] && !microfacet[k] && m->ks[k] > 0.0f ? phong_lobe(x[k], m->alpha[k]) : 0.0f;
    }
    for (int k = 0; k < LANES; k++) set3(f, k, bsdf_f_of_lobe(phong_lane(m, k), lobe[k]));
    for (int k = 0; any_lane(microfacet) && k < LANES; k++)
        if (microfacet[k])
            set3(f, k, bsdf_f(phong_lane(m, k), get3(n, k), get3(wi, k), get3(wo, k)));
}

/* The lanes whose path reached a diffuse hit (id[k] >= 0), and wo, the way back along their last
 * rays d. */
LANE_FN void packet_diffuse_hits(const int *active, const int *id, const lanes3 *d, int *diffuse,
                                 lanes3 *wo) {
    for (int k = 0; k < LANES; k++) {
        diffuse[k] = active[k] & (id[k] >= 0);
        set3(wo, k, v3_scale(get3(d, k), -1.0f));
    }
}

/* What a path ending as id along d brings back: its weight times the environment on a miss
 * (-1), black past the bounce limit (-2), else its weight times the light found at its diffuse
 * hit. */
LANE_FN vec3 path_radiance(const packed_scene *p, int id, vec3 d, vec3 weight, vec3 found) {
    vec3 lit = id == -1 ? v3_mul(weight, environment_radiance(p, d)) : v3_mul(weight, found);
    return id == -2 ? v3(0.0f, 0.0f, 0.0f) : lit;
}

/* Direct light from every point light at the active lanes' diffuse hits (point_lights of
 * lights.h, lane by lane) into sum. */
LANE_FN void packet_direct_light(const packed_scene *p, const int *id, const lanes3 *pos,
                                 const lanes3 *n, const lanes3 *ng, const phong_lanes *m,
                                 const lanes3 *wo, const int *active, lanes3 *sum) {
    lanes3 o;
    for (int k = 0; k < LANES; k++) set3(sum, k, v3(0.0f, 0.0f, 0.0f));
    for (uint32_t l = 0; l < p->frame.light_count; l++) {
        lanes3 wi, light, f;
        float dist[LANES];
        int facing[LANES], blocker[LANES];
        float blocker_t[LANES];
        tz_vec4 position_power = p->lights[l].position_power, color = p->lights[l].color;
        tz_vec4 shape = p->lights[l].shape;
        for (int k = 0; k < LANES; k++) {
            light_sample ls = point_light(position_power, color, shape, get3(pos, k), get3(n, k));
            vec3 ngk = get3(ng, k);
            set3(&light, k, select3(ls.cos_i < 0.0f, v3_scale(ls.radiance, -1.0f), ls.radiance));
            set3(&wi, k, ls.wi);
            set3(&o, k, bsdf_next_origin(get3(pos, k), ngk, ls.wi));
            dist[k] = ls.dist;
            facing[k] = active[k] & point_light_reaches(m->material[k], ls.cos_i, ngk, ls.wi);
        }
        if (!any_lane(facing)) continue;
        packet_trace(p, &o, &wi, id, dist, facing, 1, NULL, blocker, blocker_t);
        packet_phong(m, n, &wi, wo, facing, &f);
        for (int k = 0; k < LANES; k++) {
            int lit = facing[k] & (blocker[k] < 0);
            vec3 s = get3(sum, k);
            set3(sum, k, select3(lit, v3_add(s, v3_mul(get3(&f, k), get3(&light, k))), s));
        }
    }
}

/* Radiance arriving along the active lanes' rays (follow_specular, then chain_direct: report.h). */
LANE_FN void packet_radiance_direct_only(const packed_scene *p, lanes3 *o, lanes3 *d, int *self,
                                         const int *active, lanes3 *radiance) {
    lanes3 weight, pos, n, ng, wo, direct;
    phong_lanes m;
    int id[LANES];
    for (int k = 0; k < LANES; k++) set3(&weight, k, v3(1.0f, 1.0f, 1.0f));
    packet_follow_specular(p, o, d, self, active, &weight, &pos, &n, &ng, &m, id);
    int diffuse[LANES];
    packet_diffuse_hits(active, id, d, diffuse, &wo);
    packet_direct_light(p, id, &pos, &n, &ng, &m, &wo, diffuse, &direct);
    for (int k = 0; k < LANES; k++)
        set3(radiance, k, path_radiance(p, id[k], get3(d, k), get3(&weight, k), get3(&direct, k)));
}

/* One cosine-weighted bounce at the active lanes' diffuse hits (indirect_light of report.h),
 * added to radiance. */
LANE_FN void packet_indirect_light(const packed_scene *p, const int *id, const lanes3 *pos,
                                   const lanes3 *n, const lanes3 *ng, const phong_lanes *m,
                                   const lanes3 *wo, const int *active_in, sampler_lanes *rng,
                                   lanes3 *radiance) {
    float y1[LANES], y2[LANES], cos_t[LANES];
    /* the sample's last draw, so lanes not drawing (their results unused) change nothing */
    draw_lanes_2d(p->frame.flags, rng, active_in, y1, y2);
    for (int k = 0; k < LANES; k++) cos_t[k] = sqrtf(1.0f - y1[k]);
    lanes3 o, wi, incoming, f;
    int self[LANES], active[LANES];
    for (int k = 0; k < LANES; k++) {
        vec3 nk = get3(n, k), ngk = get3(ng, k), pk = get3(pos, k);
        vec3 w = cosine_direction(nk, y1[k], y2[k]);
        set3(&wi, k, w);
        set3(&o, k, offset_origin(pk, ngk));
        self[k] = id[k];
        /* nothing below a triangle's face (its shading normal leaning away) */
        int below = (id[k] >= 0 && is_triangle(p, id[k])) & !(v3_dot(ngk, w) > 0.0f);
        active[k] = active_in[k] & !below;
    }
    packet_phong(m, n, &wi, wo, active, &f); /* before the walk below turns wi into its last ray */
    packet_radiance_direct_only(p, &o, &wi, self, active, &incoming);
    for (int k = 0; k < LANES; k++) {
        float pdf = cos_t[k] / TZ_PI;
        vec3 light = v3_mul(get3(&f, k), v3_scale(get3(&incoming, k), cos_t[k] / pdf));
        vec3 r = get3(radiance, k);
        set3(radiance, k, select3(active[k], v3_add(r, light), r));
    }
}

/* The packet_integrator sample function of this build (integrator.h). */
void PACKET_ENTRY(PACKET_BUILD)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                uint32_t sample_index, vec3 *out);

void PACKET_ENTRY(PACKET_BUILD)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t lanes,
                                uint32_t sample_index, vec3 *out) {
    const struct gpu_frame *fr = &p->frame;
    sampler_lanes rng;
    int active[LANES], self[LANES], id[LANES];
    lanes3 o, d, weight, pos, n, ng, wo, radiance;
    phong_lanes m;
    /* Copied once, here: read through fr in the loop, gcc copied them for every lane
     * (docs/PERF.md). */
    tz_vec4 right = fr->right, up = fr->up, forward = fr->forward;
    tz_vec4 origin = fr->origin, lens = fr->lens;
    float near_distance = fr->near_distance;
    for (int k = 0; k < LANES; k++) {
        active[k] = (uint32_t)k < lanes;
        sampler_state one =
            sampler_start(fr->flags, fr->seed, j * fr->width + i + (uint32_t)k, sample_index);
        camera_numbers c = camera_draw(fr->flags, &one);
        lane_sampler_set(&rng, k, 1, one);
        next_ray ray = camera_ray_through(fr->flags, origin, right, up, forward, near_distance,
                                          lens, i + (uint32_t)k, j, c);
        set3(&d, k, ray.d);
        set3(&o, k, ray.o);
        set3(&weight, k, v3(1.0f, 1.0f, 1.0f));
        self[k] = -1;
    }
    packet_follow_specular(p, &o, &d, self, active, &weight, &pos, &n, &ng, &m, id);
    int diffuse[LANES];
    packet_diffuse_hits(active, id, &d, diffuse, &wo);
    packet_direct_light(p, id, &pos, &n, &ng, &m, &wo, diffuse, &radiance);
    if (fr->flags & TZ_FLAG_INDIRECT)
        packet_indirect_light(p, id, &pos, &n, &ng, &m, &wo, diffuse, &rng, &radiance);
    for (int k = 0; k < LANES; k++)
        out[k] = path_radiance(p, id[k], get3(&d, k), get3(&weight, k), get3(&radiance, k));
}
