/* dielectric.h: rough glass (`refractive roughness` above 0), one text for C and GLSL
 * (dialect.h): Walter, Marschner, Li and Torrance 2007's microfacet BSDF of a dielectric
 * interface, reflection and transmission through the GGX distribution of microfacet.h with the
 * height-correlated Smith G2 and the exact Fresnel reflectance at the microfacet, drawn from the
 * visible normals (ggx_sample_half), Fresnel choosing the lobe. Its throughput keeps the delta
 * glass's convention (a weight of the tint, no eta^2), so that roughness 0 and its limit agree.
 * bsdf.h calls it; tests/test_dielectric.c tests its pdf against its sampling. */
#ifndef TRAZADOR_COMMON_DIELECTRIC_H
#define TRAZADOR_COMMON_DIELECTRIC_H

#include "dialect.h"
#include "microfacet.h"
#include "sampling.h"
#include "shade.h"

/* Whether material kind is rough glass, whose lobes reach below the surface. */
TZ_LANE_FN TZ_BOOL is_dielectric(int kind) { return kind == TZ_MATERIAL_DIELECTRIC; }

/* The index a material of kind and refractive index ior scatters with, seen along d at outward
 * normal nout: for rough glass the ratio of the far side's index to the near side's (ior
 * entering, 1 / ior leaving), what its lobes take in bsdf_material.ior; the other kinds' ior. */
TZ_LANE_FN float bsdf_eta(int kind, float ior, vec3 nout, vec3 d) {
    TZ_BOOL leaving = is_dielectric(kind) TZ_AND !(v3_dot(d, nout) < 0.0f);
    return leaving ? 1.0f / ior : ior;
}

/* Rough glass of tint color, relative index eta (bsdf_eta) and GGX width alpha at local lo (the
 * way back, lo.z > 0) and li: the BSDF f and the pdf of dielectric_direction drawing li. With D
 * the distribution, so = sqrt(a2 (x^2 + y^2) + z^2) of lo and si of li (G2 = 2 co ci / (so ci +
 * si co), G1(lo) = 2 co / (co + so)) and F the exact Fresnel reflectance at lo . h: li above,
 * h = normalize(lo + li), f = F D / (2 (so ci + si co)) and pdf = F D / (2 (co + so)); li below,
 * h = normalize(lo + eta li) turned up, f = (1 - F) D 2 (lo . h) |li . h| eta^2 / ((so |ci| +
 * si co) (lo . h + eta li . h)^2), the pdf the same over (co + so): each sample weighs G2 / G1.
 * A pair whose microfacet faces away from either direction gives 0. */
TZ_FN microfacet_value dielectric_at(vec3 color, float eta, float alpha, vec3 lo, vec3 li) {
    float a2 = alpha * alpha;
    TZ_BOOL reflects = li.z > 0.0f;
    float e = reflects ? 1.0f : eta;
    TZ_PRECISE vec3 hw = v3_add(lo, v3_scale(li, e));
    vec3 hn = v3_normalize(hw);
    vec3 h = select3(hn.z < 0.0f, v3_scale(hn, -1.0f), hn);
    float co = lo.z, ci = TZ_ABS(li.z);
    TZ_PRECISE float so = TZ_SQRT(a2 * (lo.x * lo.x + lo.y * lo.y) + lo.z * lo.z);
    TZ_PRECISE float si = TZ_SQRT(a2 * (li.x * li.x + li.y * li.y) + li.z * li.z);
    TZ_PRECISE float t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
    float d = 1.0f / (TZ_PI * a2 * t * t);
    float oh = v3_dot(lo, h), ih = v3_dot(li, h);
    float inv = 1.0f / eta;
    TZ_PRECISE float k = 1.0f - inv * inv * (1.0f - oh * oh);
    float fr = fresnel_dielectric(inv, oh, k);
    TZ_PRECISE float g = so * ci + si * co;
    TZ_PRECISE float den = oh + eta * ih;
    float jac = 2.0f * oh * -ih * eta * eta / (den * den);
    float f_r = fr * d / (2.0f * g), pdf_r = fr * d / (2.0f * (co + so));
    float f_t = (1.0f - fr) * d * jac / g, pdf_t = (1.0f - fr) * d * jac / (co + so);
    TZ_BOOL valid =
        (co > 0.0f) TZ_AND(li.z != 0.0f) TZ_AND(oh > 0.0f) TZ_AND(reflects ? ih > 0.0f : ih < 0.0f);
    microfacet_value v;
    v.f = v3_scale(color, valid ? (reflects ? f_r : f_t) : 0.0f);
    v.pdf = valid ? (reflects ? pdf_r : pdf_t) : 0.0f;
    return v;
}

/* The direction rough glass (relative index eta, GGX width alpha) draws at shading normal n seen
 * from wo for uniform us, u1, u2: a visible normal h (ggx_sample_half of u1, u2), then wo
 * reflected about it where us is under the Fresnel reflectance at wo . h, else refracted
 * through it; the zero vector where the direction leaves on the side the other lobe covers,
 * which dielectric_at gives a pdf of 0. */
TZ_FN vec3 dielectric_direction(float eta, float alpha, vec3 n, vec3 wo, float us, float u1,
                                float u2) {
    tangent_frame f = basis(n);
    vec3 lo = to_local(f, n, wo);
    vec3 h = from_local(f, n, ggx_sample_half(lo, alpha, u1, u2));
    float c1 = v3_dot(wo, h);
    float inv = 1.0f / eta;
    TZ_PRECISE float k = 1.0f - inv * inv * (1.0f - c1 * c1);
    float fr = fresnel_dielectric(inv, c1, k);
    TZ_PRECISE vec3 wr = v3_sub(v3_scale(h, 2.0f * c1), wo);
    TZ_PRECISE float along = inv * c1 - TZ_SQRT(TZ_MAX(k, 0.0f));
    TZ_PRECISE vec3 wt = v3_normalize(v3_sub(v3_scale(h, along), v3_scale(wo, inv)));
    TZ_BOOL reflects = us < fr;
    vec3 wi = select3(reflects, wr, wt);
    float side = v3_dot(n, wi);
    TZ_BOOL kept = reflects ? side > 0.0f : side < 0.0f;
    return select3(kept, wi, v3(0.0f, 0.0f, 0.0f));
}

/* Whether a path goes on along wi drawn from rough glass at a vertex of geometric normal ng
 * (cos_i the shading cosine, pdf the BSDF's): on the same side of both normals, pdf above 0. */
TZ_LANE_FN TZ_BOOL dielectric_goes_on(float cos_i, vec3 ng, vec3 wi, float pdf) {
    float side = v3_dot(ng, wi);
    TZ_BOOL above = (cos_i > 0.0f) TZ_AND(side > 0.0f);
    TZ_BOOL below = (cos_i < 0.0f) TZ_AND(side < 0.0f);
    return (above TZ_OR below)TZ_AND(pdf > 0.0f);
}

#endif
