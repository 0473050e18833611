/* exr_image.c: an image as a plain OpenEXR file (R, G and B, half or float) and back, through
 * the file layer of exr.c. */
#include <math.h>
#include <stdlib.h>

#include "image/exr.h"
#include "util/big_memory.h"
#include "util/log.h"

bool exr_write_image(const char *path, const image *img, bool half) {
    size_t n = (size_t)img->width * (size_t)img->height;
    exr_channel channels[3] = {{.name = "B"}, {.name = "G"}, {.name = "R"}};
    bool ok = true;
    for (int c = 0; c < 3; c++) {
        channels[c].type = half ? EXR_SAMPLE_HALF : EXR_SAMPLE_FLOAT;
        channels[c].data = big_malloc(n * (half ? sizeof(uint16_t) : sizeof(float)));
        if (!channels[c].data) ok = false;
    }
    if (!ok) log_error("%s: out of memory for a %dx%d image", path, img->width, img->height);
    size_t overflowed = 0; /* pixels with a finite value that half float makes infinite */
    for (size_t i = 0; ok && i < n; i++) {
        bool over = false;
        for (int c = 0; c < 3; c++) {
            float v = img->rgb[3 * i + (size_t)(2 - c)]; /* channels are B, G, R */
            if (half) {
                uint16_t h = exr_half_from_float(v);
                ((uint16_t *)channels[c].data)[i] = h;
                over = over || (isfinite(v) && (h & 0x7fffu) == 0x7c00u);
            } else {
                ((float *)channels[c].data)[i] = v;
            }
        }
        overflowed += over;
    }
    exr_file f = {.display_width = img->width,
                  .display_height = img->height,
                  .width = img->width,
                  .height = img->height,
                  .channel_count = 3,
                  .channels = channels};
    ok = ok && exr_file_write(path, &f);
    if (ok && overflowed)
        log_warn(
            "%s: %zu pixel%s past 65504, the largest half float, %s infinite in this half "
            "EXR (--exr-type float keeps %s)",
            path, overflowed, overflowed == 1 ? "" : "s", overflowed == 1 ? "is" : "are",
            overflowed == 1 ? "it" : "them");
    for (int c = 0; c < 3; c++) free(channels[c].data);
    return ok;
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
