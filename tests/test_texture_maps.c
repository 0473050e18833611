/* test_texture_maps.c: the maps a material reads besides its colour (shaders/common/texture.h)
 * on the back end named by argv[1] ("cpu" or "vulkan"; Vulkan exits 77 without a device): a
 * constant normal map bends a lit quad's shading as the closed form of its decoded normal says,
 * on a face and on a sphere; a metallic-roughness map scales pbr's factors as the same material
 * with the products as constants renders; and a scene of every map on both
 * back ends in both modes, bit for bit. */
#include <math.h>
#include <png.h>
#include <string.h>

#include "check.h"
#include "render/vk/vk_context.h"
#include "test_scenes.h"
#include "tmp_dir.h"

#define PI 3.14159265358979323846

static bool use_vulkan;

/* Writes a side x side RGB PNG of one colour. */
static void write_flat(const char *path, int side, const uint8_t rgb[3]) {
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!fp || !png || !info || setjmp(png_jmpbuf(png))) exit(1);
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)side, (png_uint_32)side, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    uint8_t row[3 * 64];
    for (int x = 0; x < side; x++) memcpy(row + 3 * x, rgb, 3);
    for (int y = 0; y < side; y++) png_write_row(png, row);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

static float pixel(const film *f, int i, int j, int c) {
    const float *p = &f->accum[((size_t)j * f->width + i) * 4];
    return p[c] / p[3];
}

/* Renders scene text on the back end under test into f (report mode as the text says, no
 * jitter); false when it does not parse or render. */
static bool render_text(const char *text, film *f) {
    scene s;
    render_opts o;
    if (!parse_scene_text(text, &s, &o)) return false;
    o.no_jitter = true;
    bool ok = render_on(use_vulkan, &s, &o, f);
    scene_free(&s);
    return ok;
}

/* The tangent-space normal of 8-bit texel rgb (2 c / 255 - 1 a channel), normalized. */
static void decoded_normal(const uint8_t rgb[3], double n[3]) {
    double len = 0;
    for (int k = 0; k < 3; k++) {
        n[k] = 2.0 * rgb[k] / 255.0 - 1.0;
        len += n[k] * n[k];
    }
    for (int k = 0; k < 3; k++) n[k] /= sqrt(len);
}

/* A quad (-1..1)^2 at z = 0 facing (its corners' order) the camera at z = -4 and the light at
 * (0, 0, -3), its UVs u along +x and v along +y, with a constant normal map: every pixel is kd /
 * pi times the light's power times the cosine between the bent normal (tangent +x, bitangent +y,
 * normal -z) and the light, over the squared distance. Seen from its back, glTF's rule for
 * two-sided faces turns the bent normal whole. */
static void test_normal_map_face(void) {
    static const uint8_t tilt[3] = {190, 96, 230};
    write_flat(tmp_path("normal.png"), 4, tilt);
    char text[1024];
    snprintf(text, sizeof text,
             "camera position 0 0 -4\nplane width 2 height 2 pixel 0.1\n"
             "light position 0 0 -3 power 20\nrender indirect off samples 1\n"
             "quad lambertian v0 -1 -1 0 v1 -1 1 0 v2 1 1 0 v3 1 -1 0 color 1 1 1 "
             "uv0 0 0 uv1 0 1 uv2 1 1 uv3 1 0 normal_map %s\n",
             tmp_path("normal.png"));
    film f = {0};
    CHECK(render_text(text, &f), "normal-mapped quad: render");
    if (!f.accum) return;
    double n[3];
    decoded_normal(tilt, n);
    double bent[3] = {n[0], n[1], -n[2]};
    int worst_i = -1, worst_j = -1;
    double worst = 0;
    for (int j = 0; j < 20; j++) {
        for (int i = 0; i < 20; i++) {
            double x = -1 + (i + 0.5) * 0.1, y = 1 - (j + 0.5) * 0.1;
            double to[3] = {-x, -y, -3}, d2 = x * x + y * y + 9;
            double cosine = (bent[0] * to[0] + bent[1] * to[1] + bent[2] * to[2]) / sqrt(d2);
            double want = cosine > 0 ? 20 * cosine / d2 / PI : 0;
            double off = fabs(pixel(&f, i, j, 0) - want) / (want + 1e-6);
            if (off > worst) worst = off, worst_i = i, worst_j = j;
        }
    }
    CHECK(worst < 3e-4, "normal-mapped quad: pixel (%d, %d) off by %.2g of the closed form",
          worst_i, worst_j, worst);
    film_free(&f);
}

/* A normal map of the flat normal (128, 128, 255 decodes within 0.4% of +z) leaves a sphere's
 * shading within that of the unmapped sphere's; a tilted one changes it. */
static void test_normal_map_sphere(void) {
    static const uint8_t flat[3] = {128, 128, 255}, tilt[3] = {230, 128, 170};
    write_flat(tmp_path("flat.png"), 4, flat);
    write_flat(tmp_path("tilt.png"), 4, tilt);
    const char *maps[] = {"", tmp_path("flat.png"), tmp_path("tilt.png")};
    film f[3] = {{0}};
    for (int k = 0; k < 3; k++) {
        char text[1024];
        snprintf(text, sizeof text,
                 "camera position 0 0 -4\nplane width 2 height 2 pixel 0.1\n"
                 "light position -2 2 -3 power 30\nrender indirect off samples 1\n"
                 "sphere lambertian center 0 0 0 radius 0.9 color 1 1 1%s%s\n",
                 k ? " normal_map " : "", maps[k]);
        CHECK(render_text(text, &f[k]), "sphere %d: render", k);
    }
    if (!f[0].accum || !f[1].accum || !f[2].accum) return;
    double flat_off = 0, tilt_off = 0;
    for (int j = 0; j < 20; j++) {
        for (int i = 0; i < 20; i++) {
            double a = pixel(&f[0], i, j, 0);
            flat_off = fmax(flat_off, fabs(pixel(&f[1], i, j, 0) - a));
            tilt_off = fmax(tilt_off, fabs(pixel(&f[2], i, j, 0) - a));
        }
    }
    CHECK(flat_off < 0.01 && tilt_off > 0.05,
          "sphere: a flat map moved a pixel by %.3g, a tilted one by %.3g", flat_off, tilt_off);
    for (int k = 0; k < 3; k++) film_free(&f[k]);
}

/* A pbr triangle pair with the map `map_key` of one colour against the same with the factors the
 * map's channels give written as constants: the same image within float rounding of the
 * products. */
static void check_factor_map(const char *map_key, const uint8_t rgb[3], const char *factors,
                             const char *constants) {
    write_flat(tmp_path("factor.png"), 2, rgb);
    const char *base =
        "camera position 0 0 -4\nplane width 2 height 2 pixel 0.1\n"
        "light position -1 1 -3 power 20\nrender indirect off samples 1\n"
        "quad pbr v0 -1 -1 0 v1 1 -1 0 v2 1 1 0 v3 -1 1 0 color 0.9 0.6 0.3 ";
    char mapped[1024], constant[1024];
    snprintf(mapped, sizeof mapped, "%s%s %s %s\n", base, factors, map_key, tmp_path("factor.png"));
    snprintf(constant, sizeof constant, "%s%s\n", base, constants);
    film a = {0}, b = {0};
    CHECK(render_text(mapped, &a) && render_text(constant, &b), "%s: render", map_key);
    if (!a.accum || !b.accum) return;
    double worst = 0, total = 0;
    for (int j = 0; j < 20; j++) {
        for (int i = 0; i < 20; i++) {
            for (int c = 0; c < 3; c++) {
                double x = pixel(&a, i, j, c), y = pixel(&b, i, j, c);
                worst = fmax(worst, fabs(x - y) / (fabs(y) + 1e-4));
                total += y;
            }
        }
    }
    CHECK(total > 1 && worst < 1e-3, "%s: off by %.3g of the constants' image (sum %g)", map_key,
          worst, total);
    film_free(&a);
    film_free(&b);
}

/* glTF's metallic-roughness map (blue metallic, green roughness) times the factors. */
static void test_factor_maps(void) {
    static const uint8_t mr[3] = {0, 102, 153}; /* 102 / 255 = 0.4, 153 / 255 = 0.6 */
    check_factor_map("metallic_roughness_map", mr, "metallic 1 roughness 1",
                     "metallic 0.6 roughness 0.4");
    check_factor_map("metallic_roughness_map", mr, "metallic 0.5 roughness 0.5",
                     "metallic 0.3 roughness 0.2");
    check_factor_map("metallic_roughness_map", mr, "metallic 0 roughness 1",
                     "metallic 0 roughness 0.4");
}

/* A scene of every map the shading reads (colour, normal, metallic-roughness) on faces and
 * spheres, on both back ends in both modes, bit for bit. */
static void test_back_ends_agree(void) {
    if (!use_vulkan) return;
    static const uint8_t mr[3] = {0, 90, 200};
    write_flat(tmp_path("mr.png"), 2, mr);
    char text[2048];
    snprintf(text, sizeof text,
             "camera position 0 0 -4\nplane width 2 height 2 pixel 0.04\n"
             "light position 0 1 -3 power 20\nrender samples 4\n"
             "quad lambertian v0 -1 -1 0 v1 1 -1 0 v2 1 1 0 v3 -1 1 0 uv1 3 0 uv2 3 3 uv3 0 3 "
             "normal_map %s\n"
             "sphere pbr center 0.5 0.5 -1 radius 0.3 color 0.8 0.7 0.5 metallic_roughness_map "
             "%s normal_map %s\n"
             "triangle pbr v0 -1 -1 -0.5 v1 -0.2 -1 -0.5 v2 -1 -0.2 -0.5 uv0 0 0 uv1 2 0 "
             "uv2 0 2 metallic_roughness_map %s normal_map %s\n",
             tmp_path("tilt.png"), tmp_path("mr.png"), tmp_path("tilt.png"), tmp_path("mr.png"),
             tmp_path("normal.png"));
    expect_back_ends_agree(text);
}

int main(int argc, char **argv) {
    use_vulkan = argc > 1 && !strcmp(argv[1], "vulkan");
    if (use_vulkan && vk_context_device_count() == 0) {
        printf("test_texture_maps: no Vulkan device, skipped\n");
        return 77;
    }
    if (!tmp_dir_make("test_texture_maps")) return 1;
    CHECK_CASE(test_normal_map_face);
    CHECK_CASE(test_normal_map_sphere);
    CHECK_CASE(test_factor_maps);
    CHECK_CASE(test_back_ends_agree);
    return check_summary(use_vulkan ? "test_texture_maps vulkan" : "test_texture_maps");
}
