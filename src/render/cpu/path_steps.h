/* path_steps.h: the sampling steps of path mode (DESIGN section 3.2): the Phong lobe, the cone and
 * the area of a sphere, the mixture pdf of the BSDF, exact Fresnel and the power heuristic. Pure
 * functions of their arguments, so that every back end computes the same values. */
#ifndef TRAZADOR_PATH_STEPS_H
#define TRAZADOR_PATH_STEPS_H

#include <math.h>

#include "render/cpu/integrator_steps.h"

/* A direction and its solid-angle pdf (0: no direction). */
typedef struct direction_sample {
    vec3 wi;
    float pdf;
} direction_sample;

/* The unit vector at polar angle theta (cosine cos_t, sine sin_t) and azimuth phi about unit
 * axis w, in the basis of cosine_direction. */
static inline vec3 direction_about(vec3 w, float cos_t, float sin_t, float phi) {
    float sign = w.z >= 0.0f ? 1.0f : -1.0f;
    float a = -1.0f / (sign + w.z);
    float c = w.x * w.y * a;
    vec3 t = v3(1.0f + sign * w.x * w.x * a, sign * c, -sign * w.x);
    vec3 b = v3(c, sign + w.y * w.y * a, -w.y);
    return v3_add(v3_add(v3_scale(t, sin_t * cosf(phi)), v3_scale(b, sin_t * sinf(phi))),
                  v3_scale(w, cos_t));
}

/* The Phong lobe's direction about unit wr for uniform u1, u2: cos = u1^(1/(alpha+1)). */
static inline vec3 phong_lobe_direction(vec3 wr, float alpha, float u1, float u2) {
    float cos_t = powf(u1, 1.0f / (alpha + 1.0f));
    float sin2 = 1.0f - cos_t * cos_t;
    return direction_about(wr, cos_t, sqrtf(sin2 > 0.0f ? sin2 : 0.0f), 2.0f * TZ_PI * u2);
}

/* The share of diffuse samples at a Phong or Lambertian surface: w_d / (w_d + w_s), w_d the mean
 * of kd, w_s = ks; -1 when both are 0 (the surface reflects nothing). */
static inline float diffuse_share(vec3 kd, float ks) {
    float wd = (kd.x + kd.y + kd.z) * (1.0f / 3.0f);
    float total = wd + ks;
    return total > 0.0f ? wd / total : -1.0f;
}

/* The solid-angle pdf with which the BSDF samples wi: P_d cos/pi + (1 - P_d) the lobe's pdf, the
 * lobe at x = phong_lobe_cos(n, wi, wo), as the BRDF takes it. */
static inline float bsdf_pdf(float share, float alpha, float cos_i, float lobe_cos) {
    float diffuse = cos_i > 0.0f ? cos_i * (1.0f / TZ_PI) : 0.0f;
    float lobe = (alpha + 1.0f) * (1.0f / (2.0f * TZ_PI)) * phong_lobe(lobe_cos, alpha);
    return share * diffuse + (1.0f - share) * lobe;
}

/* 1 - cos(theta_max) of the cone a sphere of squared radius r2 subtends at squared distance d2
 * > r2, exact for tiny cones: sin^2 / (1 + cos). */
static inline float cone_one_minus_cos(float r2, float d2) {
    float sin2 = r2 / d2;
    float cos_max = sqrtf(1.0f - sin2 > 0.0f ? 1.0f - sin2 : 0.0f);
    return sin2 / (1.0f + cos_max);
}

/* A direction uniform in the cone of half-angle theta_max about unit w (omc = 1 - cos(theta_max)),
 * for uniform u1, u2; pdf 1 / (2 pi omc). */
static inline direction_sample cone_direction(vec3 w, float omc, float u1, float u2) {
    float x = u1 * omc; /* 1 - cos(theta) */
    float sin2 = x * (2.0f - x);
    vec3 wi = direction_about(w, 1.0f - x, sqrtf(sin2 > 0.0f ? sin2 : 0.0f), 2.0f * TZ_PI * u2);
    return (direction_sample){wi, 1.0f / (2.0f * TZ_PI * omc)};
}

/* The unit vector uniform on the sphere for uniform u1, u2: z = 1 - 2 u1, phi = 2 pi u2. */
static inline vec3 sphere_area_direction(float u1, float u2) {
    float z = 1.0f - 2.0f * u1;
    float rho2 = 1.0f - z * z;
    float rho = sqrtf(rho2 > 0.0f ? rho2 : 0.0f), phi = 2.0f * TZ_PI * u2;
    return v3(rho * cosf(phi), rho * sinf(phi), z);
}

/* The solid-angle pdf of area sampling a sphere of radius r at a point dist2 away, whose normal
 * makes cosine cos_l with the direction: dist2 / (4 pi r^2 |cos_l|). */
static inline float area_pdf(float r, float dist2, float cos_l) {
    float c = cos_l < 0.0f ? -cos_l : cos_l;
    return dist2 / (4.0f * TZ_PI * r * r * c);
}

/* Unpolarized Fresnel reflectance of a dielectric: relative index eta = n_incident / n_other,
 * c1 the cosine of incidence, k = 1 - eta^2 (1 - c1^2) (< 0: total internal reflection, 1). */
static inline float fresnel_dielectric(float eta, float c1, float k) {
    if (k < 0.0f) return 1.0f;
    float ct = sqrtf(k);
    float rs = (eta * c1 - ct) / (eta * c1 + ct);
    float rp = (c1 - eta * ct) / (c1 + eta * ct);
    return 0.5f * (rs * rs + rp * rp);
}

/* Veach's power heuristic weight of a strategy of pdf a against one of pdf b. */
static inline float power_heuristic(float a, float b) {
    float a2 = a * a;
    return a2 > 0.0f ? a2 / (a2 + b * b) : 0.0f;
}

#endif
