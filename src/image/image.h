/* image.h: float RGB images, the film -> image resolve, tonemapping, PPM/PNG/PFM read and write
 * (PNG in image_png.c). */
#ifndef TRAZADOR_IMAGE_H
#define TRAZADOR_IMAGE_H

#include <stdbool.h>
#include <stdint.h>
#include <string.h>

#include "image/film.h"

typedef enum tonemap { TONEMAP_SRGB = 0, TONEMAP_LINEAR = 1 } tonemap;

/* Largest width or height image_init and image_read accept. */
#define IMAGE_MAX_DIM 16384

/* Linear float RGB, rows top to bottom, 3 floats a pixel. */
typedef struct image {
    int width, height;
    float *rgb;
} image;

/* Allocates a black width x height image; false on a size outside 1..IMAGE_MAX_DIM or OOM. */
bool image_init(image *img, int width, int height);
/* Averages the film into a new image (sum / count, black where count is 0); false on OOM. */
bool image_from_film(const film *f, image *out);
/* Frees the pixels; safe on a zeroed image. */
void image_free(image *img);
/* Clamps to [0,1] and applies the transfer function: 8-bit value of one linear channel. */
uint8_t tonemap_channel(float linear, tonemap tm);
/* Clamps to [0,1] (NaN to 0) and applies the transfer function, unquantized: display value in
 * [0,1]; never fails. */
double tonemap_encode(float linear, tonemap tm);
/* tonemap_channel as tables: bound[k] is the least float that encodes to k or more (k = 1..255),
 * and start[i] the byte of the least float in [0, 1) whose bits begin with the 16 bits i, so a
 * channel costs a look-up and a comparison or two instead of a pow. */
#define TONEMAP_TABLE_STARTS (0x3f800000u >> 16) /* the bits of 1.0f, shifted */
typedef struct tonemap_table {
    float bound[257]; /* bound[256] is +infinity, past every value */
    uint8_t start[TONEMAP_TABLE_STARTS];
} tonemap_table;
/* Fills the table for tm from tonemap_channel itself; never fails. */
void tonemap_table_init(tonemap_table *t, tonemap tm);
/* tonemap_channel(linear, tm) through the table, to the same byte; never fails. */
static inline uint8_t tonemap_table_channel(const tonemap_table *t, float linear) {
    uint32_t bits;
    memcpy(&bits, &linear, sizeof bits);
    /* Past 1.0f come the sign bit (negatives and -0 encode to 0), +infinity and NaN. */
    if (bits >= 0x3f800000u) return bits <= 0x7f800000u ? 255 : 0;
    unsigned k = t->start[bits >> 16];
    while (linear >= t->bound[k + 1]) k++;
    return (uint8_t)k;
}
/* Inverse of tonemap_channel: a linear value that encodes back to exactly `value` (never fails). */
float tonemap_decode(uint8_t value, tonemap tm);
/* Writes .ppm, .png, .pfm or .exr (half; exr_write_image for float) by extension via a temporary
 * file and rename; false on error. */
bool image_write(const char *path, const image *img, tonemap tm);
/* The format ("ppm", "png", "pfm" or "exr") the path's extension names, any case; NULL for none. */
const char *image_path_format(const char *path);
/* image_write in `format` ("ppm", "png", "pfm" or "exr"; NULL: by extension) whatever the path's
 * name, for outputs such as /dev/stdout; false on error. */
bool image_write_as(const char *path, const char *format, const image *img, tonemap tm);
/* The film's mean as an image written by image_write_as, an EXR one with half or float channels
 * (exr_half) and the film's feature images as layers; false (logged) on error. */
bool image_write_film(const char *path, const char *format, const film *f, tonemap tm,
                      bool exr_half);
/* Reads .ppm, .png, .pfm or .exr (8-bit formats decoded with tm back to linear); false on error. */
bool image_read(const char *path, image *out, tonemap tm);
/* Writes each feature image of f (f->aov) as a file of its own beside path: NAME.albedo.exr and
 * so on for an EXR output (half or float), NAME.albedo.pfm for any other (depth in all three
 * channels); false (logged) on failure. */
bool image_write_aov_files(const char *path, const char *format, const film *f, bool exr_half);

#endif
