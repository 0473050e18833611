/* test_triangles.c: closed-form checks of triangles and quads (DESIGN section 3), run on the back
 * end named by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 when no device exists): a quad floor
 * under a point light, closed boxes and a tessellated sphere that no ray escapes (watertight),
 * the furnace inside them, and the form factor of a square emitter over a floor. Means are
 * compared as in test_path.c, within 4.5 standard errors. */
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
#define SIGMAS 4.5

static bool use_vulkan;

/* Renders scene text into f (its own settings); false on any error. */
static bool render_text(const char *text, film *f) {
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* The mean of channel c of pixel (i, j). */
static double pixel(const film *f, int i, int j, int c) {
    const float *p = &f->accum[((size_t)j * f->width + i) * 4];
    return p[c] / p[3];
}

/* The unit direction of the camera ray through the centre of pixel (i, j) for a camera at the
 * origin frame of DESIGN section 3.1 (right r, up u, forward fw), in double. */
static void camera_ray(const double r[3], const double u[3], const double fw[3], double width,
                       double height, double pixel_size, int i, int j, double d[3]) {
    double x = -width / 2 + (i + 0.5) * pixel_size, y = height / 2 - (j + 0.5) * pixel_size;
    double len = 0.0;
    for (int a = 0; a < 3; a++) d[a] = x * r[a] + y * u[a] + 2 * width * fw[a], len += d[a] * d[a];
    for (int a = 0; a < 3; a++) d[a] /= sqrt(len);
}

/* Renders the floor of test_quad_floor's camera and light: `floor` (a directive line) into f. */
static bool render_floor(const char *floor, film *f) {
    char text[2048];
    snprintf(text, sizeof text,
             "camera position 0 2 -4 direction 0 -0.5 1 up 0 1 0\nplane width 1 height 1 pixel "
             "0.03125\nlight position 0.5 3 1 power 20\nrender samples 1 indirect off\n%s",
             floor);
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    o.no_jitter = true;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* Report mode, direct light only: a quad floor at y = 0 lit by a point light of power I at
 * height h is kd / pi * I cos / dist^2 at every pixel (the report's huge-sphere floor, exactly
 * flat), and a huge sphere's floor renders the same within its curvature. So does a quad of
 * half-size 1e7, whose hits are placed on its plane (plane_hit): at the watertight test's own
 * distance they fell below it, and its halves shaded each other on 3 pixels in 4. */
static void test_quad_floor(void) {
    static const char *const halves[] = {"50", "1e7"};
    film quad[2] = {{0}}, ball = {0};
    for (int k = 0; k < 2; k++) {
        char floor[512];
        snprintf(floor, sizeof floor,
                 "quad lambertian v0 -%s 0 -%s v1 -%s 0 %s v2 %s 0 %s v3 %s 0 -%s color 0.8 0.6 "
                 "0.4\n",
                 halves[k], halves[k], halves[k], halves[k], halves[k], halves[k], halves[k],
                 halves[k]);
        CHECK(render_floor(floor, &quad[k]), "quad floor %s: render failed", halves[k]);
    }
    CHECK(render_floor("sphere lambertian center 0 -100000 0 radius 100000 color 0.8 0.6 0.4\n",
                       &ball),
          "sphere floor: render failed");
    if (!quad[0].accum || !quad[1].accum || !ball.accum) {
        film_free(&quad[0]), film_free(&quad[1]), film_free(&ball);
        return;
    }
    /* The camera frame of scene_pack, in double. */
    double fw[3] = {0, -0.5, 1}, n = sqrt(1.25);
    for (int a = 0; a < 3; a++) fw[a] /= n;
    double r[3] = {fw[2], 0, -fw[0]}, rl = sqrt(r[0] * r[0] + r[2] * r[2]);
    r[0] /= rl, r[2] /= rl;
    double u[3] = {fw[1] * r[2] - fw[2] * r[1], fw[2] * r[0] - fw[0] * r[2],
                   fw[0] * r[1] - fw[1] * r[0]};
    double kd[3] = {0.8, 0.6, 0.4}, worst[2] = {0.0, 0.0}, worst_ball = 0.0;
    int floor_pixels = 0;
    for (int j = 0; j < ball.height; j++) {
        for (int i = 0; i < ball.width; i++) {
            double d[3];
            camera_ray(r, u, fw, 1.0, 1.0, 0.03125, i, j, d);
            if (d[1] >= 0) continue;
            double t = -2.0 / d[1], p[3] = {t * d[0], 0.0, -4 + t * d[2]};
            double l[3] = {0.5 - p[0], 3.0, 1 - p[2]};
            double dist2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
            double cos_l = l[1] / sqrt(dist2);
            for (int c = 0; c < 3; c++) {
                double want = kd[c] / PI * 20.0 * cos_l / dist2;
                for (int k = 0; k < 2; k++) {
                    double err = fabs(pixel(&quad[k], i, j, c) - want) / want;
                    worst[k] = err > worst[k] ? err : worst[k];
                }
                double err_ball = fabs(pixel(&ball, i, j, c) - pixel(&quad[0], i, j, c)) / want;
                worst_ball = err_ball > worst_ball ? err_ball : worst_ball;
            }
            floor_pixels++;
        }
    }
    CHECK(floor_pixels > 500, "quad floor: only %d pixels see the floor", floor_pixels);
    for (int k = 0; k < 2; k++)
        CHECK(worst[k] < 1e-4,
              "quad floor of half-size %s: %.2e relative error against the "
              "closed form",
              halves[k], worst[k]);
    CHECK(worst_ball < 2e-3, "quad floor: %.2e relative difference from the huge sphere floor",
          worst_ball);
    film_free(&quad[0]);
    film_free(&quad[1]);
    film_free(&ball);
}

/* The six faces of the box [-1, 1]^3 as quads of material `face`, appended to text. */
static void box_text(char *text, size_t size, const char *face) {
    static const int corners[6][4][3] = {
        {{-1, -1, -1}, {1, -1, -1}, {1, -1, 1}, {-1, -1, 1}}, /* floor */
        {{-1, 1, -1}, {-1, 1, 1}, {1, 1, 1}, {1, 1, -1}},     /* ceiling */
        {{-1, -1, -1}, {-1, -1, 1}, {-1, 1, 1}, {-1, 1, -1}}, /* left */
        {{1, -1, -1}, {1, 1, -1}, {1, 1, 1}, {1, -1, 1}},     /* right */
        {{-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1}},     /* back */
        {{-1, -1, -1}, {-1, 1, -1}, {1, 1, -1}, {1, -1, -1}}, /* front */
    };
    for (int f = 0; f < 6; f++) {
        size_t at = strlen(text);
        snprintf(text + at, size - at, "quad %s", face);
        for (int k = 0; k < 4; k++) {
            at = strlen(text);
            snprintf(text + at, size - at, " v%d %d %d %d", k, corners[f][k][0], corners[f][k][1],
                     corners[f][k][2]);
        }
        at = strlen(text);
        snprintf(text + at, size - at, "\n");
    }
}

/* A sphere of radius 1 at the origin as `rings` x 2 rings triangles whose shared corners are
 * written from one table (the same decimal text, so the same floats), appended to text. */
static void tessellated_sphere_text(char *text, size_t size, int rings, const char *face) {
    int segments = 2 * rings;
    char(*corner)[64] = calloc((size_t)(rings + 1) * segments, sizeof *corner);
    for (int a = 0; a <= rings; a++) {
        for (int b = 0; b < segments; b++) {
            double theta = PI * a / rings, phi = 2 * PI * b / segments;
            double x = a == 0 || a == rings ? 0 : sin(theta) * cos(phi);
            double z = a == 0 || a == rings ? 0 : sin(theta) * sin(phi);
            snprintf(corner[a * segments + b], 64, "%.9g %.9g %.9g", x, cos(theta), z);
        }
    }
    for (int a = 0; a < rings; a++) {
        for (int b = 0; b < segments; b++) {
            int b1 = (b + 1) % segments;
            const char *p00 = corner[a * segments + b], *p01 = corner[a * segments + b1];
            const char *p10 = corner[(a + 1) * segments + b],
                       *p11 = corner[(a + 1) * segments + b1];
            size_t at = strlen(text);
            if (a > 0)
                at += (size_t)snprintf(text + at, size - at, "triangle %s v0 %s v1 %s v2 %s\n",
                                       face, p00, p10, p01);
            if (a < rings - 1)
                snprintf(text + at, size - at, "triangle %s v0 %s v1 %s v2 %s\n", face, p01, p10,
                         p11);
        }
    }
    free(corner);
}

/* Renders the surface's text seen from inside it, after the settings `header` (plane pixel
 * size, background and render line), into f; false on failure. */
static bool render_inside(const char *header, const char *surface, film *f) {
    size_t size = strlen(surface) + 512;
    char *text = malloc(size);
    snprintf(text, size,
             "camera position 0.1 0.05 -0.2 direction 0.3 0.2 1\nplane width 2 height 2 %s\n%s",
             header, surface);
    bool ok = render_text(text, f);
    free(text);
    return ok;
}

/* Inside a closed surface of black faces with a white background and no light, every pixel is
 * exactly 0: a ray that slipped between two faces would see the background. Jittered rays, many
 * through edges and corners. */
static void expect_closed(const char *name, const char *surface) {
    film f = {0};
    CHECK(render_inside("pixel 0.015625\nbackground 1 1 1\nrender samples 4 indirect off", surface,
                        &f),
          "%s: render failed", name);
    if (!f.accum) return;
    int leaks = 0;
    for (int j = 0; j < f.height; j++)
        for (int i = 0; i < f.width; i++) leaks += pixel(&f, i, j, 0) != 0.0;
    CHECK(leaks == 0, "%s: %d of %d pixels see the background", name, leaks, f.width * f.height);
    film_free(&f);
}

static char big_text[1 << 20];

static void test_watertight(void) {
    big_text[0] = '\0';
    box_text(big_text, sizeof big_text, "lambertian color 0 0 0");
    expect_closed("box of quads", big_text);
    big_text[0] = '\0';
    tessellated_sphere_text(big_text, sizeof big_text, 24, "lambertian color 0 0 0");
    expect_closed("tessellated sphere", big_text);
}

/* Path mode inside a closed surface whose faces all emit Le = 1 with albedo a = 0.5: every
 * pixel sees 1 + a + ... + a^B, B = 24, roulette off. */
static void expect_furnace(const char *name, const char *surface) {
    film f = {0};
    CHECK(render_inside("pixel 0.0625\nbackground 5 5 5\nrender mode path bounces 24 roulette "
                        "off samples 32",
                        surface, &f),
          "%s: render failed", name);
    if (!f.accum) return;
    double sum = 0.0, sum2 = 0.0;
    int n = f.width * f.height;
    for (int j = 0; j < f.height; j++) {
        for (int i = 0; i < f.width; i++) {
            double v = pixel(&f, i, j, 1);
            sum += v, sum2 += v * v;
        }
    }
    double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / (n - 1));
    double want = (1.0 - pow(0.5, 25)) / 0.5;
    CHECK(fabs(mean - want) <= SIGMAS * se + 1e-5 * want, "%s: %.6f +- %.6f, want %.6f", name, mean,
          se, want);
    film_free(&f);
}

static void test_furnace(void) {
    big_text[0] = '\0';
    box_text(big_text, sizeof big_text, "lambertian color 0.5 0.5 0.5 emission 1 1 1");
    expect_furnace("furnace box", big_text);
    big_text[0] = '\0';
    tessellated_sphere_text(big_text, sizeof big_text, 12,
                            "lambertian color 0.5 0.5 0.5 emission 1 1 1");
    expect_furnace("furnace tessellated sphere", big_text);
}

/* The form factor from a point to the rectangle [0, a] x [0, b] in a parallel plane at height
 * c, its corner above the point (Howell's catalogue, C-11), signed by the signs of a and b. */
static double corner_form_factor(double a, double b, double c) {
    double x = fabs(a) / c, y = fabs(b) / c;
    double f = (x / sqrt(1 + x * x) * atan(y / sqrt(1 + x * x)) +
                y / sqrt(1 + y * y) * atan(x / sqrt(1 + y * y))) /
               (2 * PI);
    return (a < 0 ? -f : f) * (b < 0 ? -1 : 1);
}

/* From the floor point (x, z) to the square [x0, x1] x [z0, z1] at height c. */
static double square_form_factor(double x, double z, double x0, double x1, double z0, double z1,
                                 double c) {
    return corner_form_factor(x1 - x, z1 - z, c) - corner_form_factor(x0 - x, z1 - z, c) -
           corner_form_factor(x1 - x, z0 - z, c) + corner_form_factor(x0 - x, z0 - z, c);
}

/* Direct light (path mode, one bounce) of a square emitter of side s = 1 at a height over a
 * Lambertian floor of albedo rho: the floor's radiance is rho Le F, F the form factor from the
 * floor point to the square. The ratio of each pixel to its exact value averages to 1. At height 1
 * light sampling takes the emitter by area, at 0.25 (within half its diagonal of its plane)
 * by solid angle. */
static void expect_form_factor(double height) {
    char text[512];
    snprintf(text, sizeof text,
             "camera position 0 0.5 -2 direction 0 -1 2 up 0 1 0\nplane width 0.5 height 0.5 "
             "pixel 0.03125\nquad lambertian v0 -10 0 -10 v1 -10 0 10 v2 10 0 10 v3 10 0 -10 "
             "color 0.6 0.6 0.6\nquad lambertian v0 -0.5 %g -0.5 v1 0.5 %g -0.5 v2 0.5 %g 0.5 v3 "
             "-0.5 %g 0.5 color 0 0 0 emission 2 2 2\nrender mode path bounces 1 samples 256\n",
             height, height, height, height);
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) {
        CHECK(false, "form factor: scene refused");
        return;
    }
    o.no_jitter = true;
    film f = {0};
    CHECK(render_on(use_vulkan, &s, &o, &f), "form factor: render failed");
    scene_free(&s);
    if (!f.accum) return;
    double fw[3] = {0, -1, 2}, n = sqrt(5.0);
    for (int a = 0; a < 3; a++) fw[a] /= n;
    double r[3] = {fw[2], 0, -fw[0]}, rl = sqrt(r[0] * r[0] + r[2] * r[2]);
    r[0] /= rl, r[2] /= rl;
    double u[3] = {fw[1] * r[2] - fw[2] * r[1], fw[2] * r[0] - fw[0] * r[2],
                   fw[0] * r[1] - fw[1] * r[0]};
    double sum = 0.0, sum2 = 0.0;
    int count = 0;
    for (int j = 0; j < f.height; j++) {
        for (int i = 0; i < f.width; i++) {
            double d[3];
            camera_ray(r, u, fw, 0.5, 0.5, 0.03125, i, j, d);
            double t = -0.5 / d[1], x = t * d[0], z = -2 + t * d[2];
            double want = 0.6 * 2.0 * square_form_factor(x, z, -0.5, 0.5, -0.5, 0.5, height);
            double ratio = pixel(&f, i, j, 0) / want;
            sum += ratio, sum2 += ratio * ratio, count++;
        }
    }
    double mean = sum / count, se = sqrt(fmax(sum2 / count - mean * mean, 0.0) / (count - 1));
    printf("form factor at height %g: ratio %.5f +- %.5f\n", height, mean, se);
    CHECK(fabs(mean - 1.0) <= SIGMAS * se + 1e-4, "form factor at %g: ratio %.5f +- %.5f, want 1",
          height, mean, se);
    CHECK(se < 0.01, "form factor at %g: standard error %.4f, too noisy to tell", height, se);
    film_free(&f);
}

static void test_form_factor(void) {
    expect_form_factor(1.0);
    expect_form_factor(0.25);
}

/* A mirror square facing the camera whose shading normals all lean 20 degrees about y turns a
 * camera ray d = +z about them, to d - 2 (n . d) n: in path mode every pixel sees the emitter
 * placed on that ray, Le exactly; with no normals (the face's own) the rays come back to the
 * camera and see the background. In report mode a sphere there, lit from behind the camera, is
 * seen instead. */
static void expect_mirror_normals(const char *mode, const char *target, bool emits) {
    const double lean = 20.0 * PI / 180.0, n[3] = {sin(lean), 0.0, -cos(lean)};
    double r[3] = {0.0, 0.0, 1.0}, centre[3];
    for (int a = 0; a < 3; a++) r[a] -= 2.0 * n[2] * n[a];
    for (int a = 0; a < 3; a++) centre[a] = (a == 2 ? 5.0 : 0.0) + 10.0 * r[a];
    char normals[160], text[2048];
    snprintf(normals, sizeof normals, "n0 %.6f 0 %.6f n1 %.6f 0 %.6f n2 %.6f 0 %.6f", n[0], n[2],
             n[0], n[2], n[0], n[2]);
    for (int smooth = 0; smooth < 2; smooth++) {
        snprintf(text, sizeof text,
                 "camera position 0 0 0 direction 0 0 1 up 0 1 0 fov 1\n"
                 "plane width 0.04 height 0.04 pixel 0.01\nbackground 0.25 0.25 0.25\n"
                 "render mode %s samples 2\nlight position 0 0 -1 power 400\n"
                 "triangle mirror v0 -1 -1 5 v1 1 1 5 v2 1 -1 5 %s\n"
                 "triangle mirror v0 -1 -1 5 v1 -1 1 5 v2 1 1 5 %s\n"
                 "sphere %s center %.6f %.6f %.6f radius 2\n",
                 mode, smooth ? normals : "", smooth ? normals : "", target, centre[0], centre[1],
                 centre[2]);
        film f = {0};
        bool ok = render_text(text, &f);
        CHECK(ok, "mirror normals %s: render failed", mode);
        if (!ok) continue;
        for (int j = 0; j < f.height; j++)
            for (int i = 0; i < f.width; i++) {
                double v = pixel(&f, i, j, 1);
                if (!smooth)
                    CHECK(v == 0.25,
                          "mirror normals %s, flat: pixel %d %d is %g, not the background", mode, i,
                          j, v);
                else if (emits)
                    CHECK(v == 3.0, "mirror normals %s: pixel %d %d is %g, want Le 3", mode, i, j,
                          v);
                else
                    CHECK(v > 0.0 && v != 0.25,
                          "mirror normals %s: pixel %d %d is %g, not the lit sphere", mode, i, j,
                          v);
            }
        film_free(&f);
    }
}

static void test_mirror_normals(void) {
    expect_mirror_normals("path", "lambertian color 0 0 0 emission 3 3 3", true);
    expect_mirror_normals("seed", "lambertian color 0.5 0.5 0.5", false);
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_triangles: no Vulkan device, skipped\n");
        return 77;
    }
    CHECK_CASE(test_quad_floor);
    CHECK_CASE(test_watertight);
    CHECK_CASE(test_furnace);
    CHECK_CASE(test_form_factor);
    CHECK_CASE(test_mirror_normals);
    return check_summary(use_vulkan ? "test_triangles vulkan" : "test_triangles cpu");
}
