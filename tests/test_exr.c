/* test_exr.c: src/image/exr.c: half conversion, channels and attributes written and read back bit
 * for bit, data and display windows, RGB images in half and float, and corrupt, truncated and
 * foreign files refused with a message that names the file. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "image/exr.h"
#include "tmp_dir.h"
#include "util/log.h"

static uint32_t rng_state = 12345u;
static uint32_t next_u32(void) {
    rng_state = rng_state * 1664525u + 1013904223u;
    return rng_state ^ (rng_state >> 16);
}

static float float_of(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Every half converts to a float and back to itself (NaNs stay NaN); floats round to the
 * nearest half, ties to even. */
static void test_half(void) {
    int bad = 0;
    for (uint32_t h = 0; h < 65536; h++) {
        float f = exr_half_to_float((uint16_t)h);
        uint16_t back = exr_half_from_float(f);
        bool nan = ((h >> 10) & 0x1f) == 31 && (h & 0x3ff);
        if (nan ? !(isnan(f) && (back & 0x7c00) == 0x7c00 && (back & 0x3ff)) : back != h) bad++;
    }
    CHECK(bad == 0, "%d halves do not round-trip", bad);
    EXPECT(exr_half_to_float(0x3c00) == 1.0f && exr_half_to_float(0x7bff) == 65504.0f);
    EXPECT(exr_half_to_float(0x0001) == 0x1p-24f && exr_half_to_float(0xc000) == -2.0f);
    EXPECT(exr_half_from_float(65519.0f) == 0x7bff && exr_half_from_float(65520.0f) == 0x7c00);
    EXPECT(exr_half_from_float(1.0f + 0x1p-11f) == 0x3c00);     /* tie to even: down */
    EXPECT(exr_half_from_float(1.0f + 3 * 0x1p-11f) == 0x3c02); /* tie to even: up */
    EXPECT(exr_half_from_float(0x1p-25f) == 0 && exr_half_from_float(0x1.8p-25f) == 1);
    EXPECT(exr_half_from_float(-0.0f) == 0x8000 && exr_half_from_float(-INFINITY) == 0xfc00);
    /* Nearest: no half next to the result is closer to x. */
    int far = 0;
    for (int i = 0; i < 200000; i++) {
        float x = float_of(next_u32() % 0x477ff000u); /* positive, below the half overflow */
        uint16_t h = exr_half_from_float(x);
        double d = fabs((double)exr_half_to_float(h) - x);
        if ((h > 0 && fabs((double)exr_half_to_float((uint16_t)(h - 1)) - x) < d) ||
            (h < 0x7bff && fabs((double)exr_half_to_float((uint16_t)(h + 1)) - x) < d))
            far++;
    }
    CHECK(far == 0, "%d floats not rounded to the nearest half", far);
}

/* A 7x5 data window at (3, 2) of a 16x9 display window, float channels of arbitrary bits (NaN
 * payloads, -0, subnormals, infinities), a uint and a half channel, and string attributes. */
static void test_channels_round_trip(void) {
    enum { W = 7, H = 5, N = W * H };
    float bits[N], neg[N];
    uint32_t counts[N];
    uint16_t halves[N];
    for (int i = 0; i < N; i++) {
        uint32_t u = next_u32();
        memcpy(&bits[i], &u, sizeof u);
        neg[i] = -(float)i;
        counts[i] = next_u32();
        halves[i] = (uint16_t)next_u32();
    }
    uint32_t specials[] = {0x7fc00001u, 0xffbfffffu, 0x80000000u,
                           0x00000001u, 0x7f800000u, 0xff800000u};
    memcpy(bits, specials, sizeof specials);
    exr_channel ch[4] = {{.name = "sum.0-4.R", .type = EXR_SAMPLE_FLOAT, .data = bits},
                         {.name = "count", .type = EXR_SAMPLE_UINT, .data = counts},
                         {.name = "a.very.long.channel.name.past.thirty.one.chars",
                          .type = EXR_SAMPLE_FLOAT,
                          .data = neg},
                         {.name = "H", .type = EXR_SAMPLE_HALF, .data = halves}};
    exr_attr attrs[2] = {{.name = "trazador.samples", .value = "16:48"},
                         {.name = "trazador.digest", .value = "0123456789abcdef"}};
    exr_file f = {.display_width = 16,
                  .display_height = 9,
                  .x0 = 3,
                  .y0 = 2,
                  .width = W,
                  .height = H,
                  .channel_count = 4,
                  .channels = ch,
                  .attr_count = 2,
                  .attrs = attrs};
    const char *path = tmp_path("channels.exr");
    EXPECT(exr_file_write(path, &f));
    exr_file g;
    EXPECT(exr_file_read(path, &g));
    EXPECT(g.display_width == 16 && g.display_height == 9 && g.x0 == 3 && g.y0 == 2 &&
           g.width == W && g.height == H && g.channel_count == 4);
    for (int c = 0; c < 4; c++) {
        const exr_channel *r = exr_file_channel(&g, ch[c].name);
        CHECK(r && r->type == ch[c].type, "channel %s", ch[c].name);
        size_t bytes = ch[c].type == EXR_SAMPLE_HALF ? 2 : 4;
        CHECK(r && !memcmp(r->data, ch[c].data, N * bytes), "channel %s differs", ch[c].name);
    }
    EXPECT(exr_file_attr(&g, "trazador.samples") &&
           !strcmp(exr_file_attr(&g, "trazador.samples"), "16:48"));
    EXPECT(exr_file_attr(&g, "trazador.digest") &&
           !strcmp(exr_file_attr(&g, "trazador.digest"), "0123456789abcdef"));
    EXPECT(exr_file_attr(&g, "nothing") == NULL && exr_file_channel(&g, "nothing") == NULL);
    exr_file_free(&g);

    /* A data window outside the display window, and duplicate names, are refused. */
    log_hold_errors();
    f.x0 = 10;
    EXPECT(!exr_file_write(tmp_path("outside.exr"), &f));
    f.x0 = 3;
    snprintf(ch[1].name, sizeof ch[1].name, "sum.0-4.R");
    EXPECT(!exr_file_write(tmp_path("twice.exr"), &f));
    const char *held = log_release_errors();
    EXPECT(strstr(held, "outside.exr") && strstr(held, "twice.exr"));
    EXPECT(access(tmp_path("outside.exr"), F_OK) != 0);
}

/* An asymmetric 6x5 RGB image: float exactly, half within half precision. */
static void test_image_round_trip(void) {
    image img;
    EXPECT(image_init(&img, 6, 5));
    for (int i = 0; i < 6 * 5 * 3; i++) img.rgb[i] = (float)i * 0.37f + (i % 3 == 1 ? 1e-3f : 0);
    img.rgb[3 * 7 + 2] = 1e6f;
    for (int half = 0; half < 2; half++) {
        const char *path = tmp_path(half ? "half.exr" : "float.exr");
        EXPECT(exr_write_image(path, &img, half));
        image back;
        EXPECT(exr_read_image(path, &back));
        EXPECT(back.width == 6 && back.height == 5);
        int bad = 0;
        for (int i = 0; back.rgb && i < 6 * 5 * 3; i++) {
            float want = img.rgb[i], got = back.rgb[i];
            if (half ? (want > 65504.0f ? got != INFINITY
                                        : fabsf(got - want) > fabsf(want) * 0x1p-11f)
                     : memcmp(&got, &want, sizeof got) != 0)
                bad++;
        }
        CHECK(bad == 0, "%s: %d samples off", path, bad);
        image_free(&back);
    }
    image_free(&img);
}

/* Every truncation of a valid file, and bytes flipped through it, are refused (or, for a flip in
 * pixel data that ZIP does not notice, read as a whole image), never a crash; the message names
 * the file. A text file and a missing file are refused too. */
static void test_damaged_files(void) {
    image img;
    EXPECT(image_init(&img, 40, 37));
    for (int i = 0; i < 40 * 37 * 3; i++) img.rgb[i] = (float)(next_u32() % 1000) / 7.0f;
    const char *good = tmp_path("good.exr"), *bad = tmp_path("damaged.exr");
    EXPECT(exr_write_image(good, &img, false));
    size_t len = 0;
    unsigned char *data = tmp_file_read(good, &len);
    EXPECT(data && len > 100);
    int accepted = 0, unnamed = 0;
    for (size_t cut = 0; data && cut < len; cut += cut < 400 ? 1 : 97) {
        tmp_file_write(bad, data, cut);
        image back;
        log_hold_errors();
        bool ok = exr_read_image(bad, &back);
        const char *held = log_release_errors();
        if (ok) accepted++;
        if (!ok && !strstr(held, bad)) unnamed++;
        image_free(&back);
    }
    CHECK(accepted == 0, "%d truncated files read as images", accepted);
    CHECK(unnamed == 0, "%d refusals do not name the file", unnamed);
    int flips_refused = 0;
    for (int k = 0; data && k < 300; k++) {
        unsigned char *copy = malloc(len);
        memcpy(copy, data, len);
        size_t at = next_u32() % len;
        copy[at] ^= (unsigned char)(1u + next_u32() % 255u);
        tmp_file_write(bad, copy, len);
        image back;
        log_hold_errors();
        bool ok = exr_read_image(bad, &back);
        log_release_errors();
        if (ok)
            EXPECT(back.width >= 1 && back.height >= 1 && back.rgb);
        else
            flips_refused++;
        image_free(&back);
        free(copy);
    }
    CHECK(flips_refused > 0, "no flipped file was refused");
    tmp_file_write(bad, (const unsigned char *)"P3\n1 1\n255\n0 0 0\n", 17);
    log_hold_errors();
    image back;
    EXPECT(!exr_read_image(bad, &back));
    EXPECT(!exr_read_image(tmp_path("missing.exr"), &back));
    const char *held = log_release_errors();
    EXPECT(strstr(held, "damaged.exr") && strstr(held, "missing.exr"));
    /* A half-only file without R, G, B reads as no image. */
    uint16_t h[4] = {0};
    exr_channel ch = {.name = "Y", .type = EXR_SAMPLE_HALF, .data = h};
    exr_file f = {.display_width = 2,
                  .display_height = 2,
                  .width = 2,
                  .height = 2,
                  .channel_count = 1,
                  .channels = &ch};
    EXPECT(exr_file_write(bad, &f));
    log_hold_errors();
    EXPECT(!exr_read_image(bad, &back));
    EXPECT(strstr(log_release_errors(), "no R, G and B"));
    free(data);
    image_free(&img);
}

int main(void) {
    if (!tmp_dir_make("test_exr")) return 1;
    CHECK_CASE(test_half);
    CHECK_CASE(test_channels_round_trip);
    CHECK_CASE(test_image_round_trip);
    CHECK_CASE(test_damaged_files);
    const char *names[] = {"channels.exr", "half.exr", "float.exr", "good.exr", "damaged.exr"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) unlink(tmp_path(names[i]));
    rmdir(tmpdir);
    return check_summary("test_exr");
}
