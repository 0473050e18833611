/* exr.h: OpenEXR files through OpenEXRCore (the C library of Debian's libopenexr-dev): one
 * scanline part of named planar channels (uint32, half or float, stored losslessly, with ZIP or
 * as is, so float and uint channels round-trip bit for bit), its data window inside a display
 * window, and string header attributes; plus RGB images as EXR. Writes are atomic
 * (util/atomic_file.h). */
#ifndef TRAZADOR_EXR_H
#define TRAZADOR_EXR_H

#include <stdbool.h>
#include <stdint.h>

#include "image/aov.h"
#include "image/image.h"

typedef enum exr_sample_type { EXR_SAMPLE_UINT, EXR_SAMPLE_HALF, EXR_SAMPLE_FLOAT } exr_sample_type;

/* Longest channel or attribute name (EXR's long-name limit), and longest attribute value. */
#define EXR_NAME_MAX 255
#define EXR_VALUE_MAX 1023

/* One channel: width * height samples of the data window, rows top to bottom: uint32_t, uint16_t
 * (half bits, exr_half_from_float) or float. */
typedef struct exr_channel {
    char name[EXR_NAME_MAX + 1];
    exr_sample_type type;
    void *data;
} exr_channel;

/* One string header attribute. */
typedef struct exr_attr {
    char name[EXR_NAME_MAX + 1];
    char value[EXR_VALUE_MAX + 1];
} exr_attr;

/* A file's content: the display window is (0, 0) to (display_width - 1, display_height - 1); the
 * data window starts at (x0, y0) and is width x height pixels, inside it. */
typedef struct exr_file {
    int display_width, display_height;
    int x0, y0, width, height;
    int channel_count;
    exr_channel *channels;
    int attr_count;
    exr_attr *attrs;
    bool uncompressed; /* stored as is, not ZIP-compressed (docs/PERF.md, "Split renders") */
} exr_file;

/* Writes f to path atomically; false (logged) on a bad description or an I/O error, leaving any
 * old file intact. */
bool exr_file_write(const char *path, const exr_file *f);
/* Reads a single-part scanline file into out (channels and string attributes allocated; other
 * attribute types are skipped); false (logged, naming the file) on an unreadable, corrupt,
 * truncated or unsupported file, with out zeroed. */
bool exr_file_read(const char *path, exr_file *out);
/* Frees what exr_file_read allocated; safe on a zeroed exr_file. */
void exr_file_free(exr_file *f);
/* The channel called name; NULL if there is none. */
const exr_channel *exr_file_channel(const exr_file *f, const char *name);
/* The value of the attribute called name; NULL if there is none. */
const char *exr_file_attr(const exr_file *f, const char *name);

/* The half nearest to x (ties to even; overflow to infinity, NaN stays NaN); never fails. */
uint16_t exr_half_from_float(float x);
/* The float equal to half h; never fails. */
float exr_half_to_float(uint16_t h);

/* Writes img as linear RGB (half or float channels R, G, B); false (logged) on failure. */
bool exr_write_image(const char *path, const image *img, bool half);
/* exr_write_image with the feature images of aov (NULL: none; each pixel of img's size) as
 * layers ("albedo.R", "normal.X", "depth.Z", ...); false (logged) on failure. */
bool exr_write_image_aov(const char *path, const image *img, bool half, const aov_set *aov);
/* Reads the R, G, B channels of an EXR (half, float or uint) as a linear image of its data
 * window; false (logged) on failure or when a channel is missing. */
bool exr_read_image(const char *path, image *out);

#endif
