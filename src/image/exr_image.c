/* exr_image.c: an image as a plain OpenEXR file (R, G and B, half or float, and the feature
 * images as layers) and back, through the file layer of exr.c. */
#include <math.h>
#include <stdlib.h>

#include "image/exr.h"
#include "util/big_memory.h"
#include "util/log.h"

/* Stores v as channel sample i (half or float); whether a finite v became infinite. */
static bool store_sample(exr_channel *ch, size_t i, float v) {
    if (ch->type == EXR_SAMPLE_FLOAT) {
        ((float *)ch->data)[i] = v;
        return false;
    }
    uint16_t h = exr_half_from_float(v);
    ((uint16_t *)ch->data)[i] = h;
    return isfinite(v) && (h & 0x7fffu) == 0x7c00u;
}

/* Up to this many channels: R, G, B and every feature image's. */
#define IMAGE_CHANNELS_MAX (3 + 3 * AOV_COUNT)

bool exr_write_image_aov(const char *path, const image *img, bool half, const aov_set *aov) {
    size_t n = (size_t)img->width * (size_t)img->height;
    exr_channel channels[IMAGE_CHANNELS_MAX] = {{.name = "B"}, {.name = "G"}, {.name = "R"}};
    const float *source[IMAGE_CHANNELS_MAX]; /* interleaved: sample i at source[c][stride * i] */
    int stride[IMAGE_CHANNELS_MAX], count = 3;
    for (int c = 0; c < 3; c++) source[c] = img->rgb + (2 - c), stride[c] = 3; /* B, G, R */
    for (int k = 0; aov && k < AOV_COUNT; k++) {
        if (!(aov->mask & 1u << k)) continue;
        int w = aov_channels((aov_kind)k);
        for (int c = 0; c < w; c++, count++) {
            aov_channel_name((aov_kind)k, c, channels[count].name, sizeof channels[count].name);
            source[count] = aov->plane[k] + c;
            stride[count] = w;
        }
    }
    bool ok = true;
    for (int c = 0; c < count; c++) {
        channels[c].type = half ? EXR_SAMPLE_HALF : EXR_SAMPLE_FLOAT;
        channels[c].data = big_malloc(n * (half ? sizeof(uint16_t) : sizeof(float)));
        if (!channels[c].data) ok = false;
    }
    if (!ok) log_error("%s: out of memory for a %dx%d image", path, img->width, img->height);
    size_t overflowed = 0; /* pixels with a finite value that half float makes infinite */
    for (size_t i = 0; ok && i < n; i++) {
        bool over = false;
        for (int c = 0; c < count; c++)
            over |= store_sample(&channels[c], i, source[c][(size_t)stride[c] * i]) && c < 3;
        overflowed += over;
    }
    exr_file f = {.display_width = img->width,
                  .display_height = img->height,
                  .width = img->width,
                  .height = img->height,
                  .channel_count = count,
                  .channels = channels};
    ok = ok && exr_file_write(path, &f);
    if (ok && overflowed)
        log_warn(
            "%s: %zu pixel%s past 65504, the largest half float, %s infinite in this half "
            "EXR (--exr-type float keeps %s)",
            path, overflowed, overflowed == 1 ? "" : "s", overflowed == 1 ? "is" : "are",
            overflowed == 1 ? "it" : "them");
    for (int c = 0; c < count; c++) free(channels[c].data);
    return ok;
}

bool exr_write_image(const char *path, const image *img, bool half) {
    return exr_write_image_aov(path, img, half, NULL);
}

/* Sample i of a channel as a float. */
static float sample_float(const exr_channel *ch, size_t i) {
    if (ch->type == EXR_SAMPLE_HALF) return exr_half_to_float(((const uint16_t *)ch->data)[i]);
    if (ch->type == EXR_SAMPLE_UINT) return (float)((const uint32_t *)ch->data)[i];
    return ((const float *)ch->data)[i];
}

bool exr_read_image(const char *path, image *out) {
    *out = (image){0};
    exr_file f;
    if (!exr_file_read(path, &f)) return false;
    const exr_channel *rgb[3] = {exr_file_channel(&f, "R"), exr_file_channel(&f, "G"),
                                 exr_file_channel(&f, "B")};
    bool ok = rgb[0] && rgb[1] && rgb[2];
    if (!ok) log_error("%s: no R, G and B channels", path);
    ok = ok && image_init(out, f.width, f.height);
    size_t n = (size_t)f.width * (size_t)f.height;
    for (size_t i = 0; ok && i < n; i++)
        for (int c = 0; c < 3; c++) out->rgb[3 * i + (size_t)c] = sample_float(rgb[c], i);
    exr_file_free(&f);
    return ok;
}
