/* test_lights.c: the sun and the spot light against closed forms, in report mode (indirect off)
 * and path mode (bounces 1: direct light alone), on the CPU back end or (argument "vulkan") the
 * Vulkan one: a Lambertian floor of albedo a under a delta sun of irradiance E at theta from its
 * normal is a E cos(theta) / pi everywhere; under a spot pointing down, each pixel is the point
 * light's a I cos / (pi d^2) times glTF's falloff inside, across and outside the cone's edge; the
 * keys' refusals. An orthographic camera looks straight down, so each pixel's floor point is
 * known in closed form. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"

#define PI 3.14159265358979323846
#define DEGREES (PI / 180.0)

static bool use_vulkan;

/* The camera straight down at the floor y = 0 from y = 5, a view 8 wide (64 x 64 pixels of
 * 0.125), pixel centres only; then the lights, a grey floor (albedo 0.5) and the mode. */
#define FLOOR_SCENE                                                             \
    "camera position 0 5 0 direction 0 -1 0 up 0 0 1 projection orthographic\n" \
    "plane width 8 height 8 pixel 0.125\n%s\n"                                  \
    "quad lambertian v0 -50 0 -50 v1 50 0 -50 v2 50 0 50 v3 -50 0 50 color 0.5 0.5 0.5\n"

static const char *modes[2] = {"render indirect off samples 1",
                               "render mode path bounces 1 samples 1"};

/* Renders the floor under the lights of `lights` in the mode and settings `render` (pixel
 * centres) with the strategy into f. */
static bool render_floor_by(film *f, const char *lights, const char *render,
                            path_strategy strategy) {
    char text[2048];
    snprintf(text, sizeof text, FLOOR_SCENE "%s\n", lights, render);
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    o.no_jitter = true;
    o.strategy = strategy;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

static bool render_floor(film *f, const char *lights, int m) {
    return render_floor_by(f, lights, modes[m], PATH_MIS);
}

/* Pixel (i, j)'s red channel and the floor point its centre sees (x, z). */
static double pixel_red(const film *f, int i, int j) {
    const float *px = &f->accum[((size_t)j * f->width + i) * 4];
    return px[3] > 0.0f ? px[0] / px[3] : 0.0;
}
static void floor_point(int i, int j, double *x, double *z) {
    *x = -4.0 + (i + 0.5) * 0.125;
    *z = 4.0 - (j + 0.5) * 0.125;
}

/* A delta sun at theta from the floor's normal lights every pixel with a E cos(theta) / pi. */
static void test_sun_irradiance(void) {
    const double e = 3.0, a = 0.5;
    for (int m = 0; m < 2; m++)
        for (int t = 0; t < 3; t++) {
            double theta = t * 30.0 * DEGREES;
            char lights[256];
            snprintf(lights, sizeof lights, "sun direction %.17g %.17g 0.3 irradiance %g angle 0",
                     sin(theta), -cos(theta), e);
            /* the direction's z part tilts it: cos(theta) from the normal of its unit vector */
            double len = sqrt(1.0 + 0.09), cos_n = cos(theta) / len;
            film f = {0};
            bool ok = render_floor(&f, lights, m);
            CHECK(ok, "rendering the sun floor");
            if (!ok) continue;
            double want = a * e * cos_n / PI, worst = 0.0;
            for (int j = 0; j < f.height; j++)
                for (int i = 0; i < f.width; i++)
                    worst = fmax(worst, fabs(pixel_red(&f, i, j) - want) / want);
            CHECK(worst < 1e-5, "%s: sun at %g degrees: a pixel %.3g off a E cos / pi = %.6f",
                  modes[m], t * 30.0, worst, want);
            film_free(&f);
        }
}

/* A sun with a disc (20 degrees across, 30 from the floor's normal) lights the floor with the
 * same a E cos(theta) / pi in path mode, the whole cap above the horizon: by light sampling of
 * its cone alone, by BSDF rays that find it alone, and by both weighed by MIS; the mean of every
 * pixel within 4.5 standard errors. Report mode takes the disc's centre: exactly that. */
static void test_sun_disc(void) {
    const double e = 3.0, a = 0.5, theta = 30.0 * DEGREES, want = a * e * cos(theta) / PI;
    char lights[256];
    snprintf(lights, sizeof lights, "sun direction %.17g %.17g 0 irradiance %g angle 20",
             sin(theta), -cos(theta), e);
    const path_strategy strategies[3] = {PATH_MIS, PATH_LIGHTS_ONLY, PATH_BSDF_ONLY};
    const char *names[3] = {"MIS", "light sampling", "BSDF sampling"};
    for (int k = 0; k < 3; k++) {
        film f = {0};
        bool ok =
            render_floor_by(&f, lights, "render mode path bounces 1 samples 64", strategies[k]);
        CHECK(ok, "rendering the sun disc");
        if (!ok) continue;
        double sum = 0, sum2 = 0;
        int n = f.width * f.height;
        for (int j = 0; j < f.height; j++)
            for (int i = 0; i < f.width; i++) {
                double v = pixel_red(&f, i, j);
                sum += v, sum2 += v * v;
            }
        double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / (n - 1));
        printf("sun disc by %s: %.6f +- %.6f, a E cos / pi = %.6f\n", names[k], mean, se, want);
        CHECK(fabs(mean - want) <= 4.5 * se + 1e-5 * want,
              "sun disc by %s: %.6f +- %.6f, want %.6f", names[k], mean, se, want);
        film_free(&f);
    }
    film f = {0};
    if (render_floor(&f, lights, 0)) {
        CHECK(fabs(pixel_red(&f, 5, 7) - want) < 1e-5 * want, "report mode: the disc's centre");
        film_free(&f);
    }
}

/* A camera that looks at the sun sees its disc of radiance E / (pi sin^2(angle / 2)) and the
 * background around it. */
static void test_sun_seen(void) {
    film f = {0};
    scene s;
    render_opts o;
    const char *text =
        "camera position 0 0 0 direction 0 1 0 up 0 0 1 fov 40\n"
        "plane width 1 height 1 pixel 0.0625\nsun direction 0 -1 0 irradiance 2 angle 10\n"
        "background 0.25 0.25 0.25\nrender mode path samples 4\n";
    if (!parse_scene_text(text, &s, &o)) {
        CHECK(false, "parsing the sky");
        return;
    }
    o.no_jitter = true;
    bool ok = render_on(use_vulkan, &s, &o, &f);
    CHECK(ok, "rendering the sky");
    if (ok) {
        double half = 5.0 * DEGREES, want = 2.0 / (PI * sin(half) * sin(half));
        double centre = pixel_red(&f, 8, 8), corner = pixel_red(&f, 0, 0);
        CHECK(fabs(centre - 0.25 - want) < 1e-5 * want, "the sun's disc: %.4f, want %.4f",
              centre - 0.25, want);
        CHECK(corner == 0.25, "the sky beside it: %.6f", corner);
    }
    film_free(&f);
    scene_free(&s);
}

/* glTF KHR_lights_punctual's falloff of a spot of half-angles inner and outer (degrees) at the
 * cosine cd from its axis. */
static double spot_falloff(double cd, double inner, double outer) {
    double ci = cos(inner * DEGREES), co = cos(outer * DEGREES);
    double scale = 1.0 / fmax(1e-3, ci - co), v = (cd - co) * scale;
    v = v < 0 ? 0 : v > 1 ? 1 : v;
    return v * v;
}

/* A spot of intensity I at height h pointing down: each pixel a I cos^3(phi) / (pi h^2)
 * times the falloff at phi from its axis, in full inside the inner cone, 0 outside the outer
 * one, glTF's smooth step across; pixels of all three kinds are checked. */
static void test_spot_falloff(void) {
    const double power = 10.0, h = 2.0, a = 0.5, inner = 20.0, outer = 35.0;
    char lights[256];
    snprintf(lights, sizeof lights, "light position 0 %g 0 power %g direction 0 -1 0 cone %g %g", h,
             power, inner, outer);
    for (int m = 0; m < 2; m++) {
        film f = {0};
        bool ok = render_floor(&f, lights, m);
        CHECK(ok, "rendering the spot floor");
        if (!ok) continue;
        int counts[3] = {0, 0, 0}, bad = 0;
        double worst = 0.0;
        for (int j = 0; j < f.height; j++)
            for (int i = 0; i < f.width; i++) {
                double x, z;
                floor_point(i, j, &x, &z);
                double d2 = x * x + h * h + z * z, cd = h / sqrt(d2);
                double fall = spot_falloff(cd, inner, outer);
                double want = a / PI * power * cd / d2 * fall, got = pixel_red(&f, i, j);
                counts[fall >= 1.0 ? 0 : fall > 0.0 ? 1 : 2]++;
                /* rounding in float moves the falloff by its slope times a few ulps of cd */
                double err = fabs(got - want), tolerance = 2e-5 * want + 1e-6;
                worst = fmax(worst, want > 0 ? err / want : err);
                bad += err > tolerance;
            }
        printf("spot (%s): %d pixels inside, %d across the edge, %d outside; worst %.3g\n",
               modes[m], counts[0], counts[1], counts[2], worst);
        CHECK(counts[0] > 50 && counts[1] > 50 && counts[2] > 50,
              "each part of the cone seen: %d %d %d", counts[0], counts[1], counts[2]);
        CHECK(bad == 0, "%s: %d pixels off the spot's formula (worst %.3g)", modes[m], bad, worst);
        film_free(&f);
    }
}

static void test_refusals(void) {
    const char *spot = "light position 0 0 0 power 1 ";
    char text[256];
    struct {
        const char *keys;
        int col;
        const char *part;
    } bad[] = {
        {"direction 0 -1 0 cone 0 10", 52, "cone must be in (0, 90]"},
        {"direction 0 -1 0 cone 10 95", 55, "cone must be in (0, 90]"},
        {"direction 0 -1 0 cone 30 20", 52, "inner angle 30 is above the outer angle 20"},
        {"direction 0 0 0 cone 10 20", 30, "light direction must not be zero"},
        {"direction 0 -1 0", 30, "takes both direction and cone"},
        {"cone 10 20", 30, "takes both direction and cone"},
        {"direction 0 -1 0 cone 10", 54, "expected 2 numbers"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        snprintf(text, sizeof text, "%s%s\n", spot, bad[k].keys);
        expect_parse_error(text, 1, bad[k].col, bad[k].part);
    }
    expect_parse_error("sun direction 0 -1 0\n", 1, 1, "irradiance");
    expect_parse_error("sun irradiance 2\n", 1, 1, "direction");
    expect_parse_error("sun direction 0 0 0 irradiance 2\n", 1, 5,
                       "sun direction must not be zero");
    expect_parse_error("sun direction 0 -1 0 irradiance -2\n", 1, 33, "irradiance must be >= 0");
    expect_parse_error("sun direction 0 -1 0 irradiance 2 angle -1\n", 1, 41, "angle must be in");
    expect_parse_error("sun direction 0 -1 0 irradiance 2 position 0 0 0\n", 1, 35, "unknown key");
    expect_parse_error("sun direction 0 -1 0 irradiance 2\nsun direction 0 -1 1 irradiance 2\n", 2,
                       1, "one sun at most");
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_lights: no Vulkan device, skipped\n");
        return 77;
    }
    if (!use_vulkan) CHECK_CASE(test_refusals);
    CHECK_CASE(test_sun_irradiance);
    CHECK_CASE(test_spot_falloff);
    CHECK_CASE(test_sun_disc);
    CHECK_CASE(test_sun_seen);
    return check_summary(use_vulkan ? "test_lights vulkan" : "test_lights");
}
