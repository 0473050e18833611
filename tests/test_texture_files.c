/* test_texture_files.c: the texture decoders (src/scene/texture.h) on images this test writes
 * with libpng, libjpeg-turbo and trazador's EXR writer: every PNG colour type at 8 and 16 bits
 * (grey, grey and alpha, palette with tRNS, RGB, RGBA) to the exact texel words, JPEG grey and
 * colour within the codec's error, EXR half and float and grey (Y) exactly; and the refusals:
 * not an image, truncated PNG and JPEG, corrupt bytes, an EXR without colour channels, a side
 * over the limit, a budget exceeded, a missing file. */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* clang-format off: jpeglib.h needs FILE and size_t declared before it */
#include <jpeglib.h>
/* clang-format on */

#include "check.h"
#include "image/exr.h"
#include "scene/texture.h"
#include "shared_layout.h"
#include "tmp_dir.h"

#define W 3
#define H 2

/* Writes a W x H PNG of colour type and depth from samples (channels per pixel, big-endian
 * 16-bit when depth 16); a palette and tRNS where given. */
static void write_png(const char *path, int color_type, int depth, const uint8_t *samples,
                      int channels, const png_color *palette, int colors, const uint8_t *trns,
                      int trns_count) {
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!fp || !png || !info || setjmp(png_jmpbuf(png))) {
        printf("cannot write %s\n", path);
        exit(1);
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, W, H, depth, color_type, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    if (palette) png_set_PLTE(png, info, palette, colors);
    if (trns) png_set_tRNS(png, info, trns, trns_count, NULL);
    png_write_info(png, info);
    size_t row = (size_t)W * channels * (depth / 8);
    for (int y = 0; y < H; y++) png_write_row(png, (png_bytep)(samples + y * row));
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

static uint32_t rgba(unsigned r, unsigned g, unsigned b, unsigned a) {
    return r | g << 8 | b << 16 | a << 24;
}

static bool load(const char *path, texture_image *t, char *why) {
    return texture_load_file(path, TEXTURE_MAX_SCENE_BYTES, t, why, 320);
}

/* 8-bit PNGs of every colour type to the words the texel table holds. */
static void test_png_8bit(void) {
    char why[320];
    texture_image t;
    const uint8_t grey[W * H] = {0, 1, 127, 128, 254, 255};
    write_png(tmp_path("grey.png"), PNG_COLOR_TYPE_GRAY, 8, grey, 1, NULL, 0, NULL, 0);
    EXPECT(load(tmp_path("grey.png"), &t, why) && t.format == TZ_TEXEL_RGBA8 && t.width == W &&
           t.height == H);
    for (int k = 0; t.words && k < W * H; k++)
        CHECK(t.words[k] == rgba(grey[k], grey[k], grey[k], 255), "grey texel %d", k);
    texture_image_free(&t);
    const uint8_t grey_alpha[W * H * 2] = {0, 10, 50, 60, 100, 110, 150, 160, 200, 210, 250, 255};
    write_png(tmp_path("ga.png"), PNG_COLOR_TYPE_GRAY_ALPHA, 8, grey_alpha, 2, NULL, 0, NULL, 0);
    EXPECT(load(tmp_path("ga.png"), &t, why));
    for (int k = 0; t.words && k < W * H; k++) {
        unsigned g = grey_alpha[2 * k], a = grey_alpha[2 * k + 1];
        CHECK(t.words[k] == rgba(g, g, g, a), "grey-alpha texel %d", k);
    }
    texture_image_free(&t);
    const png_color palette[3] = {{255, 0, 0}, {0, 255, 0}, {10, 20, 30}};
    const uint8_t trns[2] = {0, 128};
    const uint8_t indices[W * H] = {0, 1, 2, 2, 1, 0};
    write_png(tmp_path("pal.png"), PNG_COLOR_TYPE_PALETTE, 8, indices, 1, palette, 3, trns, 2);
    EXPECT(load(tmp_path("pal.png"), &t, why));
    for (int k = 0; t.words && k < W * H; k++) {
        png_color c = palette[indices[k]];
        unsigned a = indices[k] < 2 ? trns[indices[k]] : 255;
        CHECK(t.words[k] == rgba(c.red, c.green, c.blue, a), "palette texel %d", k);
    }
    texture_image_free(&t);
    uint8_t rgb[W * H * 3], rgba8[W * H * 4];
    for (int k = 0; k < W * H * 3; k++) rgb[k] = (uint8_t)(k * 13);
    for (int k = 0; k < W * H * 4; k++) rgba8[k] = (uint8_t)(k * 11 + 3);
    write_png(tmp_path("rgb.png"), PNG_COLOR_TYPE_RGB, 8, rgb, 3, NULL, 0, NULL, 0);
    EXPECT(load(tmp_path("rgb.png"), &t, why));
    for (int k = 0; t.words && k < W * H; k++)
        CHECK(t.words[k] == rgba(rgb[3 * k], rgb[3 * k + 1], rgb[3 * k + 2], 255), "rgb %d", k);
    texture_image_free(&t);
    write_png(tmp_path("rgba.png"), PNG_COLOR_TYPE_RGBA, 8, rgba8, 4, NULL, 0, NULL, 0);
    EXPECT(load(tmp_path("rgba.png"), &t, why));
    for (int k = 0; t.words && k < W * H; k++)
        CHECK(
            t.words[k] == rgba(rgba8[4 * k], rgba8[4 * k + 1], rgba8[4 * k + 2], rgba8[4 * k + 3]),
            "rgba %d", k);
    texture_image_free(&t);
}

/* 16-bit PNGs: four floats a texel, v / 65535. */
static void test_png_16bit(void) {
    char why[320];
    texture_image t;
    uint8_t grey[W * H * 2], rgba16[W * H * 8];
    for (int k = 0; k < W * H; k++) grey[2 * k] = (uint8_t)(k * 40), grey[2 * k + 1] = (uint8_t)k;
    for (int k = 0; k < W * H * 4; k++)
        rgba16[2 * k] = (uint8_t)(k * 9), rgba16[2 * k + 1] = (uint8_t)(255 - k);
    write_png(tmp_path("grey16.png"), PNG_COLOR_TYPE_GRAY, 16, grey, 1, NULL, 0, NULL, 0);
    EXPECT(load(tmp_path("grey16.png"), &t, why) && t.format == TZ_TEXEL_RGBA32F &&
           t.word_count == 4u * W * H);
    for (int k = 0; t.words && k < W * H; k++) {
        float f[4], want = (float)((grey[2 * k] << 8 | grey[2 * k + 1]) / 65535.0);
        memcpy(f, t.words + 4 * k, sizeof f);
        CHECK(f[0] == want && f[1] == want && f[2] == want && f[3] == 1.0f, "grey16 texel %d", k);
    }
    texture_image_free(&t);
    write_png(tmp_path("rgba16.png"), PNG_COLOR_TYPE_RGBA, 16, rgba16, 4, NULL, 0, NULL, 0);
    EXPECT(load(tmp_path("rgba16.png"), &t, why));
    for (int k = 0; t.words && k < W * H * 4; k++) {
        float f, want = (float)((rgba16[2 * k] << 8 | rgba16[2 * k + 1]) / 65535.0);
        memcpy(&f, t.words + k, sizeof f);
        CHECK(f == want, "rgba16 sample %d", k);
    }
    texture_image_free(&t);
}

/* A JPEG of `components` (1 grey, 3 RGB) of one colour; quality 100 keeps it within 2. */
static void write_jpeg(const char *path, int components, const uint8_t colour[3]) {
    struct jpeg_compress_struct c;
    struct jpeg_error_mgr err;
    c.err = jpeg_std_error(&err);
    jpeg_create_compress(&c);
    FILE *fp = fopen(path, "wb");
    jpeg_stdio_dest(&c, fp);
    c.image_width = 16, c.image_height = 8, c.input_components = components;
    c.in_color_space = components == 1 ? JCS_GRAYSCALE : JCS_RGB;
    jpeg_set_defaults(&c);
    jpeg_set_quality(&c, 100, TRUE);
    jpeg_start_compress(&c, TRUE);
    uint8_t row[16 * 3];
    for (int x = 0; x < 16; x++)
        for (int k = 0; k < components; k++) row[x * components + k] = colour[k];
    while (c.next_scanline < c.image_height) {
        JSAMPROW r = row;
        jpeg_write_scanlines(&c, &r, 1);
    }
    jpeg_finish_compress(&c);
    jpeg_destroy_compress(&c);
    fclose(fp);
}

static bool within(unsigned a, unsigned b, unsigned d) { return a > b ? a - b <= d : b - a <= d; }

static void test_jpeg(void) {
    char why[320];
    texture_image t;
    const uint8_t colour[3] = {200, 100, 30};
    write_jpeg(tmp_path("rgb.jpg"), 3, colour);
    EXPECT(load(tmp_path("rgb.jpg"), &t, why) && t.width == 16 && t.height == 8 &&
           t.format == TZ_TEXEL_RGBA8);
    for (size_t k = 0; t.words && k < t.word_count; k++) {
        uint32_t w = t.words[k];
        CHECK(within(w & 255, 200, 2) && within(w >> 8 & 255, 100, 2) &&
                  within(w >> 16 & 255, 30, 2) && w >> 24 == 255,
              "jpeg texel %zu = %08x", k, w);
    }
    texture_image_free(&t);
    write_jpeg(tmp_path("grey.jpg"), 1, colour);
    EXPECT(load(tmp_path("grey.jpg"), &t, why));
    for (size_t k = 0; t.words && k < t.word_count; k++) {
        uint32_t w = t.words[k];
        CHECK(within(w & 255, 200, 1) && (w & 255) == (w >> 8 & 255) &&
                  (w & 255) == (w >> 16 & 255) && w >> 24 == 255,
              "grey jpeg texel %zu = %08x", k, w);
    }
    texture_image_free(&t);
}

/* EXR half RGBA and float Y through trazador's writer, read back exactly. */
static void test_exr(void) {
    char why[320];
    texture_image t;
    uint16_t half[4][W * H];
    float y[W * H];
    for (int k = 0; k < W * H; k++) {
        for (int c = 0; c < 4; c++) half[c][k] = exr_half_from_float(0.25f * (float)(k + c));
        y[k] = 1.5f * (float)k;
    }
    exr_channel rgba_ch[4] = {{.name = "A", .type = EXR_SAMPLE_HALF, .data = half[3]},
                              {.name = "B", .type = EXR_SAMPLE_HALF, .data = half[2]},
                              {.name = "G", .type = EXR_SAMPLE_HALF, .data = half[1]},
                              {.name = "R", .type = EXR_SAMPLE_HALF, .data = half[0]}};
    exr_file f = {.display_width = W,
                  .display_height = H,
                  .width = W,
                  .height = H,
                  .channels = rgba_ch,
                  .channel_count = 4};
    EXPECT(exr_file_write(tmp_path("rgba.exr"), &f));
    EXPECT(load(tmp_path("rgba.exr"), &t, why) && t.format == TZ_TEXEL_RGBA32F);
    for (int k = 0; t.words && k < W * H; k++) {
        float v[4];
        memcpy(v, t.words + 4 * k, sizeof v);
        for (int c = 0; c < 4; c++)
            CHECK(v[c] == 0.25f * (float)(k + c), "exr texel %d channel %d = %g", k, c, v[c]);
    }
    texture_image_free(&t);
    exr_channel grey_ch[1] = {{.name = "Y", .type = EXR_SAMPLE_FLOAT, .data = y}};
    f.channels = grey_ch, f.channel_count = 1;
    EXPECT(exr_file_write(tmp_path("y.exr"), &f));
    EXPECT(load(tmp_path("y.exr"), &t, why));
    for (int k = 0; t.words && k < W * H; k++) {
        float v[4];
        memcpy(v, t.words + 4 * k, sizeof v);
        CHECK(v[0] == y[k] && v[1] == y[k] && v[2] == y[k] && v[3] == 1.0f, "exr Y texel %d", k);
    }
    texture_image_free(&t);
    exr_channel depth_ch[1] = {{.name = "Z", .type = EXR_SAMPLE_FLOAT, .data = y}};
    f.channels = depth_ch;
    EXPECT(exr_file_write(tmp_path("z.exr"), &f));
    CHECK(!load(tmp_path("z.exr"), &t, why) && strstr(why, "without colour channels"),
          "EXR without colour: %s", why);
}

/* Refusals: each says why, never a crash. */
static void test_refusals(void) {
    char why[320];
    texture_image t;
    tmp_file_write(tmp_path("text.png"), "hello", 5);
    CHECK(!load(tmp_path("text.png"), &t, why) && strstr(why, "not a PNG, JPEG or OpenEXR"),
          "text: %s", why);
    CHECK(!load(tmp_path("missing.png"), &t, why) && strstr(why, "No such file"), "missing: %s",
          why);
    const char *whole[] = {"rgba.png", "rgb.jpg", "rgba.exr"};
    for (int k = 0; k < 3; k++) {
        size_t size;
        unsigned char *bytes = tmp_file_read(tmp_path(whole[k]), &size);
        EXPECT(bytes != NULL);
        if (!bytes) continue;
        CHECK(!texture_decode(bytes, size * 2 / 3, TEXTURE_MAX_SCENE_BYTES, &t, why, sizeof why),
              "%s truncated to 2/3 decoded", whole[k]);
        CHECK(
            !texture_decode(bytes, size, 8, &t, why, sizeof why) && strstr(why, "bytes of texels"),
            "%s over a budget of 8 bytes: %s", whole[k], why);
        free(bytes);
    }
    /* A PNG header claiming 20000 x 1 pixels: refused before any pixel is decoded. */
    static const uint8_t wide[8] = {0, 0, 0x4e, 0x20, 0, 0, 0, 1};
    size_t size;
    unsigned char *bytes = tmp_file_read(tmp_path("grey.png"), &size);
    if (bytes) {
        memcpy(bytes + 16, wide, sizeof wide); /* IHDR's width and height (its CRC now wrong) */
        CHECK(!texture_decode(bytes, size, TEXTURE_MAX_SCENE_BYTES, &t, why, sizeof why),
              "a 20000-pixel-wide PNG decoded");
        free(bytes);
    }
}

int main(void) {
    if (!tmp_dir_make("test_texture_files")) return 1;
    CHECK_CASE(test_png_8bit);
    CHECK_CASE(test_png_16bit);
    CHECK_CASE(test_jpeg);
    CHECK_CASE(test_exr);
    CHECK_CASE(test_refusals);
    return check_summary("test_texture_files");
}
