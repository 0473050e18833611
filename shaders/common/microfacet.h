/* microfacet.h: the Trowbridge-Reitz (GGX) microfacet lobes, one text for C and GLSL
 * (dialect.h): the distribution D, the height-correlated Smith masking-shadowing term G2, the
 * sampling of the distribution of visible normals (Dupuy and Benyoub 2023, spherical caps) and
 * the materials made of them (DESIGN section 3.2): a rough conductor (`mirror roughness`) and
 * glTF 2.0's metallic-roughness model (`pbr`, its specification's Appendix B), each with Kulla and
 * Conty's lobe for the energy that multiple scattering between microfacets returns, read from the
 * tables of src/render/ggx_albedo.c. bsdf.h calls them; their pdfs are tested against their
 * sampling (tests/test_microfacet.c). */
#ifndef TRAZADOR_COMMON_MICROFACET_H
#define TRAZADOR_COMMON_MICROFACET_H

#include "dialect.h"
#include "shade.h"
#include "transcendental.h"

#ifndef GL_core_profile
#include "render/ggx_albedo.h"
/* Float i of the GGX tables (shared_layout.h, TZ_TEXTURE_GGX); the shaders' includer reads them
 * from the texture table, where the packer copied these very floats. */
static inline float ggx_table(uint32_t i) { return ggx_albedo_words[i]; }
#endif

/* Whether material kind scatters by the microfacet lobes here. */
TZ_LANE_FN TZ_BOOL is_microfacet(int kind) {
    return (kind == TZ_MATERIAL_CONDUCTOR) TZ_OR(kind == TZ_MATERIAL_PBR)
        TZ_OR(kind == TZ_MATERIAL_DIELECTRIC);
}

/* Unit w in the frame (t, b, n) of basis(n). */
TZ_FN vec3 to_local(tangent_frame f, vec3 n, vec3 w) {
    return v3(v3_dot(w, f.t), v3_dot(w, f.b), v3_dot(w, n));
}

/* The local direction l back in the world frame (t, b, n). */
TZ_FN vec3 from_local(tangent_frame f, vec3 n, vec3 l) {
    TZ_PRECISE vec3 w = v3_add(v3_add(v3_scale(f.t, l.x), v3_scale(f.b, l.y)), v3_scale(n, l.z));
    return w;
}

/* The GGX distribution at local unit half vector h: 1 / (pi a2 ((x^2 + y^2) / a2 + z^2)^2). */
TZ_FN float ggx_d(vec3 h, float a2) {
    TZ_PRECISE float t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
    float d = 1.0f / (TZ_PI * a2 * t * t);
    return d;
}

/* A local half vector drawn from GGX's distribution of visible normals seen from local lo
 * (lo.z > 0) for uniform u1 (the cap's height) and u2 (its azimuth): lo stretched to the
 * hemisphere configuration, a point uniform on the spherical cap below it added, unstretched. */
TZ_FN vec3 ggx_sample_half(vec3 lo, float alpha, float u1, float u2) {
    vec3 v = v3_normalize(v3(alpha * lo.x, alpha * lo.y, lo.z));
    cos_sin phi = cos_sin_turn(u2);
    TZ_PRECISE float z = (1.0f - u1) * (1.0f + v.z) - v.z;
    TZ_PRECISE float s = TZ_SQRT(TZ_MAX(1.0f - z * z, 0.0f));
    TZ_PRECISE vec3 hs = v3(s * phi.c + v.x, s * phi.s + v.y, z + v.z);
    vec3 h = v3_normalize(v3(alpha * hs.x, alpha * hs.y, TZ_MAX(hs.z, 0.0f)));
    return h;
}

/* E, the directional albedo of a white GGX conductor of width alpha seen at cosine mu, bilinear
 * in the table (texels at the square roots of the cosines 0..1 and at the roughnesses 0..1, the
 * square roots of the widths). */
TZ_FN float ggx_albedo(float mu, float alpha) {
    float n1 = TZ_FLOAT(TZ_GGX_TABLE_SIZE - 1u);
    float x = TZ_MIN(TZ_MAX(TZ_SQRT(TZ_MAX(mu, 0.0f)) * n1, 0.0f), n1);
    float y = TZ_MIN(TZ_MAX(TZ_SQRT(alpha) * n1, 0.0f), n1);
    TZ_UINT i = TZ_MIN(TZ_UINT_OF(x), TZ_GGX_TABLE_SIZE - 2u);
    TZ_UINT j = TZ_MIN(TZ_UINT_OF(y), TZ_GGX_TABLE_SIZE - 2u);
    TZ_UINT at = j * TZ_GGX_TABLE_SIZE + i;
    float fx = x - TZ_FLOAT(i), fy = y - TZ_FLOAT(j);
    float e00 = ggx_table(at), e01 = ggx_table(at + 1u);
    float e10 = ggx_table(at + TZ_GGX_TABLE_SIZE), e11 = ggx_table(at + TZ_GGX_TABLE_SIZE + 1u);
    TZ_PRECISE float lo = e00 + (e01 - e00) * fx;
    TZ_PRECISE float hi = e10 + (e11 - e10) * fx;
    TZ_PRECISE float e = lo + (hi - lo) * fy;
    return e;
}

/* E_avg, the cosine-weighted mean of ggx_albedo over the hemisphere at width alpha, linear in the
 * table's roughnesses. */
TZ_FN float ggx_albedo_avg(float alpha) {
    float n1 = TZ_FLOAT(TZ_GGX_TABLE_SIZE - 1u);
    float y = TZ_MIN(TZ_MAX(TZ_SQRT(alpha) * n1, 0.0f), n1);
    TZ_UINT j = TZ_MIN(TZ_UINT_OF(y), TZ_GGX_TABLE_SIZE - 2u);
    TZ_UINT at = TZ_GGX_TABLE_SIZE * TZ_GGX_TABLE_SIZE + j;
    float fy = y - TZ_FLOAT(j);
    float a = ggx_table(at), b = ggx_table(at + 1u);
    TZ_PRECISE float e = a + (b - a) * fy;
    return e;
}

/* Kulla and Conty's colour of the multiple-scattering lobe for a mean Fresnel reflectance fa
 * (clamped to [0, 1]): fa^2 E_avg / (1 - fa (1 - E_avg)), the light that leaves after the
 * second and later bounces over what a white surface's leaves; 1 for fa 1. */
TZ_FN float ggx_ms_fresnel(float fa, float eavg) {
    float f = TZ_MIN(TZ_MAX(fa, 0.0f), 1.0f);
    TZ_PRECISE float r = f * f * eavg / (1.0f - f * (1.0f - eavg));
    return r;
}

/* ggx_ms_fresnel of each component of fa. */
TZ_FN vec3 ggx_ms_fresnel3(vec3 fa, float eavg) {
    return v3(ggx_ms_fresnel(fa.x, eavg), ggx_ms_fresnel(fa.y, eavg), ggx_ms_fresnel(fa.z, eavg));
}

/* The white multiple-scattering lobe at the albedos eo and ei of the way back and the way to the
 * light and E_avg: (1 - eo) (1 - ei) / (pi (1 - E_avg)), whose albedo seen at eo is 1 - eo by the
 * table's construction; reciprocal. */
TZ_FN float ggx_ms_lobe(float eo, float ei, float eavg) {
    TZ_PRECISE float f = (1.0f - eo) * (1.0f - ei) / (TZ_PI * TZ_MAX(1.0f - eavg, 1e-6f));
    return f;
}

/* The mean Fresnel reflectance of a Schlick term of normal reflectance f0: f0 + (1 - f0) / 21. */
TZ_FN float schlick_avg(float f0) {
    TZ_PRECISE float r = f0 + (1.0f - f0) * (1.0f / 21.0f);
    return r;
}

/* The share of a microfacet material's samples that its GGX lobe draws, seen at cosine co (eo the
 * white albedo E there, eavg E_avg): the single-scattering weight (E times the Fresnel
 * reflectance at co of the mean colour: the conductor's colour, for pbr the Schlick terms of the
 * dielectric and metal parts mixed by metallic) over that plus the multiple-scattering lobe's
 * ((1 - E) times its Fresnel factor) and pbr's diffuse weight; the rest is drawn by the cosine
 * lobe. */
TZ_FN float microfacet_spec_share(int kind, vec3 color, float metallic, float ior, float co,
                                  float eo, float eavg) {
    float x = TZ_MIN(TZ_MAX(1.0f - co, 0.0f), 1.0f);
    float w5 = x * x * x * x * x;
    float mean = (color.x + color.y + color.z) * (1.0f / 3.0f);
    float r = (ior - 1.0f) / (ior + 1.0f);
    float f0 = r * r;
    TZ_PRECISE float fd = f0 + (1.0f - f0) * w5;
    TZ_PRECISE float fm = mean + (1.0f - mean) * w5;
    TZ_BOOL pbr = kind == TZ_MATERIAL_PBR;
    TZ_PRECISE float fs = pbr ? (1.0f - metallic) * fd + metallic * fm : mean;
    float msd = ggx_ms_fresnel(schlick_avg(f0), eavg),
          msm = ggx_ms_fresnel(schlick_avg(mean), eavg);
    TZ_PRECISE float fms =
        pbr ? (1.0f - metallic) * msd + metallic * msm : ggx_ms_fresnel(mean, eavg);
    TZ_PRECISE float wd = (1.0f - metallic) * (1.0f - fd) * (1.0f - f0) * mean;
    float ws = fs * eo;
    TZ_PRECISE float sum = ws + (1.0f - eo) * fms + (pbr ? wd : 0.0f);
    float share = ws / sum;
    return sum > 0.0f ? share : 1.0f;
}

/* A microfacet material's BRDF at a pair of local directions and the pdf of drawing li. */
TZ_STRUCT(microfacet_value) {
    vec3 f;
    float pdf;
}
TZ_STRUCT_END(microfacet_value)

/* Material kind (colour color, metallic, ior, GGX width alpha) at local lo (the way back) and li
 * (to the light), both above the surface or f and pdf are 0. The GGX lobe spec = D G2 /
 * (4 ci co) with the height-correlated G2 = 1 / (1 + Lambda_o + Lambda_i), which is D / (2 (so ci
 * + si co)), s the stretched lengths of ggx_stretched; its sampling pdf (ggx_sample_half's
 * reflection) D G1(lo) / (4 co) = D / (2 (co + so)). The conductor is color spec; pbr (Appendix
 * B) mix(dielectric, spec F(color), metallic), F Schlick's at lo . h, the dielectric spec F(f0)
 * over the Lambertian color / pi weighted by what the specular layer lets through both ways,
 * (1 - F(f0, ci)) (1 - F(f0, co)) at the macro normal: Appendix B's 1 - F(lo . h) reflects up to
 * 1.46 of the light at grazing angles (furnace, tests/test_microfacet.c), this at most 1 and
 * still reciprocal. Each specular term gains Kulla and Conty's multiple-scattering lobe,
 * ggx_ms_lobe coloured by ggx_ms_fresnel of its mean Fresnel reflectance: the conductor's colour,
 * Schlick's mean of f0 and of the metal's colour. The pdf mixes the cosine lobe (which draws
 * pbr's diffuse and the multiple-scattering lobes) and the GGX lobe by microfacet_spec_share. */
TZ_FN microfacet_value microfacet_at(int kind, vec3 color, float metallic, float ior, float alpha,
                                     vec3 lo, vec3 li) {
    float a2 = alpha * alpha;
    vec3 h = v3_normalize(v3_add(lo, li));
    TZ_PRECISE float so = TZ_SQRT(a2 * (lo.x * lo.x + lo.y * lo.y) + lo.z * lo.z);
    TZ_PRECISE float si = TZ_SQRT(a2 * (li.x * li.x + li.y * li.y) + li.z * li.z);
    TZ_PRECISE float t = (h.x * h.x + h.y * h.y) / a2 + h.z * h.z;
    float d = 1.0f / (TZ_PI * a2 * t * t);
    TZ_PRECISE float spec = d / (2.0f * (so * li.z + si * lo.z));
    float ggx_pdf = d / (2.0f * (lo.z + so));
    float xh = TZ_MIN(TZ_MAX(1.0f - v3_dot(lo, h), 0.0f), 1.0f);
    float xo = TZ_MIN(TZ_MAX(1.0f - lo.z, 0.0f), 1.0f);
    float xi = TZ_MIN(TZ_MAX(1.0f - li.z, 0.0f), 1.0f);
    float w5 = xh * xh * xh * xh * xh, wo5 = xo * xo * xo * xo * xo, wi5 = xi * xi * xi * xi * xi;
    float r = (ior - 1.0f) / (ior + 1.0f);
    float f0 = r * r;
    TZ_PRECISE float fd = f0 + (1.0f - f0) * w5;
    TZ_PRECISE vec3 fm = v3_add(color, v3_scale(v3_sub(v3(1.0f, 1.0f, 1.0f), color), w5));
    TZ_PRECISE float through =
        (1.0f - (f0 + (1.0f - f0) * wo5)) * (1.0f - (f0 + (1.0f - f0) * wi5));
    vec3 diffuse = v3_scale(color, through * (1.0f / TZ_PI));
    vec3 metal = v3_scale(fm, spec);
    float sf = spec * fd;
    float eo = ggx_albedo(lo.z, alpha), ei = ggx_albedo(li.z, alpha), eavg = ggx_albedo_avg(alpha);
    float ms = ggx_ms_lobe(eo, ei, eavg);
    TZ_PRECISE float sd = sf + ms * ggx_ms_fresnel(schlick_avg(f0), eavg);
    vec3 fa = v3(schlick_avg(color.x), schlick_avg(color.y), schlick_avg(color.z));
    TZ_PRECISE vec3 metal_ms = v3_add(metal, v3_scale(ggx_ms_fresnel3(fa, eavg), ms));
    TZ_PRECISE vec3 dielectric = v3_add(diffuse, v3(sd, sd, sd));
    TZ_PRECISE vec3 pbr =
        v3_add(v3_scale(dielectric, 1.0f - metallic), v3_scale(metal_ms, metallic));
    TZ_PRECISE vec3 conductor =
        v3_add(v3_scale(color, spec), v3_scale(ggx_ms_fresnel3(color, eavg), ms));
    float ps = microfacet_spec_share(kind, color, metallic, ior, lo.z, eo, eavg);
    TZ_PRECISE float pdf = (1.0f - ps) * (li.z * (1.0f / TZ_PI)) + ps * ggx_pdf;
    vec3 f = kind == TZ_MATERIAL_PBR ? pbr : conductor;
    TZ_BOOL above = (lo.z > 0.0f) TZ_AND(li.z > 0.0f);
    microfacet_value v;
    v.f = select3(above, f, v3(0.0f, 0.0f, 0.0f));
    v.pdf = above ? pdf : 0.0f;
    return v;
}

#endif
