/* test_sampling.c: path mode's sampling routines (cosine, Phong lobe, sphere cone, sphere area)
 * against their pdfs by a chi-square test over bins of (cos theta, phi), as Mitsuba's sampling
 * tests do, and the triangle's area sample over equal sub-triangles; and the test's own power: a
 * wrong pdf is rejected. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "chi_square.h"
#include "common/rng.h"
#include "common/sampling.h"

#define PI 3.14159265358979323846

#define COS_BINS 24
#define PHI_BINS 24
#define SAMPLES 400000

typedef vec3 (*sampler)(const void *ctx, float u1, float u2);
typedef double (*pdf_fn)(const void *ctx, double cos_t, double phi);

/* The chi-square statistic's z score (Wilson-Hilferty) of the samples' (cos theta, phi) about
 * axis w against pdf: bins over cos theta in [c_lo, 1] (narrow lobes and cones need a narrow
 * range) and phi, one more bin for everything below c_lo, bins expecting fewer than
 * CHI_SQUARE_MIN_EXPECTED samples pooled. */
static double chi_square_z(sampler sample, pdf_fn pdf, const void *ctx, vec3 w, double c_lo,
                           uint32_t seed) {
    static double observed[COS_BINS][PHI_BINS];
    double below = 0.0;
    for (int a = 0; a < COS_BINS; a++)
        for (int b = 0; b < PHI_BINS; b++) observed[a][b] = 0.0;
    /* a basis about w: any unit t orthogonal to it */
    vec3 t = fabsf(w.x) < 0.9f ? v3(1, 0, 0) : v3(0, 1, 0);
    t = v3_normalize(v3_sub(t, v3_scale(w, v3_dot(t, w))));
    vec3 b = v3_cross(w, t);
    uint32_t rng = rng_seed(seed, 0, 0);
    double dc = (1.0 - c_lo) / COS_BINS, dp = 2 * PI / PHI_BINS;
    for (int k = 0; k < SAMPLES; k++) {
        float u1 = rng_next(&rng), u2 = rng_next(&rng);
        vec3 d = sample(ctx, u1, u2);
        double c = v3_dot(d, w), phi = atan2(v3_dot(d, b), v3_dot(d, t));
        if (phi < 0) phi += 2 * PI;
        if (c < c_lo) {
            below += 1.0;
            continue;
        }
        int ci = (int)((c - c_lo) / dc), pi = (int)(phi / dp);
        ci = ci >= COS_BINS ? COS_BINS - 1 : ci;
        pi = pi < 0 ? 0 : pi >= PHI_BINS ? PHI_BINS - 1 : pi;
        observed[ci][pi] += 1.0;
    }
    chi_square c2 = chi_square_start(SAMPLES, below);
    for (int a = 0; a < COS_BINS; a++) {
        for (int bb = 0; bb < PHI_BINS; bb++) {
            /* the pdf integrated over the bin (d omega = d cos d phi) by 64 x 4 midpoints */
            double c0 = c_lo + a * dc, p0 = bb * dp, mass = 0.0;
            for (int i = 0; i < 64; i++)
                for (int j = 0; j < 4; j++)
                    mass += pdf(ctx, c0 + (i + 0.5) * dc / 64, p0 + (j + 0.5) * dp / 4);
            double expected = mass * dc * dp / 256.0 * SAMPLES;
            chi_square_bin(&c2, observed[a][bb], expected);
        }
    }
    return chi_square_result(c2);
}

typedef struct lobe_ctx {
    vec3 axis;
    float alpha, omc;
    double c_lo; /* the lowest cos theta binned */
} lobe_ctx;

static vec3 sample_cosine(const void *ctx, float u1, float u2) {
    const lobe_ctx *c = ctx;
    return cosine_direction(c->axis, u1, u2);
}
static double pdf_cosine(const void *ctx, double cos_t, double phi) {
    (void)ctx, (void)phi;
    return cos_t > 0 ? cos_t / PI : 0.0;
}
static double pdf_uniform_sphere(const void *ctx, double cos_t, double phi) {
    (void)ctx, (void)cos_t, (void)phi;
    return 1.0 / (4 * PI);
}
static vec3 sample_lobe(const void *ctx, float u1, float u2) {
    const lobe_ctx *c = ctx;
    return phong_lobe_direction(c->axis, c->alpha, u1, u2);
}
static double pdf_lobe(const void *ctx, double cos_t, double phi) {
    const lobe_ctx *c = ctx;
    (void)phi;
    return cos_t > 0 ? (c->alpha + 1.0) / (2 * PI) * pow(cos_t, c->alpha) : 0.0;
}
static double pdf_lobe_14(const void *ctx, double cos_t, double phi) {
    (void)ctx, (void)phi;
    return cos_t > 0 ? 15.0 / (2 * PI) * pow(cos_t, 14.0) : 0.0;
}
static vec3 sample_cone(const void *ctx, float u1, float u2) {
    const lobe_ctx *c = ctx;
    return cone_direction(c->axis, c->omc, u1, u2).wi;
}
static double pdf_cone(const void *ctx, double cos_t, double phi) {
    const lobe_ctx *c = ctx;
    (void)phi;
    return cos_t >= 1.0 - c->omc ? 1.0 / (2 * PI * c->omc) : 0.0;
}
static vec3 sample_area(const void *ctx, float u1, float u2) {
    (void)ctx;
    return sphere_area_direction(u1, u2);
}

/* Passes when the z score is below 4 (p about 3e-5 one-sided). */
static void expect_fit(const char *name, sampler s, pdf_fn pdf, const lobe_ctx *ctx, bool fits) {
    double z = chi_square_z(s, pdf, ctx, ctx->axis, ctx->c_lo, 7);
    CHECK(fits ? z < 4.0 : z > 10.0, "%s: chi-square z score %.2f", name, z);
}

/* The chi-square z score of triangle_area_point on the triangle (0,0,0) (1,0,0) (0,1,0), or with
 * wrong_warp the warp without its square root, over its n^2 congruent sub-triangles (equal areas:
 * each expects SAMPLES / n^2). */
static double triangle_chi_square_z(bool wrong_warp) {
    enum { N = 20 };
    static double observed[N][N][2];
    memset(observed, 0, sizeof observed);
    uint32_t rng = rng_seed(11, 0, 0);
    for (int k = 0; k < SAMPLES; k++) {
        float ua = rng_next(&rng), ub = rng_next(&rng);
        if (wrong_warp) ua *= ua;
        vec3 q = triangle_area_point(v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0), ua, ub);
        double x = q.x * N, y = q.y * N;
        int i = (int)x, j = (int)y;
        i = i < 0 ? 0 : i >= N ? N - 1 : i;
        j = j < 0 ? 0 : j >= N ? N - 1 : j;
        int down = (x - i) + (y - j) >= 1.0 || i + j >= N;
        if (i + j >= N) i = N - 1 - j; /* rounding past the hypotenuse */
        observed[i][j][down]++;
    }
    double chi2 = 0.0, expected = (double)SAMPLES / (N * N);
    int cells = 0;
    for (int i = 0; i < N; i++) {
        for (int j = 0; i + j < N; j++) {
            for (int down = 0; down < 2; down++) {
                if (down && i + j == N - 1) continue; /* the diagonal row has up cells only */
                double diff = observed[i][j][down] - expected;
                chi2 += diff * diff / expected;
                cells++;
            }
        }
    }
    return chi_square_z_of(chi2, cells - 1);
}

int main(void) {
    vec3 tilted = v3_normalize(v3(0.3f, -0.5f, 0.8f)), down = v3(0, 0, -1);
    lobe_ctx up = {v3(0, 0, 1), 0, 0, -1.0}, tilt = {tilted, 0, 0, -1.0};
    lobe_ctx under = {down, 0, 0, -1.0};
    expect_fit("cosine about +z", sample_cosine, pdf_cosine, &up, true);
    expect_fit("cosine about a tilted axis", sample_cosine, pdf_cosine, &tilt, true);
    expect_fit("cosine about -z (the basis's other branch)", sample_cosine, pdf_cosine, &under,
               true);
    float alphas[] = {0.0f, 1.0f, 12.5f, 200.0f};
    for (int k = 0; k < 4; k++) {
        /* bins over the cosines that hold all but about 1e-4 of the lobe */
        double c_lo = alphas[k] > 0.0f ? pow(1e-4, 1.0 / (alphas[k] + 1.0)) : 0.0;
        lobe_ctx c = {tilted, alphas[k], 0, c_lo > 0.0 ? 1.0 - 1.05 * (1.0 - c_lo) : -1.0};
        char name[64];
        snprintf(name, sizeof name, "Phong lobe alpha %g", (double)alphas[k]);
        expect_fit(name, sample_lobe, pdf_lobe, &c, true);
    }
    /* cones from a hemisphere down to one whose 1 - cos is 1e-6 of a radian-sized one */
    float sin2s[] = {0.999f, 0.5f, 0.01f};
    for (int k = 0; k < 3; k++) {
        float omc = cone_one_minus_cos(sin2s[k], 1.0f);
        lobe_ctx c = {tilted, 0, omc, 1.0 - 1.25 * omc};
        char name[64];
        snprintf(name, sizeof name, "sphere cone sin^2 %g", (double)sin2s[k]);
        expect_fit(name, sample_cone, pdf_cone, &c, true);
    }
    expect_fit("sphere area", sample_area, pdf_uniform_sphere, &up, true);
    double tz = triangle_chi_square_z(false), wrong = triangle_chi_square_z(true);
    CHECK(tz < 4.0, "triangle area: chi-square z score %.2f", tz);
    CHECK(wrong > 10.0, "power: a triangle warp without its square root: z score %.2f", wrong);
    /* the test rejects what is wrong: cosine samples against a uniform pdf, a lobe against
     * another exponent */
    expect_fit("power: cosine is not uniform", sample_cosine, pdf_uniform_sphere, &up, false);
    lobe_ctx c = {tilted, 12.5f, 0, 0.0};
    expect_fit("power: lobe 12.5 is not lobe 14", sample_lobe, pdf_lobe_14, &c, false);
    /* exact Fresnel: 0.04 head-on into glass of 1.5; at Brewster's angle (tan = 1.5) only the s
     * part, sin^2(i - t) / sin^2(i + t) halved; the same both ways through the interface; total
     * internal reflection past the critical angle */
    float eta = 1.0f / 1.5f, k0 = 1.0f - eta * eta * 0.0f;
    CHECK(fabsf(fresnel_dielectric(eta, 1.0f, k0) - 0.04f) < 1e-6f, "head-on %g",
          (double)fresnel_dielectric(eta, 1.0f, k0));
    double bi = atan(1.5), bt = asin(sin(bi) / 1.5), rs = sin(bi - bt) / sin(bi + bt);
    float cb = (float)cos(bi), kb = 1.0f - eta * eta * (1.0f - cb * cb);
    CHECK(fabs(fresnel_dielectric(eta, cb, kb) - 0.5 * rs * rs) < 1e-6, "Brewster %g vs %g",
          (double)fresnel_dielectric(eta, cb, kb), 0.5 * rs * rs);
    float ct = sqrtf(kb), back = 1.0f - 1.5f * 1.5f * (1.0f - ct * ct);
    CHECK(fabsf(fresnel_dielectric(1.5f, ct, back) - fresnel_dielectric(eta, cb, kb)) < 1e-6f,
          "reciprocal %g vs %g", (double)fresnel_dielectric(1.5f, ct, back),
          (double)fresnel_dielectric(eta, cb, kb));
    CHECK(fresnel_dielectric(1.5f, 0.5f, 1.0f - 2.25f * 0.75f) == 1.0f,
          "total internal reflection");
    CHECK(fabsf(power_heuristic(1.0f, 1.0f) - 0.5f) < 1e-7f &&
              power_heuristic(0.0f, 1.0f) == 0.0f && power_heuristic(2.0f, 0.0f) == 1.0f,
          "power heuristic");
    /* tiny cones: 1 - cos(theta_max) keeps its precision where 1 - sqrt(1 - s) loses it */
    float omc = cone_one_minus_cos(1e-10f, 1.0f);
    CHECK(fabsf(omc - 5e-11f) < 5e-11f * 1e-5f, "tiny cone 1 - cos %g", (double)omc);
    return check_summary("test_sampling");
}
