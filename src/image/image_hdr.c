/* image_hdr.c: HDR images as linear RGB (image_hdr.h): the file's kind told by its first bytes,
 * OpenEXR read through exr.h with the reader's messages held for the caller, Radiance HDR (RGBE)
 * through stb_image, as Debian's libstb builds it (no decoder of the project's own; stb is the
 * small, kept HDR reader Debian has besides OpenImageIO). */
#include "image/image_hdr.h"

#include <errno.h>
#include <stb_image.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "image/exr.h"
#include "util/log.h"

/* A sample of an EXR channel as a float. */
static float channel_float(const exr_channel *ch, size_t i) {
    if (ch->type == EXR_SAMPLE_HALF) return exr_half_to_float(((const uint16_t *)ch->data)[i]);
    if (ch->type == EXR_SAMPLE_UINT) return (float)((const uint32_t *)ch->data)[i];
    return ((const float *)ch->data)[i];
}

/* The first line of the errors held while reading, without the program's prefix. */
static void first_held(const char *held, char *why, size_t size) {
    const char *text = strstr(held, "error: ");
    text = text ? text + strlen("error: ") : held;
    size_t n = strcspn(text, "\n");
    snprintf(why, size, "not a readable OpenEXR image (%.*s)", (int)n, text);
}

/* The EXR at path into out; false with the reason in why. */
static bool load_exr(const char *path, image *out, char *why, size_t size) {
    exr_file f;
    log_hold_errors();
    bool read = exr_file_read(path, &f);
    const char *held = log_release_errors();
    if (!read) {
        first_held(held, why, size);
        return false;
    }
    const exr_channel *rgb[3] = {exr_file_channel(&f, "R"), exr_file_channel(&f, "G"),
                                 exr_file_channel(&f, "B")};
    const exr_channel *grey = exr_file_channel(&f, "Y");
    bool colour = rgb[0] && rgb[1] && rgb[2], ok = colour || grey;
    if (!ok) snprintf(why, size, "an OpenEXR image without R, G and B (or Y) channels");
    log_hold_errors();
    if (ok && !image_init(out, f.width, f.height)) {
        snprintf(why, size, "an OpenEXR image of %d x %d pixels: more than %d a side or memory",
                 f.width, f.height, IMAGE_MAX_DIM);
        ok = false;
    }
    log_release_errors();
    size_t n = (size_t)f.width * (size_t)f.height;
    for (size_t i = 0; ok && i < n; i++)
        for (int c = 0; c < 3; c++)
            out->rgb[3 * i + (size_t)c] = channel_float(colour ? rgb[c] : grey, i);
    exr_file_free(&f);
    return ok;
}

/* The Radiance HDR at path into out; false with the reason in why. */
static bool load_radiance(const char *path, image *out, char *why, size_t size) {
    int w = 0, h = 0, channels = 0;
    float *rgb = stbi_loadf(path, &w, &h, &channels, 3);
    if (!rgb) {
        snprintf(why, size, "not a readable Radiance HDR image (%s)", stbi_failure_reason());
        return false;
    }
    log_hold_errors();
    bool ok = image_init(out, w, h);
    log_release_errors();
    if (ok)
        memcpy(out->rgb, rgb, (size_t)w * (size_t)h * 3 * sizeof *rgb);
    else
        snprintf(why, size, "a Radiance HDR image of %d x %d pixels: more than %d a side or memory",
                 w, h, IMAGE_MAX_DIM);
    stbi_image_free(rgb);
    return ok;
}

bool image_load_hdr(const char *path, image *out, char *why, size_t size) {
    *out = (image){0};
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        snprintf(why, size, "%s", strerror(errno));
        return false;
    }
    unsigned char magic[4] = {0};
    size_t got = fread(magic, 1, sizeof magic, fp);
    fclose(fp);
    static const unsigned char exr_magic[4] = {0x76, 0x2f, 0x31, 0x01};
    if (got == sizeof magic && !memcmp(magic, exr_magic, sizeof magic))
        return load_exr(path, out, why, size);
    if (got >= 2 && magic[0] == '#' && magic[1] == '?') return load_radiance(path, out, why, size);
    snprintf(why, size, "neither an OpenEXR nor a Radiance HDR image");
    return false;
}
