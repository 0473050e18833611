/* image_hdr.h: a high-dynamic-range image read from a file as linear RGB floats, for the
 * environment map (scenes/README.md, `environment file`): OpenEXR through OpenEXRCore (exr.h),
 * Radiance HDR (RGBE, `#?RADIANCE`) through Debian's stb_image. */
#ifndef TRAZADOR_IMAGE_HDR_H
#define TRAZADOR_IMAGE_HDR_H

#include <stdbool.h>
#include <stddef.h>

#include "image/image.h"

/* Reads the HDR image at path into out (an EXR's R, G and B channels, or Y as grey, of half,
 * float or uint; a Radiance file's RGBE pixels); false with the reason in why (what the file is,
 * what the reader said), out zeroed. */
bool image_load_hdr(const char *path, image *out, char *why, size_t size);

#endif
