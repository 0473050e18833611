/* bsdf.h: how a surface scatters light, one text for C and GLSL (dialect.h): the material a hit
 * reads (bsdf_material), the one switch of material kinds (bsdf_is_delta, bsdf_refracts), and the
 * BSDF's evaluation (bsdf_f, bsdf_eval), pdf (bsdf_pdf_at) and sampling (bsdf_sample_lobe,
 * bsdf_delta_transmits), through which report mode (report.h, lights.h) and path mode (path.h)
 * shade and which the CPU packet builds call lane by lane. A new material kind is a case here
 * and a row in the parser's table (src/scene/scene_material.c). */
#ifndef TRAZADOR_COMMON_BSDF_H
#define TRAZADOR_COMMON_BSDF_H

#include "dialect.h"
#include "dielectric.h"
#include "microfacet.h"
#include "sampling.h"
#include "shade.h"

/* Whether the microfacet kinds' code is live: where the flags are a specialization constant
 * (trace.comp) a scene without them compiles it out, as primitive.h does the triangles'. */
#ifdef GL_core_profile
#define TZ_MICROFACET_ON ((FLAGS & TZ_FLAG_MICROFACET) != 0u)
#else
#define TZ_MICROFACET_ON 1
#endif

/* A material as a hit reads it (struct gpu_material): kind TZ_MATERIAL_*, color the kd of a lobe,
 * the tint of a delta or a conductor, pbr's base colour, the Phong weight ks (0: Lambertian) or
 * pbr's metallic, alpha the Phong exponent or the GGX width (roughness^2) of the microfacet kinds,
 * the refractive index ior. A texture overrides these fields at the hit. */
TZ_STRUCT(bsdf_material) {
    int kind;
    vec3 color;
    float ks;
    float alpha;
    float ior;
}
TZ_STRUCT_END(bsdf_material)

/* The material of a gpu_material's first two vec4s as the accessors give them: color_ks, and
 * params (alpha, ior, kind). */
TZ_LANE_FN bsdf_material bsdf_material_of(TZ_VEC4 color_ks, TZ_VEC4 params) {
    bsdf_material m;
    m.kind = TZ_INT(params.z);
    m.color = xyz(color_ks);
    m.ks = color_ks.w;
    m.alpha = params.x;
    m.ior = params.y;
    return m;
}

/* The switch of material kinds. A delta (mirror, glass) scatters into one direction, which light
 * sampling cannot reach and report mode follows; lambertian and phong scatter by the Phong lobe
 * below (Lambertian is its ks 0), the microfacet kinds by microfacet.h's lobes. */
TZ_LANE_FN TZ_BOOL bsdf_is_delta(int kind) {
    return (kind == TZ_MATERIAL_MIRROR) TZ_OR(kind == TZ_MATERIAL_REFRACTIVE);
}
/* Whether a delta of kind refracts (glass) rather than mirrors. */
TZ_LANE_FN TZ_BOOL bsdf_refracts(int kind) { return kind == TZ_MATERIAL_REFRACTIVE; }

/* The BRDF of lobe material m given its lobe value (phong_lobe of the lobe cosine, unused where
 * ks is 0): kd / pi + ks (alpha + 2) / (2 pi) lobe. */
TZ_LANE_FN vec3 bsdf_f_of_lobe(bsdf_material m, float lobe) {
    return phong_from_lobe(m.color, m.ks, m.alpha, m.ks > 0.0f ? lobe : 0.0f);
}

/* The BRDF of lobe material m at the lobe cosine x (phong_lobe_cos); pow only where ks > 0. */
TZ_FN vec3 bsdf_f_at(bsdf_material m, float x) {
    float lobe = m.ks > 0.0f ? phong_lobe(x, m.alpha) : 0.0f;
    return bsdf_f_of_lobe(m, lobe);
}

/* The lobes of microfacet material m at local lo (the way back) and li: rough glass's
 * (dielectric_at, m.ior its bsdf_eta) or the reflecting kinds' (microfacet_at). */
TZ_FN microfacet_value microfacet_lobes(bsdf_material m, vec3 lo, vec3 li) {
    if (is_dielectric(m.kind)) return dielectric_at(m.color, m.ior, m.alpha, lo, li);
    return microfacet_at(m.kind, m.color, m.ks, m.ior, m.alpha, lo, li);
}

/* The BRDF of lobe material m for light from wi seen from wo at shading normal n, unfolded (report
 * mode, point lights). */
TZ_FN vec3 bsdf_f(bsdf_material m, vec3 n, vec3 wi, vec3 wo) {
    if (TZ_MICROFACET_ON && is_microfacet(m.kind)) {
        tangent_frame f = basis(n);
        return microfacet_lobes(m, to_local(f, n, wo), to_local(f, n, wi)).f;
    }
    return bsdf_f_at(m, phong_lobe_cos(n, wi, wo));
}

/* The colour a denoiser takes as material m's albedo (the AOV of shaders/common/aov.h): a lobe's
 * head-on reflectance kd + ks, a delta's tint. The one place a new kind says its albedo. */
TZ_LANE_FN vec3 bsdf_albedo(bsdf_material m) {
    return bsdf_is_delta(m.kind) ? m.color : v3_add(m.color, v3(m.ks, m.ks, m.ks));
}

/* The share of the cosine lobe in lobe material m's sampling (diffuse_share; -1: it reflects
 * nothing); 0 for the microfacet kinds, whose share depends on the way back
 * (microfacet_spec_share). */
TZ_LANE_FN float bsdf_share(bsdf_material m) {
    return is_microfacet(m.kind) ? 0.0f : diffuse_share(m.color, m.ks);
}

/* The axis of the Phong lobe at shading normal n seen from wo: wo mirrored about n. */
TZ_LANE_FN vec3 phong_lobe_axis(vec3 n, vec3 wo) {
    TZ_PRECISE vec3 wr = v3_sub(v3_scale(n, 2.0f * v3_dot(n, wo)), wo);
    return wr;
}

/* What fold_at takes at the mirror image of wi in the face's plane (geometric normal ng): its
 * shading cosine cos_m and lobe cosine xm. */
TZ_STRUCT(fold_mirror) {
    float cos_m;
    float xm;
}
TZ_STRUCT_END(fold_mirror)

TZ_LANE_FN fold_mirror fold_mirror_of(vec3 n, vec3 ng, vec3 wi, vec3 wo) {
    vec3 wm = mirror_in_plane(wi, ng);
    fold_mirror r;
    r.cos_m = v3_dot(n, wm);
    r.xm = phong_lobe_cos(n, wm, wo);
    return r;
}

/* fold_terms of material m (share its bsdf_share) over the terms at wi itself (BRDF f_i, shading
 * cosine cos_i, pdf pdf_i) and at its mirror image (cos_m, and lobe_m: phong_lobe of its xm). */
TZ_LANE_FN folded_bsdf fold_of_lobe(bsdf_material m, float share, vec3 f_i, float cos_i,
                                    float pdf_i, float cos_m, float lobe_m) {
    return fold_terms(f_i, cos_i, pdf_i, bsdf_f_of_lobe(m, lobe_m), cos_m,
                      bsdf_pdf_of_lobe(share, m.alpha, cos_m, lobe_m));
}

/* The folded BSDF (fold_terms) at direction wi of a smooth vertex (shading normal n, geometric
 * normal ng, wo the way back, material m, share its bsdf_share), given its terms at wi itself:
 * BRDF f_i, shading cosine cos_i and pdf pdf_i. */
TZ_FN folded_bsdf fold_at(vec3 n, vec3 ng, vec3 wi, vec3 wo, bsdf_material m, float share, vec3 f_i,
                          float cos_i, float pdf_i) {
    fold_mirror fm = fold_mirror_of(n, ng, wi, wo);
    return fold_of_lobe(m, share, f_i, cos_i, pdf_i, fm.cos_m, phong_lobe(fm.xm, m.alpha));
}

/* Lobe material m's BSDF at wi seen from wo at a vertex of facing shading normal n and geometric
 * normal ng: f times f_scale is f cos, folded onto the geometric hemisphere where folds_at (DESIGN
 * section 3.3), pdf the solid-angle pdf of bsdf_sample_lobe drawing wi, cos_i = n . wi. */
TZ_STRUCT(bsdf_value) {
    vec3 f;
    float f_scale;
    float pdf;
    float cos_i;
}
TZ_STRUCT_END(bsdf_value)

/* bsdf_eval of a microfacet material: its lobes at wi. The reflecting kinds' do not fold on smooth
 * faces (a direction below the shading or the geometric hemisphere gives nothing and ends a path):
 * the fold's second evaluation, summed under precise, sent glslang's propagation of precise past 16
 * GB on the module of both modes. */
TZ_FN bsdf_value microfacet_eval(bsdf_material m, vec3 n, vec3 wi, vec3 wo) {
    tangent_frame f = basis(n);
    vec3 lo = to_local(f, n, wo), li = to_local(f, n, wi);
    microfacet_value a = microfacet_lobes(m, lo, li);
    bsdf_value v;
    v.f = a.f;
    v.f_scale = TZ_ABS(li.z); /* rough glass's transmission is below */
    v.pdf = a.pdf;
    v.cos_i = li.z;
    return v;
}

TZ_FN bsdf_value bsdf_eval(bsdf_material m, float share, vec3 n, vec3 ng, vec3 wi, vec3 wo) {
    if (TZ_MICROFACET_ON && is_microfacet(m.kind)) return microfacet_eval(m, n, wi, wo);
    float cos_i = v3_dot(n, wi), x = phong_lobe_cos(n, wi, wo);
    float pdf = bsdf_pdf(share, m.alpha, cos_i, x);
    vec3 f = bsdf_f_at(m, x);
    float f_scale = cos_i; /* f times f_scale: f cos */
    if (folds_at(n, ng)) {
        folded_bsdf fb = fold_at(n, ng, wi, wo, m, share, f, cos_i, pdf);
        f = fb.f_cos;
        f_scale = 1.0f;
        pdf = fb.pdf;
    }
    bsdf_value v;
    v.f = f;
    v.f_scale = f_scale;
    v.pdf = pdf;
    v.cos_i = cos_i;
    return v;
}

/* The pdf with which bsdf_sample_lobe draws wi (bsdf_eval's). */
TZ_FN float bsdf_pdf_at(bsdf_material m, float share, vec3 n, vec3 ng, vec3 wi, vec3 wo) {
    return bsdf_eval(m, share, n, ng, wi, wo).pdf;
}

/* Whether a point light in direction wi (shading cosine cos_i) reaches a vertex of material
 * kind and facing geometric normal ng: above both normals, or for rough glass below both
 * (through it: its shadow ray leaves below, bsdf_next_origin, and its radiance, which holds
 * cos_i, is negated). */
TZ_LANE_FN TZ_BOOL point_light_reaches(int kind, float cos_i, vec3 ng, vec3 wi) {
    float side = v3_dot(ng, wi);
    TZ_BOOL above = !(cos_i <= 0.0f) TZ_AND !(side <= 0.0f);
    TZ_BOOL through = is_dielectric(kind) TZ_AND(cos_i < 0.0f) TZ_AND(side < 0.0f);
    return above TZ_OR through;
}

/* A direction drawn from a lobe material's BSDF: wi, weight f cos / pdf, the pdf, and whether the
 * path goes on (ok: above the face, pdf above 0). A delta's is bsdf_delta_transmits'. */
TZ_STRUCT(bsdf_sample) {
    vec3 wi;
    vec3 weight;
    float pdf;
    TZ_BOOL ok;
}
TZ_STRUCT_END(bsdf_sample)

/* Whether a path goes on along wi drawn at a vertex of geometric normal ng (cos_i the shading
 * cosine, pdf the BSDF's, folds whether it folds) from material kind: above the face, and above
 * the shading normal unless folded, with a pdf above 0; rough glass's dielectric_goes_on. */
TZ_LANE_FN TZ_BOOL bsdf_goes_on(int kind, TZ_BOOL folds, float cos_i, vec3 ng, vec3 wi, float pdf) {
    TZ_BOOL on = (folds TZ_OR(cos_i > 0.0f)) TZ_AND(v3_dot(ng, wi) > 0.0f) TZ_AND(pdf > 0.0f);
    return is_dielectric(kind) ? dielectric_goes_on(cos_i, ng, wi, pdf) : on;
}

/* Where the ray along wi leaves a non-delta vertex at pos of facing geometric normal ng: offset
 * to the side wi goes to (below only for rough glass's transmission). */
TZ_LANE_FN vec3 bsdf_next_origin(vec3 pos, vec3 ng, vec3 wi) {
    return offset_origin(pos, select3(v3_dot(ng, wi) < 0.0f, v3_scale(ng, -1.0f), ng));
}

/* The direction a microfacet material m draws at shading normal n seen from wo for uniform us,
 * u1, u2: rough glass's dielectric_direction; else us under the cosine lobe's share (1 -
 * microfacet_spec_share) the cosine direction of (u1, u2), else wo reflected about a visible normal
 * (ggx_sample_half). */
TZ_FN vec3 microfacet_direction(bsdf_material m, vec3 n, vec3 wo, float us, float u1, float u2) {
    if (is_dielectric(m.kind)) return dielectric_direction(m.ior, m.alpha, n, wo, us, u1, u2);
    tangent_frame f = basis(n);
    vec3 lo = to_local(f, n, wo);
    float ps = microfacet_spec_share(m.kind, m.color, m.ks, m.ior, lo.z, ggx_albedo(lo.z, m.alpha),
                                     ggx_albedo_avg(m.alpha));
    if (us < 1.0f - ps) return cosine_direction(n, u1, u2);
    vec3 h = from_local(f, n, ggx_sample_half(lo, m.alpha, u1, u2));
    TZ_PRECISE vec3 wi = v3_sub(v3_scale(h, 2.0f * v3_dot(wo, h)), wo);
    return wi;
}

/* Draws wi for lobe material m (share its bsdf_share, at least 0) from uniform us, u1, u2 at a
 * vertex of facing normals n and ng, wo the way back: us < share the cosine direction of (u1,
 * u2), else the Phong lobe about n's mirror of wo; a smooth face folds a direction below it above
 * it (folds_at), any other ends the path there. */
TZ_FN bsdf_sample bsdf_sample_lobe(bsdf_material m, float share, vec3 n, vec3 ng, vec3 wo, float us,
                                   float u1, float u2) {
    vec3 wi;
    if (TZ_MICROFACET_ON && is_microfacet(m.kind)) {
        wi = microfacet_direction(m, n, wo, us, u1, u2);
    } else if (us < share) {
        wi = cosine_direction(n, u1, u2);
    } else {
        wi = phong_lobe_direction(phong_lobe_axis(n, wo), m.alpha, u1, u2);
    }
    TZ_BOOL folds = folds_at(n, ng) TZ_AND !is_microfacet(m.kind); /* microfacet_eval's */
    if (folds && !(v3_dot(ng, wi) > 0.0f)) wi = mirror_in_plane(wi, ng);
    bsdf_value v = bsdf_eval(m, share, n, ng, wi, wo);
    bsdf_sample s;
    s.wi = wi;
    s.pdf = v.pdf;
    s.ok = bsdf_goes_on(m.kind, folds, v.cos_i, ng, wi, v.pdf);
    TZ_PRECISE vec3 f = v3_scale(v.f, v.f_scale / v.pdf);
    s.weight = f;
    return s;
}

/* Whether delta material m sends the ray d (meeting a surface of outward normal nout, turned
 * about n, specular_normal's) through it: never for a mirror; for glass when uniform uf is not
 * under the exact Fresnel reflectance (DESIGN section 3.2, step 6). Its weight is the tint. */
TZ_LANE_FN TZ_BOOL bsdf_delta_transmits(bsdf_material m, vec3 d, vec3 nout, vec3 n, float uf) {
    TZ_BOOL refractive = bsdf_refracts(m.kind);
    TZ_BOOL transmits = refractive;
    TZ_BRANCH_IF(refractive) {
        TZ_BOOL entering = v3_dot(d, nout) < 0.0f;
        TZ_PRECISE float eta = entering ? 1.0f / m.ior : m.ior;
        TZ_PRECISE float c1 = -v3_dot(d, n);
        TZ_PRECISE float kk = 1.0f - eta * eta * (1.0f - c1 * c1);
        transmits = refractive TZ_AND !(uf < fresnel_dielectric(eta, c1, kk));
    }
    return transmits;
}

#endif
