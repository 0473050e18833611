/* test_aov.c: the feature images (render --aov, render/cpu/render_aov.c) on the back end named
 * by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 when no device exists): the albedo of a
 * Lambertian quad is its colour, through a mirror the colour it shows times the tint; a sphere's
 * normal and a plane's depth at a pixel are the closed forms'; parts split by region and by
 * samples merge to the whole render's feature images byte for byte, through their files too; and
 * the Vulkan back end's parts carry the very feature images of the CPU back end's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "image/aov.h"
#include "render/part.h"
#include "render/render.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"

static backend_choice backend = BACKEND_CPU;

/* Every feature image. */
#define ALL_AOVS ((1u << AOV_COUNT) - 1u)

/* Renders region x0,x1,y0,y1 and samples begin:end of the scene text (jitter as `jitter` says)
 * with every feature image into p, on `on`; false on failure. */
static bool render_part_of(const char *text, bool jitter, int x0, int x1, int y0, int y1,
                           uint32_t begin, uint32_t end, backend_choice on, part *p) {
    scene s;
    render_opts o;
    *p = (part){0};
    if (!parse_scene_text(text, &s, &o)) return false;
    o.no_jitter = !jitter;
    o.validate = on == BACKEND_VULKAN;
    o.aov = ALL_AOVS;
    part_meta m;
    render_part_meta(&s, &o, &m);
    if (x1 > 0) m.x0 = x0, m.x1 = x1, m.y0 = y0, m.y1 = y1;
    m.sample_begin = begin;
    const char *used;
    bool ok = part_init(p, &m) && render_choose_part(&s, &o, on, p, end, &used);
    scene_free(&s);
    return ok;
}

/* Channel c of feature image k at image pixel (x, y) of a part. */
static float feature(const part *p, aov_kind k, int x, int y, int c) {
    size_t i =
        (size_t)(y - p->meta.y0) * (size_t)(p->meta.x1 - p->meta.x0) + (size_t)(x - p->meta.x0);
    return p->aov.plane[k][(size_t)aov_channels(k) * i + (size_t)c];
}

static bool near(double got, double want, double tol) { return fabs(got - want) <= tol; }

/* A 20 x 20 view from (0, 0, -10) along +z: the plane 0.8 ahead, 0.4 wide. */
#define VIEW "camera position 0 0 -10\nplane width 0.4 height 0.4 pixel 0.02\n"
#define LIGHT "light position 0 0 -10 power 100\n"

/* The unit direction of the centre of pixel (i, j) of VIEW, in double. */
static void view_direction(int i, int j, double d[3]) {
    double x = -0.2 + (i + 0.5) * 0.02, y = 0.2 - (j + 0.5) * 0.02, z = 0.8;
    double n = sqrt(x * x + y * y + z * z);
    d[0] = x / n, d[1] = y / n, d[2] = z / n;
}

static void test_quad_albedo(void) {
    const char *text = VIEW LIGHT
        "quad lambertian v0 -5 -5 5 v1 5 -5 5 v2 5 5 5 v3 -5 5 5 color 0.3 0.55 0.7\n"
        "render samples 16\n";
    part p;
    EXPECT(render_part_of(text, true, 0, 0, 0, 0, 0, 16, backend, &p));
    const float want[3] = {0.3f, 0.55f, 0.7f};
    for (int y = 0; p.aov.mask && y < 20; y += 7)
        for (int x = 0; x < 20; x += 7)
            for (int c = 0; c < 3; c++) /* the mean of 4 equal floats: two roundings of an ulp */
                CHECK(near(feature(&p, AOV_ALBEDO, x, y, c), want[c], 2e-7),
                      "albedo (%d, %d) channel %d = %.9g, want %.9g", x, y, c,
                      feature(&p, AOV_ALBEDO, x, y, c), want[c]);
    part_free(&p);
}

static void test_mirror_albedo(void) {
    /* a mirror of tint 0.5 facing the camera shows the red quad behind the camera */
    const char *text = VIEW LIGHT
        "quad mirror v0 -5 -5 5 v1 5 -5 5 v2 5 5 5 v3 -5 5 5 color 0.5 0.5 0.5\n"
        "quad lambertian v0 -50 -50 -20 v1 -50 50 -20 v2 50 50 -20 v3 50 -50 -20 color 0.8 0.2 "
        "0.4\n"
        "render samples 4\n";
    part p;
    EXPECT(render_part_of(text, false, 0, 0, 0, 0, 0, 4, backend, &p));
    const float want[3] = {0.4f, 0.1f, 0.2f};
    for (int c = 0; p.aov.mask && c < 3; c++)
        CHECK(near(feature(&p, AOV_ALBEDO, 10, 10, c), want[c], 1e-6),
              "mirror albedo channel %d = %.9g, want %.9g", c, feature(&p, AOV_ALBEDO, 10, 10, c),
              want[c]);
    /* the normal is the red quad's, facing the ray back from the mirror: -z */
    if (p.aov.mask)
        CHECK(near(feature(&p, AOV_NORMAL, 10, 10, 2), 1.0, 1e-6),
              "normal through the mirror z = %.9g, want 1", feature(&p, AOV_NORMAL, 10, 10, 2));
    part_free(&p);
}

static void test_sphere_normal(void) {
    const char *text = VIEW LIGHT
        "sphere lambertian center 0 0 0 radius 1 color 0.5 0.5 0.5\n"
        "render samples 4\n";
    part p;
    EXPECT(render_part_of(text, false, 0, 0, 0, 0, 0, 4, backend, &p));
    const int pixels[3][2] = {{12, 7}, {10, 10}, {8, 11}};
    for (int k = 0; p.aov.mask && k < 3; k++) {
        int i = pixels[k][0], j = pixels[k][1];
        double d[3], o[3] = {0.0, 0.0, -10.0};
        view_direction(i, j, d);
        double b = d[0] * o[0] + d[1] * o[1] + d[2] * o[2];
        double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - 1.0;
        double t = -b - sqrt(b * b - c); /* the near root */
        for (int a = 0; a < 3; a++) {
            double want = o[a] + t * d[a]; /* the unit sphere's normal is the point */
            CHECK(near(feature(&p, AOV_NORMAL, i, j, a), want, 2e-5),
                  "sphere normal (%d, %d) axis %d = %.9g, want %.9g", i, j, a,
                  feature(&p, AOV_NORMAL, i, j, a), want);
            CHECK(near(feature(&p, AOV_POSITION, i, j, a), want, 2e-5),
                  "sphere position (%d, %d) axis %d = %.9g, want %.9g", i, j, a,
                  feature(&p, AOV_POSITION, i, j, a), want);
        }
        CHECK(near(feature(&p, AOV_DEPTH, i, j, 0), t, 2e-5 * t),
              "sphere depth (%d, %d) = %.9g, want %.9g", i, j, feature(&p, AOV_DEPTH, i, j, 0), t);
    }
    /* a corner misses it: no depth, no albedo */
    if (p.aov.mask) {
        EXPECT(isinf(feature(&p, AOV_DEPTH, 0, 0, 0)));
        EXPECT(feature(&p, AOV_ALBEDO, 0, 0, 0) == 0.0f);
    }
    part_free(&p);
}

static void test_plane_depth(void) {
    const char *text = VIEW LIGHT
        "quad lambertian v0 -5 -5 5 v1 5 -5 5 v2 5 5 5 v3 -5 5 5 color 0.5 0.5 0.5\n"
        "render samples 4\n";
    part p;
    EXPECT(render_part_of(text, false, 0, 0, 0, 0, 0, 4, backend, &p));
    for (int j = 0; p.aov.mask && j < 20; j += 3)
        for (int i = 0; i < 20; i += 5) {
            double d[3];
            view_direction(i, j, d);
            double t = 15.0 / d[2]; /* from z = -10 to the plane z = 5 */
            CHECK(near(feature(&p, AOV_DEPTH, i, j, 0), t, 2e-6 * t),
                  "plane depth (%d, %d) = %.9g, want %.9g", i, j, feature(&p, AOV_DEPTH, i, j, 0),
                  t);
            CHECK(near(feature(&p, AOV_NORMAL, i, j, 2), -1.0, 1e-6), "plane normal z = %.9g",
                  feature(&p, AOV_NORMAL, i, j, 2));
        }
    part_free(&p);
}

/* A scene of every kind the features meet: glass, mirror, emitter, a miss, in path mode. */
static const char *const mixed =
    "camera position 0 1 -8\nplane width 0.48 height 0.36 pixel 0.02\n"
    "sphere lambertian center 0 -1001 0 radius 1000 color 0.8 0.8 0.8\n"
    "sphere refractive center -1 0 2 radius 1 ior 1.5\n"
    "sphere mirror center 1.2 0 3 radius 1 color 0.9 0.8 0.7\n"
    "sphere lambertian center 0 3 4 radius 0.5 emission 4 4 4\n"
    "render samples 40 mode path\n";

static bool same_aov(const part *a, const part *b, const char *what) {
    bool same = a->aov.mask == b->aov.mask && a->aov.mask;
    size_t n = (size_t)(a->meta.x1 - a->meta.x0) * (size_t)(a->meta.y1 - a->meta.y0);
    for (int k = 0; same && k < AOV_COUNT; k++)
        same = !memcmp(a->aov.plane[k], b->aov.plane[k],
                       n * (size_t)aov_channels((aov_kind)k) * sizeof(float));
    CHECK(same, "%s: feature images differ", what);
    return same;
}

static void test_merge(void) {
    part whole, parts[4], merged, back;
    EXPECT(render_part_of(mixed, true, 0, 0, 0, 0, 0, 40, backend, &whole));
    EXPECT(render_part_of(mixed, true, 0, 10, 0, 18, 0, 16, backend, &parts[0]));
    EXPECT(render_part_of(mixed, true, 0, 10, 0, 18, 16, 40, backend, &parts[1]));
    EXPECT(render_part_of(mixed, true, 10, 24, 0, 18, 0, 32, backend, &parts[2]));
    EXPECT(render_part_of(mixed, true, 10, 24, 0, 18, 32, 40, backend, &parts[3]));
    EXPECT(parts[1].aov.mask == 0 && parts[3].aov.mask == 0); /* not of chunk 0 */
    /* the files carry them too */
    char path[64];
    snprintf(path, sizeof path, "test_aov_part_%d.exr", (int)getpid());
    EXPECT(part_write(path, &parts[2]) && part_read(path, &back));
    remove(path);
    same_aov(&parts[2], &back, "a part read back");
    part_free(&back);
    const char *names[4] = {"a", "b", "c", "d"};
    EXPECT(part_merge(parts, names, 4, &merged));
    same_aov(&whole, &merged, "merged parts");
    film fw, fm;
    EXPECT(part_film(&whole, &fw) && part_film(&merged, &fm));
    same_aov(&whole, &(part){.meta = whole.meta, .aov = fm.aov}, "the merged film");
    film_free(&fw);
    film_free(&fm);
    part_free(&merged);
    for (int k = 0; k < 4; k++) part_free(&parts[k]);
    /* the Vulkan back end's parts carry the CPU back end's very feature images */
    if (backend == BACKEND_VULKAN) {
        part cpu;
        EXPECT(render_part_of(mixed, true, 0, 0, 0, 0, 0, 40, BACKEND_CPU, &cpu));
        same_aov(&whole, &cpu, "vulkan against cpu");
        part_free(&cpu);
    }
    part_free(&whole);
}

int main(int argc, char **argv) {
    if (argc > 1 && !strcmp(argv[1], "vulkan")) {
        if (vk_context_device_count() == 0) {
            printf("test_aov vulkan: no Vulkan device, skipped\n");
            return 77;
        }
        backend = BACKEND_VULKAN;
    }
    CHECK_CASE(test_quad_albedo);
    CHECK_CASE(test_mirror_albedo);
    CHECK_CASE(test_sphere_normal);
    CHECK_CASE(test_plane_depth);
    CHECK_CASE(test_merge);
    return check_summary(backend == BACKEND_VULKAN ? "test_aov vulkan" : "test_aov");
}
