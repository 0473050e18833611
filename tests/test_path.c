/* test_path.c: closed-form and statistical checks of path mode (DESIGN section 3.2), run on the
 * back end named by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 when no device exists). Means are
 * compared with 4.5 standard errors of their pixels (independent samples), so a test fails by
 * chance about once in 150,000 runs and always when a term is missing or counted twice. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"

#define PI 3.14159265358979323846
#define SIGMAS 4.5

static bool use_vulkan;
/* Every case runs with each sampler: both estimate the same expectations. */
static render_sampler sampler_under_test;

/* Renders scene text (its own settings, strategy as given) into f; false on any error. */
static bool render_text(const char *text, path_strategy strategy, film *f) {
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    o.strategy = strategy;
    o.sampler = sampler_under_test;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* render_text with MIS of the scene text printf makes of fmt. */
static bool render_format(film *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static bool render_format(film *f, const char *fmt, ...) {
    char text[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return render_text(text, PATH_MIS, f);
}

/* The mean and standard error of channel c's pixel means over the rectangle x0..x1, y0..y1. */
typedef struct estimate {
    double mean, se;
} estimate;

static estimate region(const film *f, int c, int x0, int x1, int y0, int y1) {
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (int j = y0; j < y1; j++) {
        for (int i = x0; i < x1; i++) {
            const float *p = &f->accum[((size_t)j * f->width + i) * 4];
            double v = p[c] / p[3];
            sum += v, sum2 += v * v, n++;
        }
    }
    double mean = sum / n, var = (sum2 / n - mean * mean) * n / (n - 1);
    return (estimate){mean, sqrt(var > 0 ? var / n : 0)};
}

static estimate whole(const film *f, int c) { return region(f, c, 0, f->width, 0, f->height); }

/* Checks an estimate against an exact value, within SIGMAS standard errors and 1e-5 relative
 * (float sums). */
static void expect_mean(const char *name, estimate e, double want) {
    CHECK(fabs(e.mean - want) <= SIGMAS * e.se + 1e-5 * fabs(want), "%s: %.6f +- %.6f, want %.6f",
          name, e.mean, e.se, want);
}

/* The camera at the centre of a closed emitting sphere of albedo a (Le = 1): every pixel sees
 * 1 + a + ... + a^B = (1 - a^(B+1)) / (1 - a). */
static void test_furnace(void) {
    int bounces[] = {0, 1, 3, 16};
    for (int k = 0; k < 4; k++) {
        film f = {0};
        CHECK(render_format(&f,
                            "camera position 0 0 0\nplane width 2 height 2 pixel 0.125\n"
                            "sphere lambertian center 0 0 0 radius 10 color 0.5 0.5 0.5 "
                            "emission 1 1 1\nrender mode path bounces %d roulette off samples 64\n",
                            bounces[k]),
              "furnace: render failed");
        if (!f.accum) continue;
        char name[64];
        snprintf(name, sizeof name, "furnace B=%d", bounces[k]);
        expect_mean(name, whole(&f, 1), (1.0 - pow(0.5, bounces[k] + 1)) / 0.5);
        film_free(&f);
    }
    /* Roulette keeps the expectation: Le / (1 - a) with B far past where a^B matters. */
    film f = {0};
    CHECK(render_text("camera position 0 0 0\nplane width 2 height 2 pixel 0.0625\n"
                      "sphere lambertian center 0 0 0 radius 10 color 0.5 0.5 0.5 emission 1 1 1\n"
                      "render mode path bounces 64 samples 64\n",
                      PATH_MIS, &f),
          "furnace with roulette: render failed");
    if (f.accum) expect_mean("furnace with roulette", whole(&f, 0), (1.0 - pow(0.5, 65)) / 0.5);
    film_free(&f);
}

/* The same with a Phong sphere, one bounce: camera rays meet the wall head-on, where the
 * normalized lobe's albedo is exactly ks, so the pixels see 1 + kd + ks. */
static void test_phong_furnace(void) {
    film f = {0};
    CHECK(render_text("camera position 0 0 0\nplane width 2 height 2 pixel 0.125\n"
                      "sphere phong center 0 0 0 radius 10 color 0.2 0.3 0.4 ks 0.4 alpha 20 "
                      "emission 1 1 1\nrender mode path bounces 1 roulette off samples 256\n",
                      PATH_MIS, &f),
          "phong furnace: render failed");
    if (!f.accum) return;
    double kd[3] = {0.2, 0.3, 0.4};
    for (int c = 0; c < 3; c++) {
        char name[64];
        snprintf(name, sizeof name, "phong furnace channel %d", c);
        expect_mean(name, whole(&f, c), 1.0 + kd[c] + 0.4);
    }
    film_free(&f);
}

/* Clear glass in a closed, uniformly emitting, black sphere is invisible: no branch may lose or
 * add light, so every sample that escapes the glass is the field, exactly. Rays meet one sphere
 * and reflect (Fresnel) or refract, and all escape: every pixel is the field. In the overlap of
 * two spheres the angles at the walls change, so rays also reflect totally (past 41.8 degrees);
 * some are then trapped, circling inside one sphere at a fixed angle until the bounce limit
 * (only total reflection can trap them), and bring back nothing: one sample a pixel, each pixel
 * is the field or black, and some are black. */
static void test_glass_in_field(void) {
    const char *glass[] = {
        "sphere refractive center 0 0 0 radius 1 ior 1.5\n",
        "sphere refractive center -0.5 0 0 radius 1 ior 1.5\n"
        "sphere refractive center 0.5 0.2 0.3 radius 0.9 ior 1.5\n",
    };
    for (int k = 0; k < 2; k++) {
        film f = {0};
        CHECK(render_format(&f,
                            "camera position 0 0 -5\nplane width 2 height 2 pixel 0.025\n"
                            "sphere lambertian center 0 0 0 radius 20 color 0 0 0 emission 0.7 "
                            "0.7 0.7\n%srender mode path bounces 64 samples 1\n",
                            glass[k]),
              "glass in field: render failed");
        if (!f.accum) continue;
        int field = 0, black = 0, n = f.width * f.height;
        for (int p = 0; p < n; p++) {
            float v = f.accum[4 * p + 1];
            field += v == 0.7f;
            black += v == 0.0f;
        }
        CHECK(field + black == n, "glass in field (%d spheres): %d pixels neither field nor black",
              k + 1, n - field - black);
        CHECK(k == 0 ? black == 0 : black > 0 && black < n / 20,
              "glass in field (%d spheres): %d of %d pixels trapped", k + 1, black, n);
        film_free(&f);
    }
}

/* The noise of a film's pixels: the RMS of their differences from another film of the same
 * scene under another seed, over sqrt(2) (what the image itself varies by cancels). */
static double pixel_noise(const film *a, const film *b) {
    double sum = 0.0;
    int n = a->width * a->height;
    for (int p = 0; p < n; p++) {
        double d = a->accum[4 * p] / a->accum[4 * p + 3] - b->accum[4 * p] / b->accum[4 * p + 3];
        sum += d * d;
    }
    return sqrt(sum / n / 2.0);
}

/* Two renders of the same expectation: their means within SIGMAS combined standard errors. */
static void expect_same_image(const char *what, const film *a, const film *b) {
    estimate x = whole(a, 0), y = whole(b, 0);
    CHECK(fabs(x.mean - y.mean) <= SIGMAS * hypot(x.se, y.se), "%s: %.5f+-%.5f against %.5f+-%.5f",
          what, x.mean, x.se, y.mean, y.se);
}

/* The estimator of a and a2 (two seeds) is less noisy than that of b and b2. */
static void expect_less_noise(const char *what, const film *a, const film *a2, const film *b,
                              const film *b2) {
    double na = pixel_noise(a, a2), nb = pixel_noise(b, b2);
    CHECK(na < nb, "%s: noise %.5f, not below %.5f", what, na, nb);
}

/* A floor lit by an emitting sphere behind a blocker (penumbrae): light sampling alone, BSDF
 * sampling alone and MIS estimate the same image, MIS with less noise than BSDF sampling. */
static void test_strategies_agree(void) {
    const char *scene =
        "camera position 0 3 -6 look_at 0 0 0\nplane width 2 height 1.5 pixel 0.05\n"
        "sphere lambertian center 0 -1000 0 radius 1000 color 0.6 0.6 0.6\n"
        "sphere lambertian center 0 4 0 radius 1 color 0 0 0 emission 4 4 4\n"
        "sphere phong center 0.5 0.6 0 radius 0.6 color 0.3 0.3 0.3 ks 0.5 alpha 30\n"
        "render mode path bounces 3 samples 128 seed ";
    char text[1024], other[1024];
    snprintf(text, sizeof text, "%s1\n", scene);
    snprintf(other, sizeof other, "%s2\n", scene);
    enum { MIS, LIGHTS, BSDF, MIS2, BSDF2, FILMS };
    film f[FILMS] = {{0}};
    bool ok =
        render_text(text, PATH_MIS, &f[MIS]) && render_text(text, PATH_LIGHTS_ONLY, &f[LIGHTS]) &&
        render_text(text, PATH_BSDF_ONLY, &f[BSDF]) && render_text(other, PATH_MIS, &f[MIS2]) &&
        render_text(other, PATH_BSDF_ONLY, &f[BSDF2]);
    CHECK(ok, "strategies: render failed");
    if (ok) {
        expect_same_image("MIS against light sampling alone", &f[MIS], &f[LIGHTS]);
        expect_same_image("MIS against BSDF sampling alone", &f[MIS], &f[BSDF]);
        expect_less_noise("MIS against BSDF sampling alone", &f[MIS], &f[MIS2], &f[BSDF],
                          &f[BSDF2]);
    }
    for (int k = 0; k < FILMS; k++) film_free(&f[k]);
}

/* light_samples 4 estimates the image light_samples 1 does (with MIS and with light sampling
 * alone, whose weights both divide by the sample count), with less noise at equal samples. The
 * emitter is big and near, so that BSDF sampling finds it often and a weight that left out the
 * count (either strategy's) would show. */
static void test_light_samples(void) {
    const char *scene =
        "camera position 0 3 -6 look_at 0 0 0\nplane width 2 height 1.5 pixel 0.05\n"
        "sphere lambertian center 0 -1000 0 radius 1000 color 0.6 0.6 0.6\n"
        "sphere lambertian center 0 4.5 0 radius 3 color 0 0 0 emission 1 1 1\n"
        "sphere phong center 0.5 0.6 0 radius 0.6 color 0.3 0.3 0.3 ks 0.5 alpha 30\n"
        "render mode path bounces 3 samples 64 light_samples %d seed %d\n";
    char one[1024], four[1024], one2[1024], four2[1024];
    snprintf(one, sizeof one, scene, 1, 1);
    snprintf(four, sizeof four, scene, 4, 1);
    snprintf(one2, sizeof one2, scene, 1, 2);
    snprintf(four2, sizeof four2, scene, 4, 2);
    enum { ONE, FOUR, FOUR_LIGHTS, ONE2, FOUR2, FILMS };
    film f[FILMS] = {{0}};
    bool ok = render_text(one, PATH_MIS, &f[ONE]) && render_text(four, PATH_MIS, &f[FOUR]) &&
              render_text(four, PATH_LIGHTS_ONLY, &f[FOUR_LIGHTS]) &&
              render_text(one2, PATH_MIS, &f[ONE2]) && render_text(four2, PATH_MIS, &f[FOUR2]);
    CHECK(ok, "light samples: render failed");
    if (ok) {
        expect_same_image("1 light sample against 4", &f[ONE], &f[FOUR]);
        expect_same_image("4 light samples: MIS against light sampling alone", &f[FOUR],
                          &f[FOUR_LIGHTS]);
        expect_less_noise("4 light samples against 1", &f[FOUR], &f[FOUR2], &f[ONE], &f[ONE2]);
    }
    for (int k = 0; k < FILMS; k++) film_free(&f[k]);
}

/* A tiny emitting sphere of radius r and radiance Le lights a floor as a point light of
 * intensity Le pi r^2 (trazador's point-light power) does: the same to (r / d)^2 and noise. */
static void test_tiny_emitter(void) {
    const char *floor_and_camera =
        "camera position 0 2 -4 look_at 0 0 0\nplane width 1 height 1 pixel 0.05\n"
        "sphere lambertian center 0 -1000 0 radius 1000 color 0.5 0.5 0.5\n"
        "render mode path bounces 1 samples 64\n";
    double r = 0.01, le = 1000.0;
    char sphere_text[1024], point_text[1024];
    snprintf(sphere_text, sizeof sphere_text,
             "%ssphere lambertian center 0.3 1.5 0.2 radius %g color 0 0 0 emission %g %g %g\n",
             floor_and_camera, r, le, le, le);
    snprintf(point_text, sizeof point_text, "%slight position 0.3 1.5 0.2 power %.9g\n",
             floor_and_camera, le * PI * r * r);
    film sph = {0}, pt = {0};
    bool ok = render_text(sphere_text, PATH_MIS, &sph) && render_text(point_text, PATH_MIS, &pt);
    CHECK(ok, "tiny emitter: render failed");
    if (ok) {
        estimate a = whole(&sph, 0), b = whole(&pt, 0);
        CHECK(fabs(a.mean - b.mean) <= SIGMAS * hypot(a.se, b.se) + 1e-3 * b.mean,
              "tiny emitter %.6f+-%.6f vs point light %.6f+-%.6f", a.mean, a.se, b.mean, b.se);
    }
    film_free(&sph);
    film_free(&pt);
}

/* On Vulkan: the same samples as the C back end. Both run the same operations in the same order
 * (shaders/common/path.h, cos, sin and pow those of shaders/common/transcendental.h), so the
 * films are bit-identical. */
static void test_agrees_with_cpu(void) {
    const char *scenes[] = {
        "camera position 0 0 -9.5\nplane width 4 height 4 pixel 0.05\n"
        "sphere lambertian center -100002 0 0 radius 100000 color 0.75 0.12 0.10\n"
        "sphere lambertian center 100002 0 0 radius 100000 color 0.12 0.70 0.15\n"
        "sphere lambertian center 0 -100002 0 radius 100000 color 0.75 0.75 0.75\n"
        "sphere lambertian center 0 100002 0 radius 100000 color 0.75 0.75 0.75\n"
        "sphere lambertian center 0 0 100003 radius 100000 color 0.75 0.75 0.75\n"
        "sphere lambertian center 0 2.9 0.8 radius 1 color 0 0 0 emission 6 6 6\n"
        "sphere mirror center -0.85 -1.3 1.4 radius 0.7 color 0.95 0.95 0.95\n"
        "sphere refractive center 0.85 -1.4 0.3 radius 0.6 ior 1.5\n"
        "sphere phong center 0 -1.6 -1 radius 0.4 color 0.3 0.3 0.6 ks 0.5 alpha 30\n"
        "light position 1 1.5 -1 power 2\n"
        "render mode path samples 4 bounces 8\n",
        /* three light samples a vertex */
        "camera position 0 3 -6 look_at 0 0 0\nplane width 2 height 1.5 pixel 0.05\n"
        "sphere lambertian center 0 -1000 0 radius 1000 color 0.6 0.6 0.6\n"
        "sphere lambertian center 0 4.5 0 radius 3 color 0 0 0 emission 1 1 1\n"
        "sphere phong center 0.5 0.6 0 radius 0.6 color 0.3 0.3 0.3 ks 0.5 alpha 30\n"
        "render mode path samples 4 bounces 3 light_samples 3\n",
    };
    for (size_t k = 0; k < sizeof scenes / sizeof scenes[0]; k++) {
        film gpu = {0}, cpu = {0};
        bool ok = render_text(scenes[k], PATH_MIS, &gpu);
        use_vulkan = false;
        ok = ok && render_text(scenes[k], PATH_MIS, &cpu);
        use_vulkan = true;
        CHECK(ok, "agreement: render failed");
        if (!ok) continue;
        int n = gpu.width * gpu.height, exact = 0;
        for (int p = 0; p < n; p++) exact += !memcmp(&gpu.accum[4 * p], &cpu.accum[4 * p], 16);
        CHECK(exact == n, "agreement: %d of %d pixels bit-exact", exact, n);
        film_free(&gpu);
        film_free(&cpu);
    }
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_path: no Vulkan device, skipped\n");
        return 77;
    }
    render_sampler samplers[] = {RENDER_SAMPLER_RANDOM, RENDER_SAMPLER_SOBOL};
    for (int k = 0; k < 2; k++) {
        sampler_under_test = samplers[k];
        printf("sampler %s\n", k ? "sobol" : "random");
        CHECK_CASE(test_furnace);
        CHECK_CASE(test_phong_furnace);
        CHECK_CASE(test_glass_in_field);
        CHECK_CASE(test_strategies_agree);
        CHECK_CASE(test_light_samples);
        CHECK_CASE(test_tiny_emitter);
        if (use_vulkan) CHECK_CASE(test_agrees_with_cpu);
    }
    return check_summary(use_vulkan ? "test_path vulkan" : "test_path cpu");
}
