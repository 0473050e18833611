/* test_analytic.c: closed-form checks of the seed integrator (DESIGN section 8), run on the back
 * end named by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 when no device exists). Every expected
 * value is computed here from the formula, with the tolerance it needs stated beside it. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "image/diff.h"
#include "image/image.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"

#define PI 3.14159265358979323846

static bool use_vulkan;
static render_stats last_stats; /* of the last render_text() */

/* Renders scene text with its own settings (no jitter) into f; false on a parse or render error. */
static bool render_text(const char *text, film *f, int bounces) {
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    o.no_jitter = true;
    last_stats = (render_stats){0};
    o.stats = &last_stats;
    if (bounces >= 0) o.bounces = bounces;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* Mean radiance of channel c of pixel (i, j). */
static float pixel(const film *f, int i, int j, int c) {
    const float *p = &f->accum[((size_t)j * f->width + i) * 4];
    return p[3] > 0.0f ? p[c] / p[3] : NAN;
}

static bool near(double got, double want, double rel) {
    return fabs(got - want) <= rel * fabs(want) + 1e-7;
}

/* Centre pixel of a 21x21 image looking down +z at a sphere whose front is lit head-on. */
static const char *const camera_21 =
    "camera position 0 0 -10\nplane width 0.21 height 0.21 pixel 0.01\n";

/* Checks the centre pixel against want[3]; the ray offset EPS (1e-4 relative) moves the shadow
 * ray origin by at most 1e-4 of the 4-unit light distance, so 2e-4 relative covers it. */
static void check_centre(const char *name, const char *scene_rest, const double want[3],
                         int bounces) {
    char text[2048];
    snprintf(text, sizeof text, "%s%s", camera_21, scene_rest);
    film f = {0};
    CHECK(render_text(text, &f, bounces), "%s: render failed", name);
    if (!f.accum) return;
    for (int c = 0; c < 3; c++)
        CHECK(near(pixel(&f, 10, 10, c), want[c], 2e-4), "%s: channel %d = %.7g, want %.7g", name,
              c, pixel(&f, 10, 10, c), want[c]);
    film_free(&f);
}

static void test_lambertian(void) {
    /* kd/pi * power / d^2 with d = 4 (hit at z = -1, light at z = -5), cos = 1. */
    double kd[3] = {0.2, 0.5, 0.8}, want[3];
    for (int c = 0; c < 3; c++) want[c] = kd[c] / PI * 10.0 / 16.0;
    check_centre("lambertian",
                 "light position 0 0 -5 power 10\n"
                 "sphere lambertian center 0 0 0 radius 1 color 0.2 0.5 0.8\n"
                 "render samples 1 indirect on\n",
                 want, -1);
}

static void test_phong(void) {
    /* wo = wi = N, so wr = N and wo.wr = 1: f = kd/pi + ks (alpha + 2) / (2 pi). */
    double kd[3] = {0.2, 0.5, 0.8}, want[3];
    for (int c = 0; c < 3; c++) want[c] = (kd[c] / PI + 0.4 * 22.0 / (2.0 * PI)) * 10.0 / 16.0;
    check_centre("phong",
                 "light position 0 0 -5 power 10\n"
                 "sphere phong center 0 0 0 radius 1 color 0.2 0.5 0.8 ks 0.4 alpha 20\n"
                 "render samples 1 indirect off\n",
                 want, -1);
}

/* A mirror at z = 0 sends the centre ray straight back past the camera to a sphere behind it,
 * lit head-on from 4 units: tint * kd/pi * power / 16. A Lambertian shading would differ. */
static const char *const mirror_scene =
    "light position 0 0 -14 power 10\n"
    "sphere mirror center 0 0 0 radius 1 color 0.5 0.7 0.9\n"
    "sphere lambertian center 0 0 -20 radius 2 color 0.6 0.6 0.6\n"
    "render samples 1 indirect off\n";

static void test_mirror(void) {
    double tint[3] = {0.5, 0.7, 0.9}, want[3], black[3] = {0, 0, 0};
    for (int c = 0; c < 3; c++) want[c] = tint[c] * 0.6 / PI * 10.0 / 16.0;
    check_centre("mirror", mirror_scene, want, -1);
    /* One specular event: allowed with bounces 1, "more than bounces" (black) with bounces 0. */
    check_centre("mirror bounces 1", mirror_scene, want, 1);
    check_centre("mirror bounces 0", mirror_scene, black, 0);
}

static void test_refractive(void) {
    /* Normal incidence: the ray crosses the glass unbent to a sphere behind it, lit head-on from
     * 4 units by a light between them. Two specular events (in, out), each times the tint:
     * tint^2 * kd/pi * power / 16. A mirror would see black, a Lambertian its own light. */
    double tint[3] = {0.9, 0.8, 0.7}, want[3];
    for (int c = 0; c < 3; c++) want[c] = tint[c] * tint[c] * 0.6 / PI * 10.0 / 16.0;
    check_centre("refractive",
                 "light position 0 0 4 power 10\n"
                 "sphere refractive center 0 0 0 radius 1 ior 1.5 color 0.9 0.8 0.7\n"
                 "sphere lambertian center 0 0 10 radius 2 color 0.6 0.6 0.6\n"
                 "render samples 1 indirect off\n",
                 want, -1);
}

/* Refracts unit d at unit normal n facing it, eta = n1/n2 (DESIGN section 3), in double. */
static void refract(const double d[3], const double n[3], double eta, double out[3]) {
    double c1 = -(d[0] * n[0] + d[1] * n[1] + d[2] * n[2]);
    double k = 1.0 - eta * eta * (1.0 - c1 * c1);
    for (int c = 0; c < 3; c++) out[c] = eta * d[c] + (eta * c1 - sqrt(k)) * n[c];
}

/* Off-axis refraction against the closed form: the ray of pixel (20, 5) enters a unit glass
 * sphere (ior 1.5) at the origin and leaves it bent twice; the exit ray is traced here in double
 * with Snell's law and a small lit target is put 6 units along it. The pixel must see the target;
 * unbent or mirrored rays would miss it by far more than its radius 0.05. */
static void test_refraction_direction(void) {
    const double plane_y = 0.205 - 5.5 * 0.01, dist = 0.82; /* 0.41 wide plane, 2 x width away */
    double len = sqrt(plane_y * plane_y + dist * dist);
    double d[3] = {0.0, plane_y / len, dist / len}, o[3] = {0.0, 0.0, -3.0};
    double b = o[2] * d[2], t = -b - sqrt(b * b - (o[2] * o[2] - 1.0));
    double p[3] = {0.0, o[1] + t * d[1], o[2] + t * d[2]}, inside[3], out[3];
    refract(d, p, 1.0 / 1.5, inside); /* p is also the outward normal of the unit sphere */
    double far = -2.0 * (p[1] * inside[1] + p[2] * inside[2]);
    double q[3] = {0.0, p[1] + far * inside[1], p[2] + far * inside[2]};
    double facing[3] = {0.0, -q[1], -q[2]};
    refract(inside, facing, 1.5, out);
    double target[3] = {0.0, q[1] + 6.0 * out[1], q[2] + 6.0 * out[2]};
    char text[1024];
    snprintf(text, sizeof text,
             "camera position 0 0 -3\nplane width 0.41 height 0.41 pixel 0.01\n"
             "light position 0 %.9f %.9f power 10\n"
             "sphere refractive center 0 0 0 radius 1 ior 1.5\n"
             "sphere lambertian center 0 %.9f %.9f radius 0.05 color 1 1 1\n"
             "render samples 1 indirect off\n",
             target[1] - 1.0, target[2] - 0.5, target[1], target[2]);
    film f = {0};
    CHECK(render_text(text, &f, -1), "refraction direction: render failed");
    if (!f.accum) return;
    CHECK(pixel(&f, 20, 5, 1) > 0.0f, "refraction direction: the exit ray misses the target");
    CHECK(pixel(&f, 20, 35, 1) == 0.0f, "refraction direction: the mirrored row sees the target");
    film_free(&f);
}

/* The same image with and without an ior = 1 sphere in front of the lit sphere: rays cross it
 * unbent. The light sits between the glass and the lit sphere so the glass's shadow is out of
 * view. Ray offsets move paths by ~1e-4, so pixels agree to 1e-3 relative except for at most a
 * few silhouette pixels. */
static void test_ior_one(void) {
    const char *base =
        "camera position 0 0.3 -10\nplane width 4 height 3 pixel 0.05\n"
        "light position 0.5 0.5 5 power 10\n"
        "sphere lambertian center 0 0 11 radius 3 color 0.7 0.5 0.3\n"
        "render samples 1 indirect off\n";
    char with_glass[1024];
    snprintf(with_glass, sizeof with_glass,
             "%ssphere refractive center 0.2 0.4 0 radius 1.2 ior 1\n", base);
    film a = {0}, b = {0};
    CHECK(render_text(base, &a, -1) && render_text(with_glass, &b, -1), "ior 1: render failed");
    if (!a.accum || !b.accum) return;
    int differ = 0, lit = 0;
    for (int j = 0; j < a.height; j++)
        for (int i = 0; i < a.width; i++) {
            float x = pixel(&a, i, j, 0), y = pixel(&b, i, j, 0);
            lit += x > 0.0f;
            differ += !near(y, x, 1e-3);
        }
    CHECK(lit > 500, "ior 1: only %d lit pixels", lit);
    CHECK(differ <= 3, "ior 1: %d of %d pixels differ", differ, a.width * a.height);
    film_free(&a);
    film_free(&b);
}

/* Inside a closed Lambertian sphere (radius R, albedo a) with a light of power I at its centre,
 * every wall point receives L0 = a I / (pi R^2); the one indirect bounce sees L0 everywhere, so
 * each sample's estimate f * L0 * cos / pdf = (a / pi) L0 pi is exactly a L0: L0 (1 + a) with no
 * Monte Carlo noise. Float rounding and the EPS offset stay under 2e-4 relative. */
static void test_closed_sphere(void) {
    const double a = 0.6, intensity = 10.0, r = 2.0, l0 = a * intensity / (PI * r * r);
    for (int indirect = 0; indirect <= 1; indirect++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "camera position 0.3 -0.2 0.1 direction 0.2 0.1 1\n"
                 "plane width 2 height 2 pixel 0.1\n"
                 "light position 0 0 0 power 10\n"
                 "sphere lambertian center 0 0 0 radius 2 color 0.6 0.6 0.6\n"
                 "render samples 4 indirect %s\n",
                 indirect ? "on" : "off");
        film f = {0};
        CHECK(render_text(text, &f, -1), "closed sphere: render failed");
        if (!f.accum) continue;
        double want = indirect ? l0 * (1.0 + a) : l0;
        int bad = 0;
        for (int j = 0; j < f.height; j++)
            for (int i = 0; i < f.width; i++) bad += !near(pixel(&f, i, j, 0), want, 2e-4);
        CHECK(bad == 0, "closed sphere (indirect %d): %d pixels differ from %.7g, e.g. %.7g",
              indirect, bad, want, pixel(&f, 0, 0, 0));
        /* Every ray hits the wall: a camera ray and its shadow ray, and with the bounce an
         * indirect ray and its shadow ray, per sample. */
        uint64_t want_rays = (uint64_t)f.width * f.height * 4u * (indirect ? 4u : 2u);
        CHECK(last_stats.rays == want_rays, "closed sphere (indirect %d): %llu rays, want %llu",
              indirect, (unsigned long long)last_stats.rays, (unsigned long long)want_rays);
        film_free(&f);
    }
}

/* Inside a mirror sphere every path bounces until the limit: black, never the background, at the
 * default limit and at 64 reflections (unnormalized mirror rays drifted off the sphere and escaped
 * to the background from the 8th). */
static void test_bounce_limit(void) {
    const char *const texts[] = {
        "camera position 0 0 0\nplane width 1 height 1 pixel 0.1\n"
        "light position 0 0.5 0 power 10\n"
        "sphere mirror center 0 0 0 radius 3\nbackground 1 1 1\n"
        "render samples 2 indirect off\n",
        "camera position 0.5 0 0 direction -0.6 0 1\nplane width 0.2 height 0.2 pixel 0.01\n"
        "sphere mirror center 0 0 0 radius 1\nbackground 1 1 1\n"
        "render samples 1 indirect off\n",
    };
    const int bounces[] = {-1, 64};
    for (int t = 0; t < 2; t++) {
        for (int b = 0; b < 2; b++) {
            film f = {0};
            CHECK(render_text(texts[t], &f, bounces[b]), "bounce limit %d: render failed", t);
            if (!f.accum) continue;
            int lit = 0;
            for (int k = 0; k < f.width * f.height; k++) lit += f.accum[k * 4] != 0.0f;
            CHECK(lit == 0, "bounce limit %d (bounces %d): %d pixels not black", t, bounces[b],
                  lit);
            film_free(&f);
        }
    }
}

/* Radiance of pixel (40, 40) of test_huge_walls' radius-1e5 room, in double: its centre ray from
 * (0.013, 0.007, -6.9) along (0.025, -0.025, 8) meets the back wall (centre z = 3 + 1e5) near
 * z = 3, lit unoccluded by the light at (0, 0.8, 0.6): 0.75 / pi * 9 * cos / d^2. In float32
 * the ray origin relative to the wall's centre, 1e5 away, is only known to half a step of 1e5
 * (0.004): the hit moves by up to 4 mm along the ray, 0.3% of the radiance (0.11% measured). */
static double huge_wall_pixel(void) {
    const double r = 1e5, o[3] = {0.013, 0.007, -6.9}, centre[3] = {0.0, 0.0, 3.0 + r};
    const double light[3] = {0.0, 0.8, 0.6};
    double d[3] = {0.025, -0.025, 8.0}, len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    double oc[3], b = 0.0, c = -r * r;
    for (int a = 0; a < 3; a++) {
        d[a] /= len;
        oc[a] = o[a] - centre[a];
        b += oc[a] * d[a];
        c += oc[a] * oc[a];
    }
    double t = c / (-b + sqrt(b * b - c)); /* the near root, without cancellation */
    double hit[3], to_light[3], dist2 = 0.0, cos_i = 0.0;
    for (int a = 0; a < 3; a++) {
        hit[a] = o[a] + t * d[a];
        to_light[a] = light[a] - hit[a];
        dist2 += to_light[a] * to_light[a];
    }
    for (int a = 0; a < 3; a++) cos_i += (hit[a] - centre[a]) / r * to_light[a] / sqrt(dist2);
    return 0.75 / PI * 9.0 * cos_i / dist2;
}

/* A Cornell room with walls of radius 1e5 renders like the same room of radius-1e3 walls: no
 * holes, no wall hit in another's place, no self-shadowing acne (direct light only, which
 * indirect noise would hide). The camera sits a little off the room's axis: from the axis, the
 * centre rays of the image's diagonals meet two walls at once, an exact tie that goes to the
 * sphere stored first in BVH order, which the two rooms' trees need not share. Also a pixel on
 * the radius-1e5 back wall against its closed form. */
static void test_huge_walls(void) {
    film films[2] = {{0}, {0}};
    const double radius[2] = {1e3, 1e5};
    for (int k = 0; k < 2; k++) {
        double r = radius[k];
        char text[2048];
        snprintf(
            text, sizeof text,
            "camera position 0.013 0.007 -6.9\nplane width 4 height 4 pixel 0.05\n"
            "light position 0 0.8 0.6 power 9\n"
            "sphere lambertian center %.0f 0 0 radius %.0f color 0.75 0.12 0.10\n"
            "sphere lambertian center %.0f 0 0 radius %.0f color 0.12 0.70 0.15\n"
            "sphere lambertian center 0 %.0f 0 radius %.0f color 0.75 0.75 0.75\n"
            "sphere lambertian center 0 %.0f 0 radius %.0f color 0.75 0.75 0.75\n"
            "sphere lambertian center 0 0 %.0f radius %.0f color 0.75 0.75 0.75\n"
            "sphere phong center -0.85 -1.3 1.4 radius 0.7 color 0.85 0.85 0.85 ks 0.25 alpha 40\n"
            "render samples 1 indirect off\n",
            -2 - r, r, 2 + r, r, -2 - r, r, 2 + r, r, 3 + r, r);
        CHECK(render_text(text, &films[k], -1), "huge walls: render of radius %g failed", r);
    }
    if (films[1].accum) {
        double want = huge_wall_pixel();
        for (int c = 0; c < 3; c++)
            CHECK(near(pixel(&films[1], 40, 40, c), want, 5e-3),
                  "huge walls: pixel (40, 40) channel %d = %.7g, want %.7g", c,
                  pixel(&films[1], 40, 40, c), want);
    }
    /* Radius-1e3 walls sag by x^2 / 2R <= 0.002 over the room: that moves hard shadow edges by a
     * pixel here and there and changes the light's falloff by ~1%; so the images agree to 40 dB
     * and differ grossly (8/255 in display units) only along edges. Holes, acne or a wrong wall
     * in the radius-1e5 room would spread gross errors over whole walls. */
    image a = {0}, b = {0};
    diff_stats st;
    if (films[0].accum && films[1].accum && image_from_film(&films[0], &a) &&
        image_from_film(&films[1], &b) && diff_images(&a, &b, &st)) {
        int gross = 0;
        for (int k = 0; k < a.width * a.height * 3; k++)
            gross += fabs(tonemap_encode(a.rgb[k], TONEMAP_SRGB) -
                          tonemap_encode(b.rgb[k], TONEMAP_SRGB)) > 8.0 / 255.0;
        CHECK(st.psnr >= 40.0, "huge walls: psnr %.2f dB", st.psnr);
        CHECK(gross <= a.width * a.height / 200, "huge walls: %d gross differences", gross);
    } else {
        CHECK(0, "huge walls: could not compare");
    }
    image_free(&a);
    image_free(&b);
    film_free(&films[0]);
    film_free(&films[1]);
}

/* Every sample of a pixel that sees only the background is the background: its mean must be it
 * to float rounding at any sample count. A plain float sum drifts as it grows (0.9 came out as
 * 0.89961 at 65,536 samples and 0.89125 at 1,048,576); the compensated sum does not. */
static void test_long_sums(void) {
    const char *text =
        "camera position 0 0 0\nplane width 2 height 1 pixel 1\nbackground 0.9 1 0.1\n"
        "render samples %d indirect off\n";
    /* lavapipe charges a tiny image as 1,024 pixels: 65,536 samples take about a second there */
    int samples = use_vulkan ? 65536 : 1048576;
    char scene_text[256];
    snprintf(scene_text, sizeof scene_text, text, samples);
    film f = {0};
    CHECK(render_text(scene_text, &f, -1), "long sums: render failed");
    if (!f.accum) return;
    const float want[3] = {0.9f, 1.0f, 0.1f};
    for (int i = 0; i < 2; i++) {
        CHECK(f.accum[4 * i + 3] == (float)samples, "long sums: pixel %d counted %.0f samples", i,
              f.accum[4 * i + 3]);
        for (int c = 0; c < 3; c++)
            CHECK(near(pixel(&f, i, 0, c), want[c], 2e-7), "long sums: %d spp, channel %d: %.9g",
                  samples, c, pixel(&f, i, 0, c));
    }
    film_free(&f);
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_analytic: no Vulkan device, skipped\n");
        return 77;
    }
    test_lambertian();
    test_phong();
    test_mirror();
    test_refractive();
    test_refraction_direction();
    test_ior_one();
    test_closed_sphere();
    test_bounce_limit();
    test_huge_walls();
    test_long_sums();
    return check_summary(use_vulkan ? "test_analytic vulkan" : "test_analytic cpu");
}
