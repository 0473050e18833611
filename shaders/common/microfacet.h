/* microfacet.h: the Trowbridge-Reitz (GGX) microfacet lobes, one text for C and GLSL
 * (dialect.h): the distribution D, the height-correlated Smith masking-shadowing term G2, the
 * sampling of the distribution of visible normals (Dupuy and Benyoub 2023, spherical caps) and
 * the materials made of them (DESIGN section 3.2): a rough conductor (`mirror roughness`) and
 * glTF 2.0's metallic-roughness model (`pbr`, its specification's Appendix B). bsdf.h calls
 * them; their pdfs are tested against their sampling (tests/test_microfacet.c). */
#ifndef TRAZADOR_COMMON_MICROFACET_H
#define TRAZADOR_COMMON_MICROFACET_H

#include "dialect.h"
#include "shade.h"
#include "transcendental.h"

/* Whether material kind scatters by the microfacet lobes here. */
TZ_LANE_FN TZ_BOOL is_microfacet(int kind) {
    return (kind == TZ_MATERIAL_CONDUCTOR) TZ_OR(kind == TZ_MATERIAL_PBR);
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

/* The share of a microfacet material's samples that its GGX lobe draws, seen at cosine co: 1 for
 * the conductor; for pbr its specular weight (the Schlick Fresnel at co of the dielectric part
 * and of the metal's mean colour, mixed by metallic) over that plus the diffuse weight. */
TZ_FN float microfacet_spec_share(int kind, vec3 color, float metallic, float ior, float co) {
    float x = TZ_MIN(TZ_MAX(1.0f - co, 0.0f), 1.0f);
    float w5 = x * x * x * x * x;
    float mean = (color.x + color.y + color.z) * (1.0f / 3.0f);
    float r = (ior - 1.0f) / (ior + 1.0f);
    float f0 = r * r;
    TZ_PRECISE float fd = f0 + (1.0f - f0) * w5;
    TZ_PRECISE float fm = mean + (1.0f - mean) * w5;
    TZ_PRECISE float ws = (1.0f - metallic) * fd + metallic * fm;
    float wd = (1.0f - metallic) * (1.0f - fd) * (1.0f - f0) * mean;
    float share = ws / (ws + wd);
    float pbr = ws + wd > 0.0f ? share : 1.0f;
    return kind == TZ_MATERIAL_PBR ? pbr : 1.0f;
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
 * still reciprocal. The pdf mixes the cosine lobe and the GGX lobe by microfacet_spec_share.
 * Written out in one function: glslang's propagation of precise from the callers grew past 16 GB
 * through a tree of small ones. */
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
    TZ_PRECISE vec3 dielectric = v3_add(diffuse, v3(sf, sf, sf));
    TZ_PRECISE vec3 pbr = v3_add(v3_scale(dielectric, 1.0f - metallic), v3_scale(metal, metallic));
    float ps = microfacet_spec_share(kind, color, metallic, ior, lo.z);
    TZ_PRECISE float pdf = (1.0f - ps) * (li.z * (1.0f / TZ_PI)) + ps * ggx_pdf;
    vec3 f = kind == TZ_MATERIAL_PBR ? pbr : v3_scale(color, spec);
    TZ_BOOL above = (lo.z > 0.0f) TZ_AND(li.z > 0.0f);
    microfacet_value v;
    v.f = select3(above, f, v3(0.0f, 0.0f, 0.0f));
    v.pdf = above ? pdf : 0.0f;
    return v;
}

#endif
