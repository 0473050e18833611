/* test_texture.c: textures (shaders/common/texture.h, src/render/texture_pack.c) on the back end
 * named by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 without a device): the sRGB table against
 * the formula for all 256 values, bilinear filtering at texel centres and corners, the wrap
 * modes, and rendered checkers: a quad of an 8 x 8 checker of 2 x 2-texel cells under a point
 * light in report mode, where every pixel whose four filtered texels lie in one cell must be that
 * cell's decoded colour times the irradiance computed here, with repeat, clamp and mirrored UVs;
 * and the same scene on both back ends, bit for bit. */
#include <math.h>
#include <png.h>
#include <string.h>

#include "check.h"
#include "render/cpu/scene_accessors.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"
#include "tmp_dir.h"
/* clang-format off: the shared text after the accessors it calls */
#include "common/texture.h"
/* clang-format on */

#define PI 3.14159265358979323846
#define SIDE 8 /* texels of the checker a side; cells of 2 x 2 texels */

static bool use_vulkan;
/* The two colours of the checker's cells, 8-bit sRGB. */
static const uint8_t cell_colour[2][3] = {{255, 128, 0}, {0, 64, 255}};

/* sRGB's decoding of 8-bit value k, in double. */
static double srgb(int k) {
    double c = k / 255.0;
    return c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
}

/* The checker's cell colour index at texel (x, y), rows from the top. */
static int cell_at(int x, int y) { return (x / 2 + y / 2) % 2; }

/* Writes the checker as an RGB PNG; texel (0, 0) of the test below gets a marker elsewhere. */
static void write_checker(const char *path) {
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!fp || !png || !info || setjmp(png_jmpbuf(png))) exit(1);
    png_init_io(png, fp);
    png_set_IHDR(png, info, SIDE, SIDE, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < SIDE; y++) {
        uint8_t row[SIDE * 3];
        for (int x = 0; x < SIDE; x++) memcpy(row + 3 * x, cell_colour[cell_at(x, y)], 3);
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

/* The scene text of a 40 x 40 view of the quad (-1..1)^2 at z = 0 lit from (0, 0, -3); the
 * quad's UVs run from lo to hi over it, read with wrap mode `wrap`. */
static void checker_scene(char *text, size_t size, double lo, double hi, const char *wrap) {
    snprintf(text, size,
             "camera position 0 0 -4\nplane width 2 height 2 pixel 0.05\n"
             "light position 0 0 -3 power 20\nrender indirect off samples 1\n"
             "quad lambertian v0 -1 -1 0 v1 1 -1 0 v2 1 1 0 v3 -1 1 0 color 1 1 1 "
             "uv0 %g %g uv1 %g %g uv2 %g %g uv3 %g %g color_map %s wrap %s\n",
             lo, lo, hi, lo, hi, hi, lo, hi, tmp_path("checker.png"), wrap);
}

/* Texel index k (any integer) of an axis of SIDE texels by wrap mode, as texture.h defines it. */
static int wrapped(long k, int mode) {
    if (mode == TZ_WRAP_CLAMP) return k < 0 ? 0 : k >= SIDE ? SIDE - 1 : (int)k;
    long period = mode == TZ_WRAP_MIRROR ? 2 * SIDE : SIDE;
    long m = ((k % period) + period) % period;
    return m < SIDE ? (int)m : (int)(period - 1 - m);
}

/* The cell whose colour bilinear filtering gives at texture coordinate t (in texels, before the
 * wrap) on one axis, or -1 where its two texels lie in different cells or t is within 1e-3 of a
 * boundary (where float rounding may pick either). */
static int axis_cell(double t, int mode) {
    if (mode == TZ_WRAP_CLAMP) t = t < 0 ? 0 : t > SIDE ? SIDE : t;
    double x = t - 0.5, f = x - floor(x);
    if (f < 1e-3 || f > 1 - 1e-3) return -1;
    int a = wrapped((long)floor(x), mode), b = wrapped((long)floor(x) + 1, mode);
    return a / 2 == b / 2 ? a / 2 : -1;
}

static float pixel(const film *f, int i, int j, int c) {
    const float *p = &f->accum[((size_t)j * f->width + i) * 4];
    return p[c] / p[3];
}

/* Renders the checker quad with UVs lo..hi and wrap mode; checks every pixel whose filtered
 * texels lie in one cell against that cell's colour times kd / pi times the irradiance. */
static void check_checker(double lo, double hi, const char *wrap, int mode) {
    char text[1024];
    checker_scene(text, sizeof text, lo, hi, wrap);
    scene s;
    render_opts o;
    film f = {0};
    CHECK(parse_scene_text(text, &s, &o), "%s: parse", wrap);
    o.no_jitter = true;
    CHECK(render_on(use_vulkan, &s, &o, &f), "%s: render", wrap);
    scene_free(&s);
    if (!f.accum) return;
    int checked = 0;
    for (int j = 0; j < 40; j++) {
        for (int i = 0; i < 40; i++) {
            double x = -1 + (i + 0.5) * 0.05, y = 1 - (j + 0.5) * 0.05;
            double u = lo + (hi - lo) * (x + 1) / 2, v = lo + (hi - lo) * (y + 1) / 2;
            int cx = axis_cell(u * SIDE, mode), cy = axis_cell((1 - v) * SIDE, mode);
            if (cx < 0 || cy < 0) continue;
            double d2 = x * x + y * y + 9, irradiance = 20 * (3 / sqrt(d2)) / d2;
            const uint8_t *c = cell_colour[(cx + cy) % 2];
            for (int k = 0; k < 3; k++) {
                double want = srgb(c[k]) / PI * irradiance;
                CHECK(fabs(pixel(&f, i, j, k) - want) <= 2e-4 * want + 1e-7,
                      "%s: pixel (%d, %d) channel %d = %.7g, want %.7g", wrap, i, j, k,
                      pixel(&f, i, j, k), want);
            }
            checked++;
        }
    }
    CHECK(checked > 100, "%s: only %d pixels checked", wrap, checked);
    film_free(&f);
}

static void test_rendered_checkers(void) {
    check_checker(0, 1, "repeat", TZ_WRAP_REPEAT);
    check_checker(-1, 2, "repeat", TZ_WRAP_REPEAT);
    check_checker(-1, 2, "clamp", TZ_WRAP_CLAMP);
    check_checker(-1, 2, "mirror", TZ_WRAP_MIRROR);
}

/* The packed checker scene (repeat), for the shared text's functions called directly. */
static bool pack_checker(const char *wrap, scene *s, packed_scene *p) {
    char text[1024];
    render_opts o;
    checker_scene(text, sizeof text, 0, 1, wrap);
    return parse_scene_text(text, s, &o) && scene_pack(s, &o, p);
}

/* The sRGB table is the formula rounded once, for all 256 values; the linear one k / 255. */
static void test_decode_tables(void) {
    scene s;
    packed_scene p;
    if (!pack_checker("repeat", &s, &p)) return;
    for (int k = 0; k < 256; k++) {
        float got = float_from_bits(p.texture_words[TZ_TEXTURE_SRGB + k]);
        CHECK(got == (float)srgb(k), "sRGB %d = %.9g, want %.9g", k, got, srgb(k));
        CHECK(fabs((double)got - srgb(k)) <= 0.5 * ldexp(1, ilogb(srgb(k) ? srgb(k) : 1) - 23),
              "sRGB %d not the nearest float", k);
        got = float_from_bits(p.texture_words[TZ_TEXTURE_LINEAR + k]);
        CHECK(got == (float)(k / 255.0), "linear %d", k);
    }
    scene_pack_free(&p);
    scene_free(&s);
}

/* Bilinear filtering: a texel's centre is its colour; the corner of four texels their mean. */
static void test_bilinear(void) {
    scene s;
    packed_scene p;
    if (!pack_checker("repeat", &s, &p)) return;
    const packed_scene *scene = &p;
    for (int y = 0; y < SIDE; y++) {
        for (int x = 0; x < SIDE; x++) {
            tex_uv centre = tex_uv_of((x + 0.5f) / SIDE, 1.0f - (y + 0.5f) / SIDE);
            texel t = texture_sample(scene, 0, centre);
            const uint8_t *c = cell_colour[cell_at(x, y)];
            CHECK(t.rgb.x == (float)srgb(c[0]) && t.rgb.y == (float)srgb(c[1]) &&
                      t.rgb.z == (float)srgb(c[2]) && t.a == 1.0f,
                  "texel (%d, %d) at its centre", x, y);
        }
    }
    /* The corner of texels (1..2, 1..2): cells 0 and 1, two texels of each, weights 1/4. */
    texel t = texture_sample(scene, 0, tex_uv_of(2.0f / SIDE, 1.0f - 2.0f / SIDE));
    for (int k = 0; k < 3; k++) {
        float a = (float)srgb(cell_colour[0][k]), b = (float)srgb(cell_colour[1][k]);
        float got = k == 0 ? t.rgb.x : k == 1 ? t.rgb.y : t.rgb.z;
        CHECK(fabsf(got - (a + b) / 2) <= 1e-7f, "corner channel %d = %g, want %g", k, got,
              (a + b) / 2);
    }
    /* Repeat: texel (0, 0)'s centre one period away reads the same bits. */
    texel here = texture_sample(scene, 0, tex_uv_of(0.5f / SIDE, 1.0f - 0.5f / SIDE));
    texel there = texture_sample(scene, 0, tex_uv_of(1.0f + 0.5f / SIDE, 2.0f - 0.5f / SIDE));
    EXPECT(!memcmp(&here, &there, sizeof here));
    /* NaN and huge coordinates read texel 0's neighbourhood, never out of the image. */
    texel nan_uv = texture_sample(scene, 0, tex_uv_of(NAN, 1e30f));
    EXPECT(isfinite(nan_uv.rgb.x) && isfinite(nan_uv.a));
    scene_pack_free(&p);
    scene_free(&s);
}

/* The same textured scene (spheres, faces with UVs, every wrap mode) on both back ends in both
 * modes, bit for bit. */
static void test_back_ends_agree(void) {
    if (!use_vulkan) return;
    char text[2048];
    snprintf(text, sizeof text,
             "camera position 0 0 -4\nplane width 2 height 2 pixel 0.04\n"
             "light position 0 0 -3 power 20\nrender samples 4\n"
             "quad lambertian v0 -1 -1 0 v1 1 -1 0 v2 1 1 0 v3 -1 1 0 color_map %s\n"
             "sphere phong center 0.5 0.5 -1 radius 0.3 color 0.5 0.5 0.5 ks 0.3 color_map %s "
             "wrap mirror\n"
             "triangle lambertian v0 -1 -1 -0.5 v1 -0.2 -1 -0.5 v2 -1 -0.2 -0.5 uv0 0 0 uv1 2 0 "
             "uv2 0 2 color_map %s wrap clamp\n",
             tmp_path("checker.png"), tmp_path("checker.png"), tmp_path("checker.png"));
    expect_back_ends_agree(text);
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_texture: no Vulkan device, skipped\n");
        return 77;
    }
    if (!tmp_dir_make("test_texture")) return 1;
    write_checker(tmp_path("checker.png"));
    CHECK_CASE(test_decode_tables);
    CHECK_CASE(test_bilinear);
    CHECK_CASE(test_rendered_checkers);
    CHECK_CASE(test_back_ends_agree);
    return check_summary(use_vulkan ? "test_texture vulkan" : "test_texture");
}
