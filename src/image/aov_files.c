/* aov_files.c: the feature images as files of their own beside the image (--aov-files), the
 * PFM files OpenImageDenoise's example reads or EXR. */
#include <stdio.h>
#include <string.h>

#include "image/exr.h"
#include "image/image.h"
#include "util/log.h"

/* path without its extension, then ".", the kind's name and ext, into out; false when too long. */
static bool beside(const char *path, const char *name, const char *ext, char *out, size_t size) {
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    size_t stem = dot && (!slash || dot > slash) ? (size_t)(dot - path) : strlen(path);
    int n = snprintf(out, size, "%.*s.%s.%s", (int)stem, path, name, ext);
    return n > 0 && (size_t)n < size;
}

bool image_write_aov_files(const char *path, const char *format, const film *f, bool exr_half) {
    const char *named = format ? format : image_path_format(path);
    bool exr = named && !strcmp(named, "exr");
    image img = {0};
    bool ok = image_init(&img, f->width, f->height);
    if (!ok) log_error("%s: out of memory for a %dx%d image", path, f->width, f->height);
    size_t n = (size_t)f->width * (size_t)f->height;
    for (int k = 0; ok && k < AOV_COUNT; k++) {
        if (!(f->aov.mask & 1u << k)) continue;
        int w = aov_channels((aov_kind)k);
        for (size_t i = 0; i < n; i++)
            for (int c = 0; c < 3; c++)
                img.rgb[3 * i + (size_t)c] =
                    f->aov.plane[k][(size_t)w * i + (size_t)(w == 3 ? c : 0)];
        char name[4096];
        if (!beside(path, aov_name((aov_kind)k), exr ? "exr" : "pfm", name, sizeof name)) {
            log_error("%s: too long a name for its %s image", path, aov_name((aov_kind)k));
            ok = false;
        }
        ok = ok && (exr ? exr_write_image(name, &img, exr_half)
                        : image_write_as(name, "pfm", &img, TONEMAP_LINEAR));
        if (ok) log_debug("%s: the %s image", name, aov_name((aov_kind)k));
    }
    image_free(&img);
    return ok;
}
