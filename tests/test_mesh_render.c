/* test_mesh_render.c: what meshes from files look like where only rendering shows it: a glass
 * slab whose file normals lean bends a camera ray about them onto a lit sphere (and passes it
 * straight on without them), and path mode inside a closed UV sphere of emitting faces keeps the
 * furnace's closed form, flat and with `smooth on`. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "check.h"
#include "mesh_test.h"
#include "tmp_dir.h"

#define PI 3.14159265358979323846
#define SIGMAS 4.5

/* A glass slab (z from 5 to 5.2; in the right-handed file, -5 to -5.2, its normals' z negated
 * and its faces wound the other way) whose front face's file normals lean 20 degrees about y bends
 * a camera ray d = +z about them, then about the back face's own normal (Snell's law twice, report
 * mode: glass always refracts): the pixels see a lit sphere placed on that ray; the same slab
 * without file normals (smooth on generates none across its right angles) passes the ray
 * straight on, to the background. */
static void test_glass_normals(void) {
    const double lean = 20.0 * PI / 180.0, n[3] = {sin(lean), 0.0, -cos(lean)}, ior = 1.5;
    double eta = 1.0 / ior, c1 = -n[2], k = 1.0 - eta * eta * (1.0 - c1 * c1), r1[3], r2[3];
    for (int a = 0; a < 3; a++) r1[a] = eta * (a == 2) + (eta * c1 - sqrt(k)) * n[a];
    k = 1.0 - ior * ior * (1.0 - r1[2] * r1[2]); /* leaving through z = 5.2, normal -z facing */
    double len = 0.0;
    for (int a = 0; a < 3; a++) r2[a] = ior * r1[a] - (a == 2) * (ior * r1[2] - sqrt(k));
    for (int a = 0; a < 3; a++) len += r2[a] * r2[a];
    double exit_x = 0.2 * r1[0] / r1[2], target[3] = {exit_x, 0.0, 5.2};
    for (int a = 0; a < 3; a++) target[a] += 10.0 * r2[a] / sqrt(len);
    static const char *corners =
        "v -1 -1 -5\nv 1 -1 -5\nv 1 1 -5\nv -1 1 -5\n"
        "v -1 -1 -5.2\nv 1 -1 -5.2\nv 1 1 -5.2\nv -1 1 -5.2\n";
    char obj[1024], text[1024];
    snprintf(obj, sizeof obj,
             "%svn %.6f 0 %.6f\nvn 0 0 -1\nvn 0 -1 0\nvn 0 1 0\nvn -1 0 0\nvn 1 0 0\n"
             "f 1//1 2//1 3//1 4//1\nf 5//2 8//2 7//2 6//2\nf 1//3 5//3 6//3 2//3\n"
             "f 4//4 3//4 7//4 8//4\nf 1//5 4//5 8//5 5//5\nf 2//6 6//6 7//6 3//6\n",
             corners, n[0], -n[2]);
    write_text("slab_lean.obj", obj);
    snprintf(obj, sizeof obj,
             "%sf 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n", corners);
    write_text("slab.obj", obj);
    for (int lean_on = 0; lean_on < 2; lean_on++) {
        snprintf(text, sizeof text,
                 "camera position 0 0 0 direction 0 0 1 up 0 1 0 fov 1\n"
                 "plane width 0.04 height 0.04 pixel 0.01\nbackground 0.25 0.25 0.25\n"
                 "render mode seed samples 2\nlight position %.6f 0 %.6f power 100\n"
                 "mesh refractive file %s ior 1.5 smooth on\n"
                 "sphere lambertian center %.6f %.6f %.6f radius 1 color 0.5 0.5 0.5\n",
                 target[0], target[2] - 5.0, lean_on ? "slab_lean.obj" : "slab.obj", target[0],
                 target[1], target[2]);
        scene s;
        scene_error err;
        film f = {0};
        bool ok = parse(text, 1, &s, &err);
        CHECK(ok, "glass normals: %s", err.message);
        if (!ok) continue;
        ok = render(&s, &f);
        CHECK(ok, "glass normals: render failed");
        for (int j = 0; ok && j < f.height; j++)
            for (int i = 0; i < f.width; i++) {
                const float *px = &f.accum[((size_t)j * f.width + i) * 4];
                double v = px[1] / px[3];
                if (lean_on)
                    CHECK(v > 0.0 && v != 0.25, "glass normals: pixel %d %d is %g, not the sphere",
                          i, j, v);
                else
                    CHECK(v == 0.25, "glass, no normals: pixel %d %d is %g, not the background", i,
                          j, v);
            }
        film_free(&f);
        scene_free(&s);
    }
}

/* Path mode inside a closed mesh whose faces all emit 1 with albedo 0.5: every pixel sees
 * 1 + a + ... + a^24 (test_triangles.c's furnace), with flat faces and with `smooth on`, whose
 * shading normals fold the directions below a face above it (DESIGN section 3.3) rather than end
 * those paths (which lost 0.33% of the energy on this sphere). */
static void expect_mesh_furnace(const char *smooth) {
    char text[512];
    snprintf(text, sizeof text,
             "camera position 0.1 0.05 -0.2 direction 0.3 0.2 1\nplane width 2 height 2 "
             "pixel 0.0625\nbackground 5 5 5\nrender mode path bounces 24 roulette off "
             "samples 32\nmesh lambertian file sphere.obj scale 3 smooth %s color 0.5 0.5 "
             "0.5 emission 1 1 1\n",
             smooth);
    scene s;
    scene_error err;
    bool ok = parse(text, 1, &s, &err);
    CHECK(ok, "furnace, smooth %s: %s", smooth, err.message);
    if (!ok) return;
    film f = {0};
    CHECK(render(&s, &f), "furnace, smooth %s: render failed", smooth);
    if (f.accum) {
        double sum = 0.0, sum2 = 0.0;
        int n = f.width * f.height;
        for (int k = 0; k < n; k++) {
            double v = f.accum[k * 4 + 1] / f.accum[k * 4 + 3];
            sum += v, sum2 += v * v;
        }
        double mean = sum / n, se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / (n - 1));
        double want = (1.0 - pow(0.5, 25)) / 0.5;
        CHECK(fabs(mean - want) <= SIGMAS * se + 1e-5 * want,
              "furnace, smooth %s: %.6f +- %.6f, want %.6f", smooth, mean, se, want);
        printf("furnace, smooth %s: %.6f +- %.6f, want %.6f\n", smooth, mean, se, want);
    }
    film_free(&f);
    scene_free(&s);
}

static void test_furnace(void) {
    write_sphere(12, 16);
    expect_mesh_furnace("off");
    expect_mesh_furnace("on");
}

int main(void) {
    if (!tmp_dir_make("test_mesh_render")) {
        printf("cannot make a temporary folder\n");
        return 1;
    }
    CHECK_CASE(test_glass_normals);
    CHECK_CASE(test_furnace);
    return check_summary("test_mesh_render");
}
