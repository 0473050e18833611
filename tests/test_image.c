/* test_image.c: tonemapping (and its table), film resolve, PPM/PNG/PFM round trips and their
   bytes for src/image/image.c and image_png.c; writing, malformed inputs and PNGs of other kinds:
   test_image_files.c. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "image_check.h"
#include "tmp_dir.h"
#include "util/log.h"

static void test_tonemap_known(void) {
    EXPECT(tonemap_channel(0.0f, TONEMAP_SRGB) == 0);
    EXPECT(tonemap_channel(1.0f, TONEMAP_SRGB) == 255);
    EXPECT(tonemap_channel(0.5f, TONEMAP_SRGB) == 188);
    EXPECT(tonemap_channel(0.5f, TONEMAP_LINEAR) == 128);
    EXPECT(tonemap_channel(0.2f, TONEMAP_LINEAR) == 51);
    EXPECT(tonemap_channel(0.0031308f, TONEMAP_SRGB) == 10); /* 12.92 * 0.0031308 * 255 = 10.3 */
    EXPECT(tonemap_channel(0.0031307f, TONEMAP_SRGB) == 10);
    EXPECT(tonemap_channel(0.0031309f, TONEMAP_SRGB) == 10);
    EXPECT(tonemap_channel(0.001f, TONEMAP_SRGB) == 3);   /* 12.92 * 0.001 * 255 = 3.29 */
    EXPECT(tonemap_channel(0.0035f, TONEMAP_SRGB) == 11); /* power curve 11.48; the line: 11.53 */
    EXPECT(fabs(tonemap_encode(0.003f, TONEMAP_SRGB) - 12.92 * (double)0.003f) < 1e-9);
    EXPECT(fabs(tonemap_encode(0.0035f, TONEMAP_SRGB) - (1.055 * pow(0.0035f, 1 / 2.4) - 0.055)) <
           1e-9);
    EXPECT(tonemap_channel(0.18f, TONEMAP_SRGB) == 118);
    EXPECT(tonemap_channel(-0.5f, TONEMAP_SRGB) == 0);
    EXPECT(tonemap_channel(-0.5f, TONEMAP_LINEAR) == 0);
    EXPECT(tonemap_channel(7.0f, TONEMAP_SRGB) == 255);
    EXPECT(tonemap_channel(7.0f, TONEMAP_LINEAR) == 255);
    EXPECT(tonemap_channel(NAN, TONEMAP_SRGB) == 0);
    EXPECT(tonemap_channel(NAN, TONEMAP_LINEAR) == 0);
    EXPECT(tonemap_channel(INFINITY, TONEMAP_SRGB) == 255);
    EXPECT(tonemap_channel(-INFINITY, TONEMAP_SRGB) == 0);
    EXPECT(fabs(tonemap_encode(0.5f, TONEMAP_SRGB) - 0.735356983) < 1e-6);
    EXPECT(tonemap_encode(0.25f, TONEMAP_LINEAR) == 0.25);
    EXPECT(tonemap_encode(2.0f, TONEMAP_SRGB) <= 1.0);
    /* the inverse: linear segment up to byte 10, the power curve from 11 */
    EXPECT(tonemap_decode(10, TONEMAP_SRGB) == (float)(10.0 / 255.0 / 12.92));
    EXPECT(fabs(tonemap_decode(11, TONEMAP_SRGB) - pow((11.0 / 255.0 + 0.055) / 1.055, 2.4)) <
           1e-9);
    EXPECT(fabs(tonemap_decode(188, TONEMAP_SRGB) - 0.502886) < 1e-6);
    EXPECT(tonemap_decode(51, TONEMAP_LINEAR) == 0.2f);
}

static void test_tonemap_decode_all_bytes(void) {
    for (int tm = TONEMAP_SRGB; tm <= TONEMAP_LINEAR; tm++) {
        float prev = -1.0f;
        for (int b = 0; b < 256; b++) {
            float v = tonemap_decode((uint8_t)b, (tonemap)tm);
            if (tonemap_channel(v, (tonemap)tm) != b || !(v > prev)) {
                printf("  %s: tonemap %d byte %d decodes to %.9g, re-encodes to %d\n",
                       check_case_name, tm, b, v, tonemap_channel(v, (tonemap)tm));
                EXPECT(!"decode then encode gives back every byte, increasing");
                break;
            }
            prev = v;
        }
        EXPECT(tonemap_decode(0, (tonemap)tm) == 0.0f);
        EXPECT(tonemap_decode(255, (tonemap)tm) == 1.0f);
    }
}

static void test_film_average(void) {
    /* 3x2: plain sample, four samples, no samples, one channel at zero, and so on */
    float accum[] = {0.5f, 1.0f, 1.5f, 1.0f, 4.0f, 2.0f, 1.0f, 4.0f, 9.0f, 9.0f, 9.0f, 0.0f,
                     0.0f, 3.0f, 0.0f, 3.0f, 0.0f, 0.0f, 0.0f, 0.0f, -1.f, 2.0f, 8.0f, 2.0f};
    film f = {.width = 3, .height = 2, .accum = accum};
    image img;
    EXPECT(image_from_film(&f, &img));
    float want[] = {0.5f, 1.0f, 1.5f, 1.0f, 0.5f, 0.25f, 0.0f,  0.0f, 0.0f,
                    0.0f, 1.0f, 0.0f, 0.0f, 0.0f, 0.0f,  -0.5f, 1.0f, 4.0f};
    image ref = {3, 2, want};
    EXPECT(same_image(&img, &ref));
    image_free(&img);
    EXPECT(img.rgb == NULL && img.width == 0);
    image_free(&img); /* safe twice */
}

static void test_init_limits(void) {
    image img;
    EXPECT(!image_init(&img, 0, 5) && img.rgb == NULL);
    EXPECT(!image_init(&img, 5, -1) && img.rgb == NULL);
    EXPECT(!image_init(&img, IMAGE_MAX_DIM + 1, 1) && img.rgb == NULL);
    EXPECT(image_init(&img, 2, 3) && img.rgb && img.rgb[17] == 0.0f);
    image_free(&img);
}

static void roundtrip_8bit(const char *name, tonemap tm) {
    image src, back;
    make_8bit_image(&src, tm);
    const char *path = tmp_path(name);
    EXPECT(image_write(path, &src, tm));
    EXPECT(image_read(path, &back, tm));
    EXPECT(same_image(&back, &src));
    bool bytes_ok = back.rgb != NULL;
    for (int y = 0; y < H && bytes_ok; y++)
        for (int x = 0; x < W; x++)
            for (int c = 0; c < 3; c++)
                if (tonemap_channel(back.rgb[(y * W + x) * 3 + c], tm) != test_byte(x, y, c))
                    bytes_ok = false;
    EXPECT(bytes_ok);
    image_free(&src);
    image_free(&back);
}

static void test_roundtrip_ppm(void) {
    roundtrip_8bit("rt_srgb.ppm", TONEMAP_SRGB);
    roundtrip_8bit("rt_linear.ppm", TONEMAP_LINEAR);
}

static void test_roundtrip_png(void) {
    roundtrip_8bit("rt_srgb.png", TONEMAP_SRGB);
    roundtrip_8bit("rt_linear.png", TONEMAP_LINEAR);
}

static void test_roundtrip_pfm(void) {
    image src, back;
    make_float_image(&src);
    src.rgb[4] = 1e-30f; /* tiny, huge, negative zero and infinity survive too */
    src.rgb[7] = 3e38f;
    src.rgb[11] = -0.0f;
    src.rgb[13] = INFINITY;
    EXPECT(image_write(tmp_path("rt.pfm"), &src, TONEMAP_SRGB));
    EXPECT(image_read(tmp_path("rt.pfm"), &back, TONEMAP_LINEAR));
    EXPECT(same_image(&back, &src));
    image_free(&src);
    image_free(&back);
}

static void test_all_bytes_through_files(void) {
    const char *names[] = {"all.ppm", "all.png"};
    for (int tm = TONEMAP_SRGB; tm <= TONEMAP_LINEAR; tm++) {
        for (int k = 0; k < 2; k++) {
            image src, back;
            image_init(&src, 256, 1);
            for (int i = 0; i < 256 * 3; i++)
                src.rgb[i] = tonemap_decode((uint8_t)((i / 3 + 85 * (i % 3)) % 256), (tonemap)tm);
            EXPECT(image_write(tmp_path(names[k]), &src, (tonemap)tm));
            EXPECT(image_read(tmp_path(names[k]), &back, (tonemap)tm));
            EXPECT(same_image(&back, &src));
            image_free(&src);
            image_free(&back);
        }
    }
}

static void test_ppm_bytes(void) {
    image src;
    make_8bit_image(&src, TONEMAP_SRGB);
    EXPECT(image_write(tmp_path("bytes.ppm"), &src, TONEMAP_SRGB));
    size_t len;
    unsigned char *data = tmp_file_read(tmp_path("bytes.ppm"), &len);
    const char header[] = "P6\n6 5\n255\n";
    size_t hl = sizeof header - 1;
    EXPECT(data && len == hl + W * H * 3);
    if (data && len == hl + W * H * 3) {
        EXPECT(memcmp(data, header, hl) == 0);
        bool ok = true; /* top row first, RGB order */
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                for (int c = 0; c < 3; c++)
                    ok = ok && data[hl + (size_t)(y * W + x) * 3 + c] == test_byte(x, y, c);
        EXPECT(ok);
    }
    free(data);
    image_free(&src);
}

static float le_float(const unsigned char *b) {
    uint32_t u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    float f;
    memcpy(&f, &u, 4);
    return f;
}

static void test_pfm_bytes(void) {
    image src;
    make_float_image(&src);
    EXPECT(image_write(tmp_path("bytes.pfm"), &src, TONEMAP_SRGB));
    size_t len;
    unsigned char *data = tmp_file_read(tmp_path("bytes.pfm"), &len);
    const char header[] = "PF\n6 5\n-1.0\n";
    size_t hl = sizeof header - 1;
    EXPECT(data && len == hl + W * H * 12);
    if (data && len == hl + W * H * 12) {
        EXPECT(memcmp(data, header, hl) == 0);
        EXPECT(le_float(data + hl) == test_float(0, H - 1, 0)); /* bottom-left red first */
        bool ok = true;
        for (int r = 0; r < H; r++)
            for (int x = 0; x < W; x++)
                for (int c = 0; c < 3; c++)
                    ok = ok && le_float(data + hl + (size_t)((r * W + x) * 3 + c) * 4) ==
                                   test_float(x, H - 1 - r, c);
        EXPECT(ok);
    }
    free(data);
    image_free(&src);
}

static void test_pfm_big_endian_and_gray(void) {
    /* big-endian PF, 2x1: 1.0 2.0 3.0 | -4.0 0.5 0.25 */
    unsigned char be[] =
        "PF\n2 1\n1.0\n"
        "\x3f\x80\x00\x00\x40\x00\x00\x00\x40\x40\x00\x00"
        "\xc0\x80\x00\x00\x3f\x00\x00\x00\x3e\x80\x00\x00";
    tmp_file_write(tmp_path("be.pfm"), be, sizeof be - 1);
    image img;
    EXPECT(image_read(tmp_path("be.pfm"), &img, TONEMAP_SRGB));
    float want_be[] = {1.0f, 2.0f, 3.0f, -4.0f, 0.5f, 0.25f};
    image ref_be = {2, 1, want_be};
    EXPECT(same_image(&img, &ref_be));
    image_free(&img);

    /* little-endian Pf, 2x2, bottom row (1, 2) first, then top row (3, 4) */
    unsigned char gray[] =
        "Pf\n2 2\n-1\n"
        "\x00\x00\x80\x3f\x00\x00\x00\x40\x00\x00\x40\x40\x00\x00\x80\x40";
    tmp_file_write(tmp_path("gray.pfm"), gray, sizeof gray - 1);
    EXPECT(image_read(tmp_path("gray.pfm"), &img, TONEMAP_SRGB));
    float want_gray[] = {3, 3, 3, 4, 4, 4, 1, 1, 1, 2, 2, 2};
    image ref_gray = {2, 2, want_gray};
    EXPECT(same_image(&img, &ref_gray));
    image_free(&img);
}

static void test_ppm_comments_and_p3(void) {
    unsigned char p6[] = "P6\n# a comment\n2 # width\n1\n255\n\x00\x80\xff\x01\x02\x03";
    tmp_file_write(tmp_path("comments.ppm"), p6, sizeof p6 - 1);
    float want[6];
    const uint8_t bytes[] = {0, 128, 255, 1, 2, 3};
    for (int i = 0; i < 6; i++) want[i] = tonemap_decode(bytes[i], TONEMAP_LINEAR);
    image ref = {2, 1, want}, img;
    EXPECT(image_read(tmp_path("comments.ppm"), &img, TONEMAP_LINEAR));
    EXPECT(same_image(&img, &ref));
    image_free(&img);

    const char p3[] = "P3\n# ascii\n2 1\n255\n0 128 255\n1 2 3\n";
    tmp_file_write(tmp_path("ascii.ppm"), p3, sizeof p3 - 1);
    EXPECT(image_read(tmp_path("ascii.ppm"), &img, TONEMAP_LINEAR));
    EXPECT(same_image(&img, &ref));
    image_free(&img);
}

static void test_extension_case(void) {
    image src, back;
    make_8bit_image(&src, TONEMAP_SRGB);
    EXPECT(image_write(tmp_path("UPPER.PPM"), &src, TONEMAP_SRGB));
    EXPECT(image_write(tmp_path("mixed.Png"), &src, TONEMAP_SRGB));
    EXPECT(image_read(tmp_path("UPPER.PPM"), &back, TONEMAP_SRGB) && same_image(&back, &src));
    image_free(&back);
    EXPECT(image_read(tmp_path("mixed.Png"), &back, TONEMAP_SRGB) && same_image(&back, &src));
    image_free(&back);
    image_free(&src);
}

/* The table gives tonemap_channel's byte: at each bound, just below it, and on a million
 * floats spread over [0, 1.5] and the special values. */
static void test_tonemap_table(void) {
    for (int tm = TONEMAP_SRGB; tm <= TONEMAP_LINEAR; tm++) {
        tonemap_table t;
        tonemap_table_init(&t, (tonemap)tm);
        bool same = true;
        for (int k = 1; k < 256; k++) {
            float below = nextafterf(t.bound[k], 0.0f);
            same &= tonemap_table_channel(&t, t.bound[k]) == tonemap_channel(t.bound[k], tm) &&
                    tonemap_channel(t.bound[k], tm) == k &&
                    tonemap_table_channel(&t, below) == tonemap_channel(below, tm);
        }
        uint32_t state = 2463534242u;
        for (int k = 0; k < 1000000; k++) {
            state ^= state << 13, state ^= state >> 17, state ^= state << 5;
            uint32_t bits = state % 0x3fc00000u; /* [0, 1.5) */
            float f;
            memcpy(&f, &bits, sizeof f);
            same &= tonemap_table_channel(&t, f) == tonemap_channel(f, tm);
        }
        const float special[] = {-0.0f,     -1.0f, 1.0f, 2.0f,   INFINITY,
                                 -INFINITY, NAN,   -NAN, 1e-45f, 1e-38f};
        for (size_t k = 0; k < sizeof special / sizeof special[0]; k++)
            same &= tonemap_table_channel(&t, special[k]) == tonemap_channel(special[k], tm);
        CHECK(same, "the tonemap table disagrees with tonemap_channel (tonemap %d)", tm);
    }
}

int main(void) {
    if (!tmp_dir_make("test_image")) {
        perror("mkdtemp");
        return 1;
    }
    /* the expected errors are noise; TRAZADOR_TEST_VERBOSE=1 shows them */
    if (!getenv("TRAZADOR_TEST_VERBOSE")) log_set_level((log_level)(LOG_ERROR + 1));
    CHECK_CASE(test_tonemap_known);
    CHECK_CASE(test_tonemap_decode_all_bytes);
    CHECK_CASE(test_film_average);
    CHECK_CASE(test_init_limits);
    CHECK_CASE(test_roundtrip_ppm);
    CHECK_CASE(test_roundtrip_png);
    CHECK_CASE(test_tonemap_table);
    CHECK_CASE(test_roundtrip_pfm);
    CHECK_CASE(test_all_bytes_through_files);
    CHECK_CASE(test_ppm_bytes);
    CHECK_CASE(test_pfm_bytes);
    CHECK_CASE(test_pfm_big_endian_and_gray);
    CHECK_CASE(test_ppm_comments_and_p3);
    CHECK_CASE(test_extension_case);
    remove_tree(tmpdir);
    return check_summary("test_image");
}
