/* test_environment.c: the environment map (DESIGN section 3.7, scenes/README.md `environment`),
 * on the back end named by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 when no device exists):
 * its sampling by importance against its pdf (chi-square over the map's texels, the pdf's
 * integral over the sphere), a convex Lambertian sphere under a constant map (a L in both
 * modes), a black map with one bright cap lighting a floor by the closed form, with light and
 * BSDF sampling alone agreeing; the map's refusals (file:line:col); and `--write-sky PATH`
 * writes scenes/maps/sky.exr, which the test checks is what the generator makes. */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "common/rng.h"
#include "image/exr.h"
#include "render/cpu/scene_accessors.h"
#include "render/scene_pack.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"
#include "tmp_dir.h"
/* scene_accessors.h first: the shared text reads the scene through it */
#include "common/emitter.h"

#define PI 3.14159265358979323846
#define SIGMAS 4.5

static bool use_vulkan;

/* A map of w x h texels whose texel (column c, row r) rgb fills. */
typedef void (*texel_fn)(int c, int r, int w, int h, float *rgb);

/* Writes the map as a float EXR at path; false on failure. */
static bool write_map(const char *path, int w, int h, texel_fn fill) {
    image img;
    if (!image_init(&img, w, h)) return false;
    for (int r = 0; r < h; r++)
        for (int c = 0; c < w; c++) fill(c, r, w, h, &img.rgb[3 * ((size_t)r * w + c)]);
    bool ok = exr_write_image(path, &img, false);
    image_free(&img);
    return ok;
}

/* A sky of the project's own making: a blue gradient from the horizon up, a grey ground and a
 * small sun (texels within 3 degrees, 2000 times the sky, ten times the sky's irradiance) above
 * the horizon, to the right and ahead. */
static void sky(int c, int r, int w, int h, float *rgb) {
    double theta = PI * (r + 0.5) / h, phi = 2 * PI * (c + 0.5) / w - PI;
    double d[3] = {sin(theta) * sin(phi), cos(theta), sin(theta) * cos(phi)};
    double sun[3] = {0.5, 0.6, 0.62}, l = sqrt(0.25 + 0.36 + 0.3844);
    double cos_sun = (d[0] * sun[0] + d[1] * sun[1] + d[2] * sun[2]) / l;
    double up = d[1] > 0 ? d[1] : 0;
    double base[3] = {0.9 - 0.6 * up, 1.0 - 0.4 * up, 1.2};
    for (int k = 0; k < 3; k++) rgb[k] = (float)(d[1] > 0 ? base[k] : 0.35);
    if (cos_sun > cos(3.0 * PI / 180)) rgb[0] = 2400.0f, rgb[1] = 2200.0f, rgb[2] = 1900.0f;
}

static float constant_value = 0.5f;
static void constant(int c, int r, int w, int h, float *rgb) {
    (void)c, (void)r, (void)w, (void)h;
    rgb[0] = rgb[1] = rgb[2] = constant_value;
}
/* Black but for the top row, the cap within pi / h of +y, of radiance 100. */
static void cap(int c, int r, int w, int h, float *rgb) {
    (void)c, (void)w, (void)h;
    rgb[0] = rgb[1] = rgb[2] = r == 0 ? 100.0f : 0.0f;
}
/* A map of varied texels: a gradient, a bright spot and a black band. */
static void varied(int c, int r, int w, int h, float *rgb) {
    (void)w;
    float g = (float)(c + 1) * (float)(r + 2) / (float)(w * h);
    rgb[0] = g, rgb[1] = 0.5f * g, rgb[2] = r == h / 2 ? 0.0f : 0.25f;
    if (c == 5 && r == 3) rgb[0] = rgb[1] = rgb[2] = 200.0f;
    if (r == h - 2) rgb[0] = rgb[1] = rgb[2] = 0.0f;
}

/* Parses the scene text printf makes of fmt into s and o; false (printed) on an error. */
static bool parse_format(scene *s, render_opts *o, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bool parse_format(scene *s, render_opts *o, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    return parse_scene_text(text, s, o);
}

/* environment_table_pick from its guide finds what a search from the start finds, the first k
 * whose next cdf entry exceeds u, for every table of the packed map p (w x h) at u on and beside
 * each entry and at evenly spaced u (the guide's own bounds among them). */
static void expect_guided_picks(const packed_scene *p, int w, int h) {
    int guides = (h + 1) + h * (w + 1), wrong = 0, tried = 0;
    for (int table = 0; table <= h; table++) {
        int count = table == 0 ? h : w;
        int first = table == 0 ? 0 : (h + 1) + (table - 1) * (w + 1);
        int guide = table == 0 ? guides : guides + h + (table - 1) * w;
        for (int i = 0; i < 3 * (count + 1) + 4 * count; i++) {
            float u = i < 3 * (count + 1) ? environment_float(p, first + i / 3)
                                          : (float)(i - 3 * (count + 1)) / (float)(4 * count);
            if (i < 3 * (count + 1) && i % 3 != 1) u = nextafterf(u, i % 3 ? 2.0f : -1.0f);
            if (!(u >= 0.0f && u < 1.0f)) continue;
            int want = 0;
            while (want < count - 1 && !(u < environment_float(p, first + want + 1))) want++;
            wrong += environment_table_pick(p, first, count, guide, u).k != want;
            tried++;
        }
    }
    CHECK(wrong == 0, "%d of %d guided table picks differ from the search's", wrong, tried);
}

/* The chi-square test of environment_sample_at against the texels' pdf: every texel a bin (its
 * expected share pdf / (w h)), bins expecting fewer than 5 pooled; and each sample's pdf against
 * environment_look_along's light pdf of its direction. */
static void test_sampling(void) {
    const char *map = tmp_path("varied.exr");
    CHECK(write_map(map, 32, 16, varied), "writing %s", map);
    scene s;
    render_opts o;
    if (!parse_format(&s, &o,
                      "camera position 0 0 0\nplane width 1 height 1 pixel 0.5\n"
                      "environment file %s\nrender mode path\n",
                      map)) {
        CHECK(false, "parsing the varied map");
        return;
    }
    packed_scene p;
    CHECK(scene_pack(&s, &o, &p), "packing");
    CHECK(p.frame.env_slot == 1u && p.frame.emitter_count == 1u, "the map is the one emitter");
    enum { W = 32, H = 16, SAMPLES = 1000000 };
    expect_guided_picks(&p, W, H);
    static double observed[W * H];
    uint32_t rng = rng_seed(7, 0, 0);
    int pdf_off = 0;
    for (int k = 0; k < SAMPLES; k++) {
        float ua = rng_next(&rng), ub = rng_next(&rng);
        environment_sample es = environment_sample_at(&p, ua, ub);
        int t = environment_texel_of(&p, environment_map_direction(&p, es.wi));
        observed[t] += 1.0;
        double looked_up = environment_look_along(&p, es.wi).light_pdf;
        if (fabs(looked_up - es.pdf) > 1e-3 * es.pdf) pdf_off++;
    }
    double chi2 = 0.0, pool_o = 0.0, pool_e = 0.0;
    int dof = 0;
    for (int t = 0; t < W * H; t++) {
        double expected = p.environment[t].w / (W * H) * SAMPLES;
        if (expected < 5.0) {
            pool_o += observed[t], pool_e += expected;
            continue;
        }
        chi2 += (observed[t] - expected) * (observed[t] - expected) / expected, dof++;
    }
    if (pool_e > 5.0) chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e, dof++;
    double k = dof - 1, z = (cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / sqrt(2.0 / (9.0 * k));
    CHECK(z < 4.0, "environment sampling: chi-square z score %.2f over %d bins", z, dof);
    CHECK(observed[(H - 2) * W + 3] == 0.0, "a black texel was drawn");
    /* samples near a texel's edge may look up its neighbour: a few per thousand at most */
    CHECK(pdf_off < SAMPLES / 1000, "%d samples' pdf differ from environment_look_along's",
          pdf_off);
    /* the solid-angle pdf integrates to 1 over the sphere: midpoints of 4 x 4 cells a texel, in
     * the map's (u, v), d omega = 2 pi^2 sin(theta) du dv */
    double integral = 0.0;
    for (int i = 0; i < 4 * H; i++)
        for (int j = 0; j < 4 * W; j++) {
            double theta = PI * (i + 0.5) / (4 * H), phi = 2 * PI * (j + 0.5) / (4 * W) - PI;
            vec3 d = v3((float)(sin(theta) * sin(phi)), (float)cos(theta),
                        (float)(sin(theta) * cos(phi)));
            integral +=
                environment_look_along(&p, d).light_pdf * 2 * PI * PI * sin(theta) / (16.0 * W * H);
        }
    CHECK(fabs(integral - 1.0) < 1e-4, "the environment pdf integrates to %.5f", integral);
    scene_pack_free(&p);
    scene_free(&s);
}

/* The mean and standard error of channel c's pixel means over x0..x1, y0..y1. */
typedef struct estimate {
    double mean, se;
} estimate;
static estimate region(const film *f, int c, int x0, int x1, int y0, int y1) {
    double sum = 0.0, sum2 = 0.0;
    int n = 0;
    for (int j = y0; j < y1; j++)
        for (int i = x0; i < x1; i++) {
            const float *px = &f->accum[((size_t)j * f->width + i) * 4];
            double v = px[c] / px[3];
            sum += v, sum2 += v * v, n++;
        }
    double mean = sum / n, var = (sum2 / n - mean * mean) * n / (n - 1);
    return (estimate){mean, sqrt(var > 0 ? var / n : 0)};
}
static void expect_mean(const char *name, estimate e, double want) {
    CHECK(fabs(e.mean - want) <= SIGMAS * e.se + 1e-5 * fabs(want), "%s: %.6f +- %.6f, want %.6f",
          name, e.mean, e.se, want);
}

/* Renders the scene text printf makes of fmt with the strategy into f; false on failure. */
static bool render_format(film *f, path_strategy strategy, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bool render_format(film *f, path_strategy strategy, const char *fmt, ...) {
    char text[2048];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(text, sizeof text, fmt, ap);
    va_end(ap);
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    o.strategy = strategy;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* A convex Lambertian sphere of albedo a under a constant map L: its pixels a L, the others L,
 * in path mode (light and BSDF sampling by MIS) and in report mode's one bounce. */
static void test_furnace(void) {
    const char *map = tmp_path("constant.exr");
    CHECK(write_map(map, 16, 8, constant), "writing %s", map);
    const char *modes[] = {"path bounces 8 roulette off", "report"};
    for (int m = 0; m < 2; m++) {
        film f = {0};
        CHECK(render_format(&f, PATH_MIS,
                            "camera position 0 0 -4\nplane width 1 height 1 pixel 0.0625\n"
                            "sphere lambertian center 0 0 0 radius 1 color 0.6 0.6 0.6\n"
                            "environment file %s\nrender mode %s samples 64\n",
                            map, modes[m]),
              "furnace render (%s)", modes[m]);
        if (!f.accum) continue;
        char name[96];
        snprintf(name, sizeof name, "furnace sphere (%s)", modes[m]);
        expect_mean(name, region(&f, 1, 6, 10, 6, 10), 0.6 * constant_value);
        snprintf(name, sizeof name, "furnace background (%s)", modes[m]);
        estimate corner = region(&f, 1, 0, 2, 0, 2);
        CHECK(corner.mean == constant_value, "%s: %.7f", name, corner.mean);
        film_free(&f);
    }
}

/* A floor of albedo a under a map black but for its top row of radiance L (a cap of half-angle
 * pi / h about +y) sees irradiance E = L pi sin^2(pi / h): its radiance a L sin^2(pi / h), by
 * MIS, by light sampling alone and by BSDF sampling alone (cosine-weighted); turned upside down
 * (rotate 1 0 0 180) the cap lights nothing. */
static void test_cap(void) {
    const char *map = tmp_path("cap.exr");
    CHECK(write_map(map, 32, 16, cap), "writing %s", map);
    const char *floor_scene =
        "camera position 0 1 0 direction 0 -1 0 up 0 0 1\nplane width 1 height 1 pixel 0.0625\n"
        "quad lambertian v0 -50 0 -50 v1 -50 0 50 v2 50 0 50 v3 50 0 -50 color 0.5 0.5 0.5\n"
        "environment file %s%s\nrender mode path bounces 1 samples %d\n";
    double want = 0.5 * 100.0 * pow(sin(PI / 16), 2);
    path_strategy strategies[] = {PATH_MIS, PATH_LIGHTS_ONLY, PATH_BSDF_ONLY};
    const char *names[] = {"cap, MIS", "cap, light sampling", "cap, BSDF sampling"};
    for (int k = 0; k < 3; k++) {
        film f = {0};
        CHECK(render_format(&f, strategies[k], floor_scene, map, "", k == 2 ? 1024 : 64),
              "%s: render", names[k]);
        if (!f.accum) continue;
        expect_mean(names[k], region(&f, 0, 0, f.width, 0, f.height), want);
        film_free(&f);
    }
    film f = {0};
    CHECK(render_format(&f, PATH_MIS, floor_scene, map, " rotate 1 0 0 180", 16), "turned cap");
    if (f.accum) CHECK(region(&f, 0, 0, f.width, 0, f.height).mean == 0.0, "turned cap lights");
    film_free(&f);
}

/* The variance of one sample of a floor under the shipped sky (a sun of 2000 times the sky), by
 * MIS with importance sampling against cosine-weighted BSDF sampling alone: the pixels of a
 * small patch seen from above, one sample each, all estimate nearly the same radiance, so their
 * spread is the estimator's. The ratio is how many more samples BSDF sampling needs. */
static void test_noise_ratio(void) {
    double variance[2];
    path_strategy strategies[] = {PATH_MIS, PATH_BSDF_ONLY};
    for (int k = 0; k < 2; k++) {
        film f = {0};
        CHECK(render_format(&f, strategies[k],
                            "camera position 0 1 0 direction 0 -1 0 up 0 0 1\n"
                            "plane width 0.5 height 0.5 pixel 0.0078125\n"
                            "quad lambertian v0 -50 0 -50 v1 -50 0 50 v2 50 0 50 v3 50 0 -50 "
                            "color 0.5 0.5 0.5\nenvironment file %s/scenes/maps/sky.exr\n"
                            "render mode path bounces 1 samples 1 sampler random\n",
                            TRAZADOR_SOURCE_DIR),
              "noise render");
        if (!f.accum) return;
        estimate e = region(&f, 1, 0, f.width, 0, f.height);
        variance[k] = e.se * e.se * f.width * f.height;
        film_free(&f);
    }
    double ratio = variance[1] / variance[0];
    printf("sky floor: one sample's variance %.4g by MIS, %.4g by BSDF sampling: %.1fx samples\n",
           variance[0], variance[1], ratio);
    CHECK(ratio >= 10.0, "importance sampling needs only %.1fx fewer samples", ratio);
}

static void test_refusals(void) {
    char text[1024];
    const char *square = tmp_path("square.exr"), *bad = tmp_path("bad.exr");
    const char *text_file = tmp_path("text.hdr"), *negative = tmp_path("negative.exr");
    CHECK(write_map(square, 8, 8, constant), "writing %s", square);
    constant_value = -1.0f;
    CHECK(write_map(negative, 8, 4, constant), "writing %s", negative);
    constant_value = 0.5f;
    FILE *fp = fopen(text_file, "w");
    if (fp) fputs("not an image\n", fp), fclose(fp);
    size_t len = 0;
    unsigned char *bytes = tmp_file_read(square, &len);
    fp = fopen(bad, "wb");
    if (fp && bytes) fwrite(bytes, 1, len / 2, fp);
    if (fp) fclose(fp);
    free(bytes);
    snprintf(text, sizeof text, "environment file %s/missing.exr\n", tmpdir);
    expect_parse_error(text, 1, 18, "No such file");
    snprintf(text, sizeof text, "\nenvironment file %s\n", square);
    expect_parse_error(text, 2, 18, "8 x 8 pixels");
    snprintf(text, sizeof text, "environment file %s\n", text_file);
    expect_parse_error(text, 1, 18, "neither an OpenEXR nor a Radiance HDR");
    snprintf(text, sizeof text, "environment file %s\n", bad);
    expect_parse_error(text, 1, 18, "not a readable OpenEXR");
    snprintf(text, sizeof text, "environment file %s\n", negative);
    expect_parse_error(text, 1, 18, "must be finite and >= 0");
    snprintf(text, sizeof text, "environment file %s rotate 0 0 0 30\n", square);
    expect_parse_error(text, 1, 18 + (int)strlen(square) + 1, "axis must not be zero");
    snprintf(text, sizeof text, "environment file %s intensity 0\n", square);
    expect_parse_error(text, 1, 18 + (int)strlen(square) + 11, "intensity");
    expect_parse_error("environment\n", 1, 1, "needs 'file PATH' or 'color R G B'");
    expect_parse_error("environment color 1 1\n", 1, 22, "expected 3 numbers");
    expect_parse_error("environment sky 1\n", 1, 13, "unknown key 'sky'");
    expect_parse_error("background 1 1 1\nenvironment color 1 1 1\n", 2, 1, "(first on line 1)");
    expect_parse_error("environment color 1 1 1\nbackground 1 1 1\n", 2, 1, "one directive");
}

/* A Radiance HDR map (flat RGBE scanlines, 8 x 4 texels of 1.0 but one of 2.5 at column 3 of
 * row 1) reads as those values; one whose rows run up (+Y), which stb_image does not read, is
 * refused. */
static void test_radiance(void) {
    const char *path = tmp_path("map.hdr"), *cut = tmp_path("cut.hdr");
    FILE *fp = fopen(path, "wb"), *fq = fopen(cut, "wb");
    if (!fp || !fq) {
        CHECK(false, "writing %s", path);
        return;
    }
    const char *header = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 4 +X 8\n";
    fputs(header, fp), fputs("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 4 +X 8\n", fq);
    for (int k = 0; k < 32; k++) {
        /* 1.0 is mantissa 128 at exponent 129; 2.5 is 160 at 130 */
        unsigned char one[4] = {128, 128, 128, 129}, bright[4] = {160, 160, 160, 130};
        fwrite(k == 11 ? bright : one, 1, 4, fp);
        if (k < 5) fwrite(one, 1, 4, fq);
    }
    fclose(fp), fclose(fq);
    scene s;
    render_opts o;
    if (parse_format(&s, &o,
                     "camera position 0 0 0\nplane width 1 height 1 pixel 0.5\n"
                     "environment file %s\n",
                     path)) {
        CHECK(s.environment.width == 8 && s.environment.height == 4, "radiance map size");
        CHECK(s.environment.rgb[0] == 1.0f && s.environment.rgb[3 * 11 + 1] == 2.5f &&
                  s.environment.rgb[3 * 31 + 2] == 1.0f,
              "radiance map values %g %g", (double)s.environment.rgb[0],
              (double)s.environment.rgb[3 * 11 + 1]);
        scene_free(&s);
    } else {
        CHECK(false, "parsing a Radiance map");
    }
    char text[600];
    snprintf(text, sizeof text, "environment file %s\n", cut);
    expect_parse_error(text, 1, 18, "not a readable Radiance HDR image");
}

/* The shipped sky (scenes/maps/sky.exr) is what sky() makes. */
static void test_shipped_sky(void) {
    const char *made = tmp_path("sky.exr");
    CHECK(write_map(made, 128, 64, sky), "writing %s", made);
    size_t a = 0, b = 0;
    unsigned char *x = tmp_file_read(made, &a);
    unsigned char *y = tmp_file_read(TRAZADOR_SOURCE_DIR "/scenes/maps/sky.exr", &b);
    CHECK(x && y && a == b && !memcmp(x, y, a), "scenes/maps/sky.exr is not sky()'s");
    free(x);
    free(y);
}

int main(int argc, char **argv) {
    if (argc == 3 && !strcmp(argv[1], "--write-sky"))
        return write_map(argv[2], 128, 64, sky) ? 0 : 1;
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_environment: no Vulkan device, skipped\n");
        return 77;
    }
    if (!tmp_dir_make("test_environment")) return 1;
    if (!use_vulkan) {
        CHECK_CASE(test_sampling);
        CHECK_CASE(test_refusals);
        CHECK_CASE(test_shipped_sky);
        CHECK_CASE(test_radiance);
        CHECK_CASE(test_noise_ratio);
    }
    CHECK_CASE(test_furnace);
    CHECK_CASE(test_cap);
    return check_summary(use_vulkan ? "test_environment vulkan" : "test_environment");
}
