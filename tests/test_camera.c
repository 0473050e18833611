/* test_camera.c: the thin lens and the orthographic camera against closed forms, on the CPU back
 * end or (argument "vulkan") the Vulkan one: a lit square on the plane in focus keeps its edges
 * sharp; an out-of-focus point's blur disc has the circle of confusion's diameter in pixels; an
 * orthographic sphere's silhouette is r / pixel across whatever its distance; the keys' refusals
 * (file:line:col). Scenes are path mode's emission alone (bounces 0), so a pixel's value is the
 * share of its rays that meet the emitter. */
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

static bool use_vulkan;

/* Renders the scene text printf makes of fmt into f; false (printed) on failure. */
static bool render_format(film *f, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static bool render_format(film *f, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* The mean of pixel (i, j)'s red channel. */
static double pixel_mean(const film *f, int i, int j) {
    const float *px = &f->accum[((size_t)j * f->width + i) * 4];
    return px[3] > 0.0f ? px[0] / px[3] : 0.0;
}

/* Camera at the origin looking along +z, the plane 2 away (2 x width), 32 x 32 pixels of 1/32:
 * a pixel spans 1/16 at depth 4. */
#define SQUARE_SCENE                                                       \
    "camera position 0 0 0 %s\nplane width 1 height 1 pixel 0.03125\n"     \
    "quad lambertian v0 -%g -%g %g v1 %g -%g %g v2 %g %g %g v3 -%g %g %g " \
    "color 0 0 0 emission 1 1 1\nrender mode path bounces 0 samples 64\n"

/* Renders the emitting square of half-size h at depth z seen through the camera keys lens, and
 * counts its pixels: lit (above 0.98), dark (below 0.02) and between. */
static void square_pixels(const char *lens, double h, double z, int counts[3]) {
    film f = {0};
    counts[0] = counts[1] = counts[2] = 0;
    bool ok = render_format(&f, SQUARE_SCENE, lens, h, h, z, h, h, z, h, h, z, h, h, z);
    CHECK(ok, "rendering the square (%s)", lens);
    if (!ok) return;
    for (int j = 0; j < f.height; j++)
        for (int i = 0; i < f.width; i++) {
            double v = pixel_mean(&f, i, j);
            counts[v > 0.98 ? 0 : v < 0.02 ? 1 : 2]++;
        }
    film_free(&f);
}

/* A square on the plane in focus, its edges on pixel edges (8 x 8 pixels at depth 4), stays
 * sharp through a wide lens: every pixel wholly lit or dark. The same square twice as far (and
 * twice as big, the same pixels) blurs over many pixels: the lens does blur. */
static void test_focus_sharp(void) {
    int c[3];
    square_pixels("aperture 0.2 focus 4", 0.25, 4.0, c);
    CHECK(c[0] == 64 && c[1] == 1024 - 64 && c[2] == 0,
          "in focus: %d lit, %d dark, %d between (want 64, 960, 0)", c[0], c[1], c[2]);
    square_pixels("aperture 0.2 focus 4", 0.5, 8.0, c);
    CHECK(c[2] >= 40, "out of focus: only %d pixels between lit and dark", c[2]);
    square_pixels("", 0.5, 8.0, c);
    CHECK(c[0] == 64 && c[2] == 0, "pinhole: %d lit, %d between (want 64, 0)", c[0], c[2]);
}

/* A small emitting sphere (radius r) at depth z, focus f, lens radius a, through a 64 x 64 image
 * of pixels p on a plane d = 2 away: each lens point sees it at its own place on the plane in
 * focus, so the image is a disc of the circle of confusion's radius R = a |z - f| d / (z f p)
 * pixels, blurred by the sphere's own image (radius rho = r d / (z p)) and by the pixel's box.
 * Second moments add under that blur: sum w r^2 / sum w about the centroid is R^2 / 2 + rho^2 / 2
 * + 1 / 6. */
static void test_circle_of_confusion(void) {
    const double a = 0.4, f = 4.0, z = 8.0, r = 0.1, d = 2.0, p = 1.0 / 64.0;
    film img = {0};
    bool ok = render_format(&img,
                            "camera position 0 0 0 aperture %g focus %g\n"
                            "plane width 1 height 1 pixel 0.015625\n"
                            "sphere lambertian center 0.05 -0.03 %g radius %g color 0 0 0 "
                            "emission 1 1 1\nrender mode path bounces 0 samples 256\n",
                            a, f, z, r);
    CHECK(ok, "rendering the point");
    if (!ok) return;
    double sw = 0, sx = 0, sy = 0;
    for (int j = 0; j < img.height; j++)
        for (int i = 0; i < img.width; i++) {
            double w = pixel_mean(&img, i, j);
            sw += w, sx += w * (i + 0.5), sy += w * (j + 0.5);
        }
    double cx = sx / sw, cy = sy / sw, m2 = 0;
    for (int j = 0; j < img.height; j++)
        for (int i = 0; i < img.width; i++) {
            double dx = i + 0.5 - cx, dy = j + 0.5 - cy;
            m2 += pixel_mean(&img, i, j) * (dx * dx + dy * dy);
        }
    m2 /= sw;
    double want = a * fabs(z - f) * d / (z * f * p), rho = r * d / (z * p);
    double got = sqrt(2.0 * (m2 - rho * rho / 2.0 - 1.0 / 6.0));
    printf("circle of confusion: diameter %.3f pixels, closed form %.3f\n", 2 * got, 2 * want);
    CHECK(fabs(got - want) < 0.02 * want, "blur disc diameter %.3f pixels, want %.3f", 2 * got,
          2 * want);
    /* its centre is where the pinhole sees the sphere's centre: (0.05, -0.03) at depth 8 */
    double want_x = 32.0 + 0.05 * d / (z * p), want_y = 32.0 + 0.03 * d / (z * p);
    CHECK(fabs(cx - want_x) < 0.1 && fabs(cy - want_y) < 0.1,
          "blur disc at %.3f %.3f, want %.3f %.3f", cx, cy, want_x, want_y);
    film_free(&img);
}

/* An orthographic camera sees a sphere of radius r as a disc of r / pixel pixels, near or far:
 * the lit share of the image is pi (r / p)^2 pixels. A perspective camera would shrink the far
 * one tenfold. */
static void test_orthographic(void) {
    const double r = 1.0, p = 0.0625;
    for (int k = 0; k < 2; k++) {
        double z = k ? 50.0 : 5.0;
        film img = {0};
        bool ok = render_format(&img,
                                "camera position 0.5 -0.25 0 projection orthographic\n"
                                "plane width 4 height 4 pixel 0.0625\n"
                                "sphere lambertian center 0.5 -0.25 %g radius %g color 0 0 0 "
                                "emission 1 1 1\nrender mode path bounces 0 samples 64\n",
                                z, r);
        CHECK(ok, "rendering the sphere at %g", z);
        if (!ok) continue;
        double lit = 0;
        for (int j = 0; j < img.height; j++)
            for (int i = 0; i < img.width; i++) lit += pixel_mean(&img, i, j);
        double radius = sqrt(lit / PI), want = r / p;
        printf("orthographic: silhouette radius %.4f pixels at depth %g, r / pixel %.4f\n", radius,
               z, want);
        CHECK(fabs(radius - want) < 0.005 * want, "silhouette radius %.4f pixels, want %.4f",
              radius, want);
        film_free(&img);
    }
}

static void test_refusals(void) {
    expect_parse_error("camera position 0 0 0 aperture -1 focus 2\n", 1, 32, "aperture must be in");
    expect_parse_error("camera position 0 0 0 aperture 0.1 focus 0\n", 1, 42, "focus must be in");
    expect_parse_error("camera position 0 0 0 aperture 0.1\n", 1, 23, "needs focus");
    expect_parse_error("camera position 0 0 0 focus 3\n", 1, 23, "needs an aperture above 0");
    expect_parse_error("camera position 0 0 0 aperture 0 focus 3\n", 1, 34, "needs an aperture");
    expect_parse_error("camera position 0 0 0 projection fisheye\n", 1, 34, "projection");
    expect_parse_error("camera position 0 0 0 projection orthographic fov 40\n", 1, 47,
                       "takes no fov");
    /* aperture 0 is the pinhole, the same scene as without it */
    scene a, b;
    render_opts oa, ob;
    if (parse_scene_text("camera position 0 0 0 aperture 0\nplane width 1 height 1 pixel 1\n", &a,
                         &oa) &&
        parse_scene_text("camera position 0 0 0\nplane width 1 height 1 pixel 1\n", &b, &ob)) {
        CHECK(a.camera_aperture == 0.0f && a.camera_focus == 0.0f && !a.camera_orthographic,
              "aperture 0 is a pinhole");
        scene_free(&a);
        scene_free(&b);
    }
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_camera: no Vulkan device, skipped\n");
        return 77;
    }
    if (!use_vulkan) CHECK_CASE(test_refusals);
    CHECK_CASE(test_focus_sharp);
    CHECK_CASE(test_circle_of_confusion);
    CHECK_CASE(test_orthographic);
    return check_summary(use_vulkan ? "test_camera vulkan" : "test_camera");
}
