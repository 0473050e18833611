/* test_dielectric.c: rough glass (shaders/common/dielectric.h) through bsdf.h: its sampling
 * against the pdf bsdf_eval gives over the whole sphere (chi-square, reflection and transmission
 * together, and the test's power), the sampled weight against f |cos| / pdf evaluated apart and
 * against its closed form G2 / G1, the albedo of one interface from either side and a rough glass
 * ball in a white furnace never above 1, roughness 0 the delta glass's bits and small roughness
 * its image, point lights through it, CPU = Vulkan bit for bit, and the key's range. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "chi_square.h"
#include "common/bsdf.h"
#include "common/rng.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"

#define PI 3.14159265358979323846
#define COS_BINS 64
#define PHI_BINS 64
#define QUAD 24
#define SAMPLES 400000

static const vec3 up = {0.0f, 0.0f, 1.0f};

static bsdf_material glass_of(float eta, float alpha) {
    bsdf_material m;
    m.kind = TZ_MATERIAL_DIELECTRIC;
    m.color = v3(1.0f, 1.0f, 1.0f);
    m.ks = 0.0f;
    m.alpha = alpha;
    m.ior = eta;
    return m;
}

/* The unit vector at (cos theta, phi) about +z. */
static vec3 sphere_at(double cos_t, double phi) {
    double s = sqrt(fmax(0.0, 1.0 - cos_t * cos_t));
    return v3((float)(s * cos(phi)), (float)(s * sin(phi)), (float)cos_t);
}

/* The chi-square z score (Wilson-Hilferty, as tests/test_microfacet.c's) of the directions
 * bsdf_sample_lobe draws for m seen from wo against pdf_m's pdf over the sphere's (cos theta,
 * phi) bins; sparse bins and the samples it drops pooled. */
static double chi_square_z(bsdf_material m, bsdf_material pdf_m, vec3 wo, uint32_t seed) {
    static double observed[COS_BINS][PHI_BINS];
    memset(observed, 0, sizeof observed);
    double dropped = 0.0;
    uint32_t rng = rng_seed(seed, 0, 0);
    double dc = 2.0 / COS_BINS, dp = 2 * PI / PHI_BINS;
    for (int k = 0; k < SAMPLES; k++) {
        float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
        bsdf_sample s = bsdf_sample_lobe(m, 0.0f, up, up, wo, us, u1, u2);
        if (!s.ok) {
            dropped += 1.0;
            continue;
        }
        double phi = atan2(s.wi.y, s.wi.x);
        if (phi < 0) phi += 2 * PI;
        int ci = (int)((s.wi.z + 1.0) / dc), pi = (int)(phi / dp);
        ci = ci < 0 ? 0 : ci >= COS_BINS ? COS_BINS - 1 : ci;
        pi = pi < 0 ? 0 : pi >= PHI_BINS ? PHI_BINS - 1 : pi;
        observed[ci][pi] += 1.0;
    }
    chi_square c2 = chi_square_start(SAMPLES, dropped);
    for (int a = 0; a < COS_BINS; a++) {
        for (int b = 0; b < PHI_BINS; b++) {
            double c0 = -1.0 + a * dc, p0 = b * dp, mass = 0.0;
            for (int i = 0; i < QUAD; i++)
                for (int j = 0; j < QUAD; j++) {
                    vec3 wi = sphere_at(c0 + (i + 0.5) * dc / QUAD, p0 + (j + 0.5) * dp / QUAD);
                    mass += bsdf_eval(pdf_m, 0.0f, up, up, wi, wo).pdf;
                }
            double expected = mass * dc * dp / (QUAD * QUAD) * SAMPLES;
            chi_square_bin(&c2, observed[a][b], expected);
        }
    }
    return chi_square_result(c2);
}

static void test_sampling_fits(void) {
    /* widths whose lobes the sphere's bins resolve (roughness 0.5 to 1) */
    float alphas[] = {0.25f, 0.5625f, 1.0f};
    float etas[] = {1.5f, 1.0f / 1.5f};
    double thetas[] = {0.5, 0.9, 1.4};
    for (int a = 0; a < 3; a++)
        for (int e = 0; e < 2; e++)
            for (int t = 0; t < 3; t++) {
                bsdf_material m = glass_of(etas[e], alphas[a]);
                vec3 wo = sphere_at(cos(thetas[t]), 0.3);
                double z = chi_square_z(m, m, wo, 11u + (uint32_t)(a * 6 + e * 3 + t));
                CHECK(z < 4.0, "alpha %g eta %g theta %g: chi-square z %.2f", (double)alphas[a],
                      (double)etas[e], thetas[t], z);
            }
    bsdf_material m = glass_of(1.5f, 0.25f), wrong = glass_of(1.5f, 0.3f);
    double z = chi_square_z(m, wrong, sphere_at(cos(0.9), 0.3), 5u);
    CHECK(z > 10.0, "power: alpha 0.25 samples against alpha 0.3's pdf: z %.2f", z);
    wrong = glass_of(1.4f, 0.25f);
    z = chi_square_z(m, wrong, sphere_at(cos(0.9), 0.3), 6u);
    CHECK(z > 10.0, "power: eta 1.5 samples against eta 1.4's pdf: z %.2f", z);
}

/* A direction uniform on the sphere. */
static vec3 uniform_direction(uint32_t *rng) {
    float z = 1.0f - 2.0f * rng_next(rng), phi = 2.0f * (float)PI * rng_next(rng);
    float r = sqrtf(fmaxf(0.0f, 1.0f - z * z));
    return v3(r * cosf(phi), r * sinf(phi), z);
}

/* The sampled weight is f |cos| / pdf of bsdf_eval at the sampled direction and the closed form
 * of the visible normals, G2 / G1 = |ci| (co + so) / (so |ci| + si co), reflected or refracted. */
static void test_weights(void) {
    uint32_t rng = rng_seed(3, 0, 0);
    int worst_weight = 0, worst_closed = 0, taken = 0, below = 0;
    for (int k = 0; k < 40000; k++) {
        float alpha = 0.002f + rng_next(&rng);
        float eta = k & 1 ? 1.0f + rng_next(&rng) : 1.0f / (1.0f + rng_next(&rng));
        bsdf_material m = glass_of(eta, alpha);
        m.color = v3(0.9f, 0.6f, 0.3f);
        vec3 wo = uniform_direction(&rng);
        wo.z = fabsf(wo.z);
        float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
        bsdf_sample s = bsdf_sample_lobe(m, 0.0f, up, up, wo, us, u1, u2);
        if (!s.ok) continue;
        taken++;
        below += s.wi.z < 0.0f;
        bsdf_value v = bsdf_eval(m, 0.0f, up, up, s.wi, wo);
        vec3 w = v3_scale(v.f, v.f_scale / v.pdf);
        worst_weight += !(fabsf(w.x - s.weight.x) <= 1e-6f * fabsf(w.x) &&
                          fabsf(s.pdf - v.pdf) <= 1e-6f * v.pdf);
        double a2 = (double)alpha * alpha, ci = fabs((double)s.wi.z), co = wo.z;
        double so = sqrt(a2 * (1 - co * co) + co * co), si = sqrt(a2 * (1 - ci * ci) + ci * ci);
        double closed = 0.9 * ci * (co + so) / (so * ci + si * co);
        worst_closed += !(fabs(s.weight.x - closed) <= 2e-4 * closed + 1e-6);
    }
    CHECK(taken > 30000 && below > 5000, "%d samples taken, %d transmitted", taken, below);
    CHECK(worst_weight == 0, "%d sampled weights differ from f |cos| / pdf", worst_weight);
    CHECK(worst_closed == 0, "%d sampled weights differ from G2 / G1", worst_closed);
}

/* One interface's albedo (reflected plus transmitted, the mean sampled weight) from either side
 * at each roughness and angle: never above 1 within 4 standard errors; the figures printed. */
static void test_interface_albedo(void) {
    float roughness[] = {0.05f, 0.25f, 0.5f, 0.75f, 1.0f};
    double thetas[] = {0.0, 0.8, 1.4};
    for (int r = 0; r < 5; r++) {
        printf("roughness %.2f albedo (eta 1.5 | 1/1.5, theta 0 0.8 1.4):", (double)roughness[r]);
        for (int e = 0; e < 2; e++)
            for (int t = 0; t < 3; t++) {
                bsdf_material m = glass_of(e ? 1.0f / 1.5f : 1.5f, roughness[r] * roughness[r]);
                vec3 wo = sphere_at(cos(thetas[t]), 0.0);
                uint32_t rng = rng_seed(41u + (uint32_t)r, (uint32_t)e, (uint32_t)t);
                double sum = 0.0, sum2 = 0.0;
                int n = 200000;
                for (int k = 0; k < n; k++) {
                    float us = rng_next(&rng), u1 = rng_next(&rng), u2 = rng_next(&rng);
                    bsdf_sample s = bsdf_sample_lobe(m, 0.0f, up, up, wo, us, u1, u2);
                    double w = s.ok ? s.weight.x : 0.0;
                    sum += w, sum2 += w * w;
                }
                double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / n);
                printf(" %.4f", mean);
                CHECK(mean <= 1.0 + 4.0 * se, "roughness %g eta side %d theta %g: albedo %.5f",
                      (double)roughness[r], e, thetas[t], mean);
                CHECK(mean > 0.4, "roughness %g eta side %d theta %g: albedo %.5f",
                      (double)roughness[r], e, thetas[t], mean);
            }
        printf("\n");
    }
}

/* Renders text on the CPU into f (true on success). */
static bool render_text(const char *text, film *f) {
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    bool ok = render_on(false, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* The mean of channel 0 over f's pixels. */
static double film_mean(const film *f) {
    double sum = 0.0;
    for (int k = 0; k < f->width * f->height; k++) sum += f->accum[k * 4] / f->accum[k * 4 + 3];
    return sum / (f->width * f->height);
}

/* A clear rough glass ball filling the view in a white furnace (background 1): every pixel at
 * most 1, each path's weight a product of G2 / G1; the loss of single scattering printed. */
static void test_furnace(void) {
    float roughness[] = {0.0f, 0.05f, 0.25f, 0.5f, 0.75f, 1.0f};
    printf("furnace ball:");
    for (int r = 0; r < 6; r++) {
        char text[512];
        snprintf(text, sizeof text,
                 "camera position 0 0 -3\nplane width 0.5 height 0.5 pixel 0.0625\n"
                 "sphere refractive center 0 0 0 radius 1 roughness %g\nbackground 1 1 1\n"
                 "render mode path samples 256 bounces 64 roulette off\n",
                 (double)roughness[r]);
        film f = {0};
        CHECK(render_text(text, &f), "roughness %g: render failed", (double)roughness[r]);
        if (!f.accum) continue;
        double mean = film_mean(&f), most = 0.0;
        for (int k = 0; k < f.width * f.height; k++)
            most = fmax(most, f.accum[k * 4] / f.accum[k * 4 + 3]);
        printf(" %g: %.4f", (double)roughness[r], mean);
        CHECK(most <= 1.0 + 1e-5, "roughness %g: a pixel at %.6f", (double)roughness[r], most);
        CHECK(mean > (r ? 0.3 : 0.99), "roughness %g: mean %.5f", (double)roughness[r], mean);
        film_free(&f);
    }
    printf("\n");
}

/* A glass ball filling the view before a wall of lit and dark stripes: `%s` its roughness key. */
#define GLASS_SCENE                                                                      \
    "camera position 0 0 -4\nplane width 0.5 height 0.5 pixel 0.03125\n"                 \
    "quad lambertian v0 -9 -0.6 3  v1 9 -0.6 3  v2 9 -0.2 3  v3 -9 -0.2 3  color 0 0 0 " \
    "emission 1 1 1\n"                                                                   \
    "quad lambertian v0 -9 0.2 3  v1 9 0.2 3  v2 9 0.6 3  v3 -9 0.6 3  color 0 0 0 "     \
    "emission 1 1 1\n"                                                                   \
    "sphere refractive center 0 0 0 radius 1 %s\n"                                       \
    "render mode path samples %d bounces 6 seed 2\n"
/* Renders GLASS_SCENE with rough (a key or nothing) into f. */
static bool render_glass(const char *rough, int samples, film *f) {
    char text[1024];
    snprintf(text, sizeof text, GLASS_SCENE, rough, samples);
    return render_text(text, f);
}

/* The mean absolute difference of two films' channel 0 means. */
static double film_distance(const film *a, const film *b) {
    double sum = 0.0;
    for (int k = 0; k < a->width * a->height; k++)
        sum += fabs(a->accum[k * 4] / a->accum[k * 4 + 3] - b->accum[k * 4] / b->accum[k * 4 + 3]);
    return sum / (a->width * a->height);
}

/* `roughness 0` is the delta glass, bit for bit; a small roughness comes near its image, nearer
 * than a larger one. */
static void test_delta_limit(void) {
    film delta = {0}, zero = {0}, small = {0}, large = {0};
    CHECK(render_glass("", 512, &delta) && render_glass("roughness 0", 512, &zero) &&
              render_glass("roughness 0.03", 512, &small) &&
              render_glass("roughness 0.3", 512, &large),
          "renders failed");
    if (delta.accum && zero.accum && small.accum && large.accum) {
        size_t bytes = (size_t)delta.width * delta.height * 4 * sizeof(float);
        CHECK(!memcmp(delta.accum, zero.accum, bytes), "roughness 0 is not the delta glass");
        double ds = film_distance(&delta, &small), dl = film_distance(&delta, &large);
        printf("distance to the delta glass: roughness 0.03 %.5f, 0.3 %.5f\n", ds, dl);
        CHECK(ds < 0.1 * dl, "roughness 0.03 %.5f not nearer the delta glass than 0.3 %.5f", ds,
              dl);
    }
    film_free(&delta);
    film_free(&zero);
    film_free(&small);
    film_free(&large);
}

/* CPU = Vulkan bit for bit on rough glass, lit by an emitter and a point light, both modes. */
static void test_back_ends_agree(void) {
    if (vk_context_device_count() == 0) {
        printf("test_dielectric: no Vulkan device, back ends not compared\n");
        return;
    }
    expect_back_ends_agree(
        "camera position 0 1 -5\nplane width 2 height 1.5 pixel 0.1\n"
        "quad lambertian v0 -9 -1 -9  v1 -9 -1 9  v2 9 -1 9  v3 9 -1 -9  color 0.6 0.5 0.4\n"
        "sphere lambertian center 0 4 0 radius 1 color 0 0 0 emission 6 6 6\n"
        "light position 2 3 -2 power 20\n"
        "sphere refractive center -0.6 0 0.5 radius 0.8 roughness 0.3\n"
        "sphere refractive center 0.9 -0.4 -0.5 radius 0.5 ior 1.3 roughness 0.7 color 1 0.8 "
        "0.8\nrender mode path samples 8 seed 5\n");
}

/* A point light inside a rough glass ball lights it through its surface in both modes, alike on
 * both back ends (before, a light below the surface gave nothing). */
static void test_point_light_through(void) {
    const char *text =
        "camera position 0 0 -4\nplane width 0.5 height 0.5 pixel 0.0625\n"
        "sphere refractive center 0 0 0 radius 1 roughness 0.5\n"
        "light position 0 0 0 power 10\nrender samples 4 seed 3\n";
    for (int mode = 0; mode < 2; mode++) {
        scene s;
        render_opts o;
        film f = {0};
        if (!parse_scene_text(text, &s, &o)) continue;
        o.mode = mode ? RENDER_MODE_PATH : RENDER_MODE_REPORT;
        CHECK(render_on(false, &s, &o, &f), "mode %d: render failed", mode);
        if (f.accum) CHECK(film_mean(&f) > 0.1, "mode %d: mean %.5f", mode, film_mean(&f));
        film_free(&f);
        scene_free(&s);
    }
    if (vk_context_device_count() > 0) expect_back_ends_agree(text);
}

static void test_bad_keys(void) {
    expect_parse_error("sphere refractive center 0 0 0 radius 1 roughness 1.5\n", 1, 51, "[0, 1]");
    expect_parse_error("sphere refractive center 0 0 0 radius 1 roughness -0.1\n", 1, 51, "[0, 1]");
}

int main(void) {
    CHECK_CASE(test_bad_keys);
    CHECK_CASE(test_weights);
    CHECK_CASE(test_sampling_fits);
    CHECK_CASE(test_interface_albedo);
    CHECK_CASE(test_furnace);
    CHECK_CASE(test_delta_limit);
    CHECK_CASE(test_back_ends_agree);
    CHECK_CASE(test_point_light_through);
    return check_summary("test_dielectric");
}
