/* image_png.h: PNG read and write through libpng (which checks every chunk's CRC). */
#ifndef TRAZADOR_IMAGE_PNG_H
#define TRAZADOR_IMAGE_PNG_H

#include <stdio.h>

#include "image/image.h"

/* zlib level of the PNGs written (docs/PERF.md, "Image output"). */
#define IMAGE_PNG_LEVEL 1

/* Writes img as an 8-bit RGB PNG, tonemapped with tm; 0 or an errno value. */
int image_png_write(FILE *fp, const image *img, tonemap tm);
/* Reads a PNG of 8 or 16 bits a channel (gray, palette or RGB; decoded with tm back to linear),
 * with alpha only when every pixel is opaque; false (logged, naming path) otherwise. */
bool image_png_read(FILE *fp, const char *path, image *out, tonemap tm);

#endif
