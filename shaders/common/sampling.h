/* sampling.h: path mode's sampling steps (DESIGN section 3.2), one text for C and GLSL
 * (dialect.h): the Phong lobe, a sphere's cone and area, the BSDF's mixture pdf, exact Fresnel
 * and the power heuristic. Pure functions, tested against their pdfs (tests/test_sampling.c). */
#ifndef TRAZADOR_COMMON_SAMPLING_H
#define TRAZADOR_COMMON_SAMPLING_H

#include "dialect.h"
#include "shade.h"

/* A direction and its solid-angle pdf. */
TZ_STRUCT(direction_sample) {
    vec3 wi;
    float pdf;
}
TZ_STRUCT_END(direction_sample)

/* Whether a diffuse vertex folds its BSDF onto the geometric hemisphere: where its shading
 * normal n is not its geometric normal ng (a smooth face), so that the part of the shading
 * hemisphere below the face is reflected above it rather than lost (DESIGN section 3.3). */
TZ_FN TZ_BOOL folds_at(vec3 n, vec3 ng) { return n.x != ng.x || n.y != ng.y || n.z != ng.z; }

/* The folded BSDF at a direction: f times the shading cosine, and the pdf of sampling it. */
TZ_STRUCT(folded_bsdf) {
    vec3 f_cos;
    float pdf;
}
TZ_STRUCT_END(folded_bsdf)

/* The folded BSDF summed over a direction (BRDF f_i at shading cosine cos_i, BSDF pdf pdf_i) and
 * its mirror image (f_m, cos_m, pdf_m). */
TZ_FN folded_bsdf fold_terms(vec3 f_i, float cos_i, float pdf_i, vec3 f_m, float cos_m,
                             float pdf_m) {
    folded_bsdf r;
    TZ_PRECISE vec3 f_cos =
        v3_add(v3_scale(f_i, TZ_MAX(cos_i, 0.0f)), v3_scale(f_m, TZ_MAX(cos_m, 0.0f)));
    TZ_PRECISE float pdf = pdf_i + pdf_m;
    r.f_cos = f_cos;
    r.pdf = pdf;
    return r;
}

/* The unit vector at polar angle theta (cosine cos_t, sine sin_t) and azimuth phi about unit
 * axis w, in the basis of the bounce direction. */
TZ_FN vec3 direction_about(vec3 w, float cos_t, float sin_t, cos_sin phi) {
    tangent_frame f = basis(w);
    TZ_PRECISE float c = sin_t * phi.c, s = sin_t * phi.s;
    TZ_PRECISE vec3 d = v3_add(v3_add(v3_scale(f.t, c), v3_scale(f.b, s)), v3_scale(w, cos_t));
    return d;
}

/* The Phong lobe's direction about unit wr for uniform u1, u2: cos theta = u1^(1/(alpha+1)). */
TZ_FN vec3 phong_lobe_direction(vec3 wr, float alpha, float u1, float u2) {
    TZ_PRECISE float cos_t = pow_unit(u1, 1.0f / (alpha + 1.0f));
    TZ_PRECISE float sin2 = 1.0f - cos_t * cos_t;
    return direction_about(wr, cos_t, TZ_SQRT(TZ_MAX(sin2, 0.0f)), cos_sin_turn(u2));
}

/* The share of diffuse samples of a Phong or Lambertian surface: w_d / (w_d + w_s), w_d the mean
 * of kd and w_s = ks; -1 when both are 0 (the surface reflects nothing). */
TZ_FN float diffuse_share(vec3 kd, float ks) {
    TZ_PRECISE float wd = (kd.x + kd.y + kd.z) * (1.0f / 3.0f);
    TZ_PRECISE float total = wd + ks;
    TZ_PRECISE float share = wd / total;
    return total > 0.0f ? share : -1.0f;
}

/* bsdf_pdf with the lobe's phong_lobe(lobe_cos, alpha) given as lobe (the packet builds take
 * it lane by lane). */
TZ_LANE_FN float bsdf_pdf_of_lobe(float share, float alpha, float cos_i, float lobe) {
    TZ_PRECISE float diffuse = cos_i * (1.0f / TZ_PI);
    TZ_PRECISE float lobe_pdf = (alpha + 1.0f) * (1.0f / (2.0f * TZ_PI)) * lobe;
    TZ_PRECISE float pdf = share * (cos_i > 0.0f ? diffuse : 0.0f) + (1.0f - share) * lobe_pdf;
    return pdf;
}

/* The solid-angle pdf with which the BSDF samples wi: share cos/pi + (1 - share) times the lobe's
 * pdf, the lobe at the cosine the BRDF takes (phong_lobe_cos). */
TZ_FN float bsdf_pdf(float share, float alpha, float cos_i, float lobe_cos) {
    return bsdf_pdf_of_lobe(share, alpha, cos_i, phong_lobe(lobe_cos, alpha));
}

/* 1 - cos(theta_max) of the cone that a sphere of squared radius r2 subtends at squared distance
 * d2 > r2, exact for tiny cones: sin^2 / (1 + cos). */
TZ_FN float cone_one_minus_cos(float r2, float d2) {
    TZ_PRECISE float sin2 = r2 / d2;
    TZ_PRECISE float cos_max = TZ_SQRT(TZ_MAX(1.0f - sin2, 0.0f));
    TZ_PRECISE float omc = sin2 / (1.0f + cos_max);
    return omc;
}

/* A direction uniform in the cone about unit w whose 1 - cos(theta_max) is omc, for uniform u1
 * and azimuth phi (cos_sin_turn of a uniform number); pdf 1 / (2 pi omc). */
TZ_LANE_FN direction_sample cone_direction_at(vec3 w, float omc, float u1, cos_sin phi) {
    TZ_PRECISE float x = u1 * omc; /* 1 - cos theta */
    TZ_PRECISE float sin2 = x * (2.0f - x);
    TZ_PRECISE float pdf = 1.0f / (2.0f * TZ_PI * omc);
    direction_sample s;
    s.wi = direction_about(w, 1.0f - x, TZ_SQRT(TZ_MAX(sin2, 0.0f)), phi);
    s.pdf = pdf;
    return s;
}

/* cone_direction_at for uniform u1, u2 (phi = 2 pi u2). */
TZ_FN direction_sample cone_direction(vec3 w, float omc, float u1, float u2) {
    return cone_direction_at(w, omc, u1, cos_sin_turn(u2));
}

/* A point of the unit disc. */
TZ_STRUCT(disc_point) {
    float x;
    float y;
}
TZ_STRUCT_END(disc_point)

/* A point uniform on the unit disc from uniform u1, u2 by Shirley and Chiu's concentric map: it
 * keeps a pair's strata compact on the disc (the thin lens's samples). */
TZ_FN disc_point concentric_disc(float u1, float u2) {
    TZ_PRECISE float a = 2.0f * u1 - 1.0f;
    TZ_PRECISE float b = 2.0f * u2 - 1.0f;
    TZ_BOOL wide = TZ_ABS(a) > TZ_ABS(b);
    float r = wide ? a : b, other = wide ? b : a;
    TZ_PRECISE float ratio = other / (r != 0.0f ? r : 1.0f);
    /* the angle in turns: (b / a) / 8 in [-1/8, 1/8], else 1/4 - (a / b) / 8 in [1/8, 3/8] */
    TZ_PRECISE float t = wide ? ratio * 0.125f : 0.25f - ratio * 0.125f;
    cos_sin phi = cos_sin_turn(TZ_ABS(t));
    disc_point p;
    p.x = r * phi.c;
    p.y = t < 0.0f ? -(r * phi.s) : r * phi.s;
    return p;
}

/* The unit vector uniform on the sphere for uniform u1 and azimuth phi: z = 1 - 2 u1. */
TZ_LANE_FN vec3 sphere_area_direction_at(float u1, cos_sin phi) {
    TZ_PRECISE float z = 1.0f - 2.0f * u1;
    TZ_PRECISE float rho = TZ_SQRT(TZ_MAX(1.0f - z * z, 0.0f));
    TZ_PRECISE vec3 d = v3(rho * phi.c, rho * phi.s, z);
    return d;
}

/* sphere_area_direction_at for uniform u1, u2 (phi = 2 pi u2). */
TZ_FN vec3 sphere_area_direction(float u1, float u2) {
    return sphere_area_direction_at(u1, cos_sin_turn(u2));
}

/* A point of the triangle (a, b, c) uniform by area from two uniform numbers: the square-root
 * warp, weights 1 - sqrt(ua), ub sqrt(ua) and the rest. */
TZ_FN vec3 triangle_area_point(vec3 a, vec3 b, vec3 c, float ua, float ub) {
    TZ_PRECISE float su = TZ_SQRT(ua);
    TZ_PRECISE float b0 = 1.0f - su, b1 = ub * su;
    TZ_PRECISE float b2 = 1.0f - b0 - b1;
    TZ_PRECISE vec3 q = v3_add(v3_add(v3_scale(a, b0), v3_scale(b, b1)), v3_scale(c, b2));
    return q;
}

/* The solid-angle pdf of area sampling a sphere of radius r at a point dist2 away whose normal
 * makes cosine cos_l with the direction: dist2 / (4 pi r^2 |cos_l|). */
TZ_FN float area_pdf(float r, float dist2, float cos_l) {
    TZ_PRECISE float pdf = dist2 / (4.0f * TZ_PI * r * r * TZ_ABS(cos_l));
    return pdf;
}

/* Unpolarized Fresnel reflectance of a dielectric: eta = n_incident / n_other, c1 the cosine of
 * incidence, k = 1 - eta^2 (1 - c1^2) (below 0: total internal reflection, 1). */
TZ_FN float fresnel_dielectric(float eta, float c1, float k) {
    TZ_PRECISE float ct = TZ_SQRT(TZ_MAX(k, 0.0f));
    TZ_PRECISE float rs = (eta * c1 - ct) / (eta * c1 + ct);
    TZ_PRECISE float rp = (c1 - eta * ct) / (c1 + eta * ct);
    TZ_PRECISE float f = 0.5f * (rs * rs + rp * rp);
    return k < 0.0f ? 1.0f : f;
}

/* The power heuristic's weight of one of n light samples of pdf a against a BSDF sample of pdf b,
 * divided by that sample's share n a: (n a) / ((n a)^2 + b^2), Veach's multi-sample weight over
 * the light estimator's denominator. */
TZ_FN float light_mis_over_pdf(float n, float a, float b) {
    TZ_PRECISE float na = n * a;
    TZ_PRECISE float w = na / (na * na + b * b);
    return w;
}

/* Veach's power heuristic: the weight of a strategy of pdf a against one of pdf b. */
TZ_FN float power_heuristic(float a, float b) {
    TZ_PRECISE float a2 = a * a;
    TZ_PRECISE float w = a2 / (a2 + b * b);
    return a2 > 0.0f ? w : 0.0f;
}

#endif
