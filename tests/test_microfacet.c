/* test_microfacet.c: the GGX lobes of shaders/common/microfacet.h through bsdf.h: the visible
 * normals' sampling against the pdf bsdf_eval gives (chi-square over (cos theta, phi) about the
 * mirror direction, and the test's power: a wrong width is rejected), the sampled weight against
 * f cos / pdf evaluated apart and against its closed form F G2 / G1, reciprocity, D and the
 * visible normals normalized by quadrature, and furnaces: a white conductor's and a white pbr's
 * albedo never above 1, the sampled albedo equal to the one integrated numerically, and Kulla and
 * Conty's multiple scattering (test_compensation). */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>

#include "check.h"
#include "chi_square.h"
#include "common/bsdf.h"
#include "common/rng.h"
#include "render/ggx_albedo.h"

#define PI 3.14159265358979323846
#define COS_BINS 24
#define PHI_BINS 24
#define SAMPLES 400000

/* A material seen from wo at normal +z, binned about axis w over cos theta in [c_lo, 1]. */
typedef struct lobe_case {
    bsdf_material m;
    vec3 wo, w, t, b;
    double c_lo;
    float wrong_alpha; /* above 0: the pdf of this width instead (the test's power) */
    int qc, qp;        /* the midpoints a bin's pdf is integrated over, in cos and in phi */
} lobe_case;

static const vec3 up = {0.0f, 0.0f, 1.0f};

static bsdf_material material_of(int kind, float r, float g, float b, float metallic, float alpha) {
    bsdf_material m;
    m.kind = kind;
    m.color = v3(r, g, b);
    m.ks = metallic;
    m.alpha = alpha;
    m.ior = 1.5f;
    return m;
}

/* The unit vector at (cos_t, phi) about c's axis. */
static vec3 direction_at(const lobe_case *c, double cos_t, double phi) {
    double s = sqrt(fmax(0.0, 1.0 - cos_t * cos_t));
    vec3 d =
        v3_add(v3_add(v3_scale(c->t, (float)(s * cos(phi))), v3_scale(c->b, (float)(s * sin(phi)))),
               v3_scale(c->w, (float)cos_t));
    return v3_normalize(d);
}

static double pdf_at(const lobe_case *c, double cos_t, double phi) {
    bsdf_material m = c->m;
    if (c->wrong_alpha > 0.0f) m.alpha = c->wrong_alpha;
    return bsdf_eval(m, 0.0f, up, up, direction_at(c, cos_t, phi), c->wo).pdf;
}

/* The chi-square z score (Wilson-Hilferty) of microfacet_direction's samples against pdf_at, as
 * tests/test_sampling.c's: sparse bins and everything below c_lo pooled. */
static double chi_square_z(const lobe_case *c, uint32_t seed) {
    static double observed[COS_BINS][PHI_BINS];
    double below = 0.0;
    for (int a = 0; a < COS_BINS; a++)
        for (int b = 0; b < PHI_BINS; b++) observed[a][b] = 0.0;
    uint32_t rng = rng_seed(seed, 0, 0);
    double dc = (1.0 - c->c_lo) / COS_BINS, dp = 2 * PI / PHI_BINS;
    for (int k = 0; k < SAMPLES; k++) {
        float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
        vec3 d = microfacet_direction(c->m, up, c->wo, us, u1, u2);
        double cs = v3_dot(d, c->w), phi = atan2(v3_dot(d, c->b), v3_dot(d, c->t));
        if (phi < 0) phi += 2 * PI;
        if (!(cs >= c->c_lo) || !(d.z > 0.0f)) { /* below the surface: pdf 0 there, pooled */
            below += 1.0;
            continue;
        }
        int ci = (int)((cs - c->c_lo) / dc), pi = (int)(phi / dp);
        ci = ci >= COS_BINS ? COS_BINS - 1 : ci;
        pi = pi < 0 ? 0 : pi >= PHI_BINS ? PHI_BINS - 1 : pi;
        observed[ci][pi] += 1.0;
    }
    chi_square c2 = chi_square_start(SAMPLES, below);
    for (int a = 0; a < COS_BINS; a++) {
        for (int bb = 0; bb < PHI_BINS; bb++) {
            double c0 = c->c_lo + a * dc, p0 = bb * dp, mass = 0.0;
            for (int i = 0; i < c->qc; i++)
                for (int j = 0; j < c->qp; j++)
                    mass += pdf_at(c, c0 + (i + 0.5) * dc / c->qc, p0 + (j + 0.5) * dp / c->qp);
            double expected = mass * dc * dp / (c->qc * c->qp) * SAMPLES;
            chi_square_bin(&c2, observed[a][bb], expected);
        }
    }
    return chi_square_result(c2);
}

/* A case of material m seen at polar angle theta_o, binned about wo's mirror image. */
static lobe_case case_of(bsdf_material m, double theta_o) {
    lobe_case c;
    c.m = m;
    c.wo = v3((float)sin(theta_o), 0.0f, (float)cos(theta_o));
    c.w = v3(-c.wo.x, -c.wo.y, c.wo.z);
    c.t = v3_normalize(v3_sub(v3(0, 1, 0), v3_scale(c.w, v3_dot(v3(0, 1, 0), c.w))));
    c.b = v3_cross(c.w, c.t);
    /* bins over the cosines holding nearly all of the lobe: about 2 alpha wide about w */
    double spread = 60.0 * (double)m.alpha * m.alpha;
    c.c_lo = spread > 1.0 ? -1.0 : 1.0 - spread;
    c.wrong_alpha = 0.0f;
    /* a narrow lobe seen at a grazing angle has ridges that need finer quadrature */
    bool ridged = theta_o > 1.2 && m.alpha < 0.01f;
    c.qc = ridged ? 256 : 64;
    c.qp = ridged ? 64 : 16;
    return c;
}

static void test_sampling_fits(void) {
    float alphas[] = {0.0025f, 0.0625f, 0.25f, 0.5625f, 1.0f};
    double thetas[] = {0.0, 0.7, 1.4};
    for (int a = 0; a < 5; a++) {
        for (int t = 0; t < 3; t++) {
            lobe_case c =
                case_of(material_of(TZ_MATERIAL_CONDUCTOR, 1, 1, 1, 0, alphas[a]), thetas[t]);
            double z = chi_square_z(&c, 7u + (uint32_t)a);
            CHECK(z < 4.0, "conductor alpha %g theta %g: chi-square z %.2f", (double)alphas[a],
                  thetas[t], z);
            lobe_case p =
                case_of(material_of(TZ_MATERIAL_PBR, 0.8f, 0.5f, 0.2f, 0.3f, alphas[a]), thetas[t]);
            z = chi_square_z(&p, 19u + (uint32_t)a);
            CHECK(z < 4.0, "pbr alpha %g theta %g: chi-square z %.2f", (double)alphas[a], thetas[t],
                  z);
        }
    }
    lobe_case wrong = case_of(material_of(TZ_MATERIAL_CONDUCTOR, 1, 1, 1, 0, 0.25f), 0.7);
    wrong.wrong_alpha = 0.3f;
    double z = chi_square_z(&wrong, 5u);
    CHECK(z > 10.0, "power: alpha 0.25 samples against alpha 0.3's pdf: z %.2f", z);
}

/* A direction uniform on the sphere. */
static vec3 uniform_direction(uint32_t *rng) {
    float z = 1.0f - 2.0f * rng_next(rng), phi = 2.0f * (float)PI * rng_next(rng);
    float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    return v3(r * cosf(phi), r * sinf(phi), z);
}

/* The sampled weight is f cos / pdf of bsdf_eval at the sampled direction, and for the conductor
 * the closed form F ci (co + So) / (So ci + Si co) of the visible normals (F G2 / G1). */
static void test_weights_and_reciprocity(void) {
    uint32_t rng = rng_seed(3, 0, 0);
    int worst_weight = 0, worst_closed = 0, worst_recip = 0;
    for (int k = 0; k < 20000; k++) {
        float alpha = 0.002f + rng_next(&rng);
        int pbr = k & 1;
        bsdf_material m = material_of(pbr ? TZ_MATERIAL_PBR : TZ_MATERIAL_CONDUCTOR, 0.9f, 0.6f,
                                      0.3f, rng_next(&rng), alpha);
        vec3 wo = uniform_direction(&rng), wi = uniform_direction(&rng);
        wo.z = fabsf(wo.z);
        float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
        bsdf_sample s = bsdf_sample_lobe(m, 0.0f, up, up, wo, us, u1, u2);
        if (s.ok) {
            bsdf_value v = bsdf_eval(m, 0.0f, up, up, s.wi, wo);
            vec3 w = v3_scale(v.f, v.f_scale / v.pdf);
            worst_weight += !(fabsf(w.x - s.weight.x) <= 1e-6f * fabsf(w.x) &&
                              fabsf(s.pdf - v.pdf) <= 1e-6f * v.pdf);
            if (!pbr) { /* the single-scattering part over the GGX lobe's pdf */
                double a2 = (double)alpha * alpha, ci = s.wi.z, co = wo.z;
                double so = sqrt(a2 * (1 - co * co) + co * co),
                       si = sqrt(a2 * (1 - ci * ci) + ci * ci);
                vec3 h = v3_normalize(v3_add(wo, s.wi));
                double ggx_pdf = ggx_d(h, (float)a2) / (2 * (co + so));
                float eavg = ggx_albedo_avg(alpha);
                double ms = ggx_ms_lobe(ggx_albedo(wo.z, alpha), ggx_albedo(s.wi.z, alpha), eavg);
                double single = (v.f.x - ggx_ms_fresnel(0.9f, eavg) * ms) * ci / ggx_pdf;
                double closed = 0.9 * ci * (co + so) / (so * ci + si * co);
                worst_closed += !(fabs(single - closed) <= 2e-4 * closed + 1e-6);
            }
        }
        wi.z = fabsf(wi.z);
        vec3 a = bsdf_f(m, up, wi, wo), b = bsdf_f(m, up, wo, wi);
        worst_recip += !(fabsf(a.y - b.y) <= 1e-5f * fabsf(a.y) + 1e-30f);
    }
    CHECK(worst_weight == 0, "%d samples' weights differ from f cos / pdf", worst_weight);
    CHECK(worst_closed == 0, "%d conductor weights differ from F G2 / G1", worst_closed);
    CHECK(worst_recip == 0, "%d pairs break reciprocity", worst_recip);
}

/* Quadrature over the hemisphere by (cos theta, phi) midpoints of fn(direction), dense about
 * the normal, where the half vectors of narrow lobes are. */
typedef double (*hemisphere_fn)(const void *ctx, vec3 w);
static double integrate(hemisphere_fn fn, const void *ctx, int n) {
    double sum = 0.0;
    for (int i = 0; i < n; i++) {
        /* cos theta = 1 - x^4 */
        double x0 = (double)i / n, x1 = (double)(i + 1) / n;
        double c0 = 1 - x1 * x1 * x1 * x1, c1 = 1 - x0 * x0 * x0 * x0;
        for (int j = 0; j < 4 * n / 8; j++) {
            double c = 0.5 * (c0 + c1), phi = (j + 0.5) * 2 * PI / (4 * n / 8);
            double s = sqrt(fmax(0.0, 1 - c * c));
            vec3 w = v3((float)(s * cos(phi)), (float)(s * sin(phi)), (float)c);
            sum += fn(ctx, w) * (c1 - c0) * 2 * PI / (4 * n / 8);
        }
    }
    return sum;
}

typedef struct albedo_case {
    bsdf_material m;
    vec3 wo;
} albedo_case;

static double d_cos(const void *ctx, vec3 h) {
    const albedo_case *c = ctx;
    double a2 = (double)c->m.alpha * c->m.alpha;
    return ggx_d(h, (float)a2) * h.z;
}
static double visible(const void *ctx, vec3 h) {
    const albedo_case *c = ctx;
    double a2 = (double)c->m.alpha * c->m.alpha, co = c->wo.z;
    double so = sqrt(a2 * (1 - co * co) + co * co), g1 = 2 * co / (co + so);
    double vh = v3_dot(c->wo, h);
    return vh > 0 ? g1 * vh * ggx_d(h, (float)a2) / co : 0.0;
}
/* f cos at the reflection of wo about half vector h, times the Jacobian 4 wo.h of the change of
 * variables from wi to h. */
static double f_cos_by_half(const void *ctx, vec3 h) {
    const albedo_case *c = ctx;
    double vh = v3_dot(c->wo, h);
    vec3 wi = v3_normalize(v3_sub(v3_scale(h, 2.0f * (float)vh), c->wo));
    if (!(vh > 0.0) || !(wi.z > 0.0f)) return 0.0;
    vec3 f = bsdf_f(c->m, up, wi, c->wo);
    return (f.x + f.y + f.z) / 3.0 * wi.z * 4.0 * vh;
}

/* f cos of the single scattering alone (f less Kulla and Conty's lobe) of a white conductor,
 * times the Jacobian as f_cos_by_half. */
static double single_cos_by_half(const void *ctx, vec3 h) {
    const albedo_case *c = ctx;
    double vh = v3_dot(c->wo, h);
    vec3 wi = v3_normalize(v3_sub(v3_scale(h, 2.0f * (float)vh), c->wo));
    if (!(vh > 0.0) || !(wi.z > 0.0f)) return 0.0;
    float alpha = c->m.alpha, eavg = ggx_albedo_avg(alpha);
    double ms = ggx_ms_lobe(ggx_albedo(c->wo.z, alpha), ggx_albedo(wi.z, alpha), eavg);
    return (bsdf_f(c->m, up, wi, c->wo).y - ms) * wi.z * 4.0 * vh;
}

/* Multiple scattering: a white conductor's albedo is at least 0.99 at every roughness and angle;
 * without the compensation lobe it is the table's E (the loss 1 - E that the lobe returns),
 * checked against the single scattering integrated here; a coloured conductor's is Kulla and
 * Conty's F E + F_ms (1 - E) with F_ms = F^2 E_avg / (1 - F (1 - E_avg)), between F E and F. */
static void test_compensation(void) {
    float roughness[] = {0.05f, 0.25f, 0.5f, 0.75f, 1.0f};
    double thetas[] = {0.0, 0.8, 1.45};
    for (int r = 0; r < 5; r++) {
        float alpha = roughness[r] * roughness[r];
        for (int t = 0; t < 3; t++) {
            vec3 wo = v3((float)sin(thetas[t]), 0.0f, (float)cos(thetas[t]));
            albedo_case c = {material_of(TZ_MATERIAL_CONDUCTOR, 1, 1, 1, 0, alpha), wo};
            double albedo = integrate(f_cos_by_half, &c, 2000);
            double single = integrate(single_cos_by_half, &c, 2000);
            double e = ggx_albedo(wo.z, alpha), eavg = ggx_albedo_avg(alpha);
            printf(
                "roughness %.2f theta %.2f: white conductor albedo %.5f, single scattering "
                "%.5f, table E %.5f\n",
                (double)roughness[r], thetas[t], albedo, single, e);
            CHECK(albedo >= 0.99 && albedo <= 1.0 + 2e-3,
                  "roughness %g theta %g: compensated white albedo %.5f", (double)roughness[r],
                  thetas[t], albedo);
            CHECK(fabs(single - e) < 2e-3, "roughness %g theta %g: single scattering %.5f, E %.5f",
                  (double)roughness[r], thetas[t], single, e);
            double tint[3] = {0.9, 0.6, 0.3};
            c.m = material_of(TZ_MATERIAL_CONDUCTOR, 0.9f, 0.6f, 0.3f, 0, alpha);
            for (int k = 0; k < 3; k++) {
                double f = tint[k], fms = f * f * eavg / (1 - f * (1 - eavg));
                double want = f * single + fms * (1 - e);
                c.m.color = v3((float)f, (float)f, (float)f);
                double got = integrate(f_cos_by_half, &c, 2000);
                CHECK(fabs(got - want) < 2e-3 && got <= f + 2e-3 && got >= f * single - 2e-3,
                      "roughness %g theta %g tint %g: albedo %.5f, Kulla-Conty %.5f",
                      (double)roughness[r], thetas[t], f, got, want);
            }
        }
    }
}

/* D and the visible normals integrate to 1; a white conductor's and pbr's albedo (f cos
 * integrated) is at most 1, and the mean sampled weight matches it. */
static void test_furnace(void) {
    float roughness[] = {0.05f, 0.25f, 0.5f, 0.75f, 1.0f};
    double thetas[] = {0.0, 0.8, 1.45};
    for (int r = 0; r < 5; r++) {
        for (int t = 0; t < 3; t++) {
            float alpha = roughness[r] * roughness[r];
            albedo_case c = {material_of(TZ_MATERIAL_CONDUCTOR, 1, 1, 1, 0, alpha),
                             v3((float)sin(thetas[t]), 0.0f, (float)cos(thetas[t]))};
            int n = 2000;
            double dn = integrate(d_cos, &c, n), vn = integrate(visible, &c, n);
            CHECK(fabs(dn - 1.0) < 2e-3 && fabs(vn - 1.0) < 2e-3,
                  "roughness %g theta %g: D integrates to %.5f, visible normals to %.5f",
                  (double)roughness[r], thetas[t], dn, vn);
            for (int pbr = 0; pbr < 2; pbr++) {
                if (pbr) c.m = material_of(TZ_MATERIAL_PBR, 1, 1, 1, 0, alpha);
                double albedo = integrate(f_cos_by_half, &c, n);
                uint32_t rng = rng_seed(17, (uint32_t)r, (uint32_t)t);
                double sum = 0.0, sum2 = 0.0;
                int m = 200000;
                for (int k = 0; k < m; k++) {
                    float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
                    bsdf_sample s = bsdf_sample_lobe(c.m, 0.0f, up, up, c.wo, us, u1, u2);
                    double w = s.ok ? (s.weight.x + s.weight.y + s.weight.z) / 3.0 : 0.0;
                    sum += w;
                    sum2 += w * w;
                }
                double mean = sum / m, err = sqrt(fmax(sum2 / m - mean * mean, 0.0) / m);
                CHECK(albedo <= 1.0 + 2e-3 && mean <= 1.0 + 4 * err,
                      "%s roughness %g theta %g: albedo %.5f, sampled %.5f +- %.5f",
                      pbr ? "pbr" : "conductor", (double)roughness[r], thetas[t], albedo, mean,
                      err);
                CHECK(fabs(mean - albedo) < 4 * err + 3e-3,
                      "%s roughness %g theta %g: sampled albedo %.5f +- %.5f, integrated %.5f",
                      pbr ? "pbr" : "conductor", (double)roughness[r], thetas[t], mean, err,
                      albedo);
            }
        }
    }
}

/* Roughness towards 0 converges to the delta mirror: at the smallest width packed the samples
 * weigh the tint on average (to 2e-3), and all but GGX's tails (about 4% beyond 0.01 rad at this
 * width) lie within 0.01 rad of the mirror direction. */
static void test_towards_delta(void) {
    uint32_t rng = rng_seed(23, 0, 0);
    int astray = 0, n = 20000;
    double sum = 0.0;
    bsdf_material m = material_of(TZ_MATERIAL_CONDUCTOR, 0.9f, 0.8f, 0.7f, 0.0f, TZ_GGX_MIN_ALPHA);
    for (int k = 0; k < n; k++) {
        float theta = 1.3f * rng_next(&rng), phi = 6.28f * rng_next(&rng);
        vec3 wo = v3(sinf(theta) * cosf(phi), sinf(theta) * sinf(phi), cosf(theta));
        vec3 mirror = v3(-wo.x, -wo.y, wo.z);
        float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
        bsdf_sample s = bsdf_sample_lobe(m, 0.0f, up, up, wo, us, u1, u2);
        astray += !(s.ok && v3_dot(s.wi, mirror) > cosf(0.01f));
        sum += s.ok ? s.weight.x : 0.0;
    }
    CHECK(astray < n / 16 && fabs(sum / n - 0.9) < 2e-3,
          "alpha %g: %d of %d samples beyond 0.01 rad of the mirror direction, mean weight %.5f "
          "for a tint of 0.9",
          (double)TZ_GGX_MIN_ALPHA, astray, n, sum / n);
}

int main(void) {
    ggx_albedo_prepare();
    test_towards_delta();
    test_sampling_fits();
    test_weights_and_reciprocity();
    test_furnace();
    test_compensation();
    return check_summary("test_microfacet");
}
