/* texture_decode.c: which decoder an image's bytes need, the file read whole, and the checks
 * every decoder makes before it decodes a pixel (texture.h). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "scene/texture.h"
#include "shared_layout.h"

bool texture_image_alloc(texture_image *out, uint32_t width, uint32_t height, uint32_t format,
                         size_t budget_bytes, char *error, size_t error_size) {
    if (width < 1 || height < 1 || width > TEXTURE_MAX_SIDE || height > TEXTURE_MAX_SIDE) {
        snprintf(error, error_size, "image of %u x %u pixels: at most %d a side", width, height,
                 TEXTURE_MAX_SIDE);
        return false;
    }
    size_t per_texel = format == TZ_TEXEL_RGBA8 ? 1 : 4;
    size_t words = (size_t)width * height * per_texel;
    if (words * 4 > budget_bytes) {
        snprintf(error, error_size,
                 "image of %u x %u pixels needs %zu bytes of texels, over what is left of the "
                 "scene's %u (its images in all)",
                 width, height, words * 4, TEXTURE_MAX_SCENE_BYTES);
        return false;
    }
    uint32_t *data = malloc(words * sizeof *data);
    if (!data) {
        snprintf(error, error_size, "out of memory for %zu bytes of texels", words * 4);
        return false;
    }
    *out = (texture_image){
        .width = width, .height = height, .format = format, .words = data, .word_count = words};
    return true;
}

void texture_image_free(texture_image *t) {
    free(t->words);
    *t = (texture_image){0};
}

bool texture_decode(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                    char *error, size_t error_size) {
    static const uint8_t png[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    static const uint8_t jpeg[3] = {0xff, 0xd8, 0xff};
    static const uint8_t exr[4] = {0x76, 0x2f, 0x31, 0x01};
    *out = (texture_image){0};
    bool ok;
    if (size >= sizeof png && !memcmp(bytes, png, sizeof png))
        ok = texture_decode_png(bytes, size, budget_bytes, out, error, error_size);
    else if (size >= sizeof jpeg && !memcmp(bytes, jpeg, sizeof jpeg))
        ok = texture_decode_jpeg(bytes, size, budget_bytes, out, error, error_size);
    else if (size >= sizeof exr && !memcmp(bytes, exr, sizeof exr))
        ok = texture_decode_exr(bytes, size, budget_bytes, out, error, error_size);
    else {
        snprintf(error, error_size, "not a PNG, JPEG or OpenEXR image");
        ok = false;
    }
    if (!ok) texture_image_free(out);
    return ok;
}

bool texture_load_file(const char *path, size_t budget_bytes, texture_image *out, char *error,
                       size_t error_size) {
    *out = (texture_image){0};
    FILE *fp = fopen(path, "rb");
    struct stat st;
    if (!fp || fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode)) {
        snprintf(error, error_size, "%s", fp ? "not a regular file" : strerror(errno));
        if (fp) fclose(fp);
        return false;
    }
    if ((uint64_t)st.st_size > TEXTURE_MAX_FILE_BYTES) {
        snprintf(error, error_size, "a file of %lld bytes: at most %u", (long long)st.st_size,
                 TEXTURE_MAX_FILE_BYTES);
        fclose(fp);
        return false;
    }
    size_t size = (size_t)st.st_size;
    uint8_t *bytes = malloc(size ? size : 1);
    bool ok = bytes && fread(bytes, 1, size, fp) == size && !ferror(fp);
    if (!ok) snprintf(error, error_size, "%s", bytes ? "cannot read the file" : "out of memory");
    fclose(fp);
    ok = ok && texture_decode(bytes, size, budget_bytes, out, error, error_size);
    free(bytes);
    return ok;
}
