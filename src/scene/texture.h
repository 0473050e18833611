/* texture.h: image files decoded into texels for the texture table (scenes/README.md,
 * "Textures"): PNG (libpng), JPEG (libjpeg-turbo) and OpenEXR (OpenEXRCore), from a file or from
 * bytes in memory (a glTF's embedded image), each a format of the shared layout's texel table
 * (TZ_TEXEL_*): 8-bit images stay 8-bit, four channels a 32-bit word; 16-bit and float images
 * become four floats a texel. */
#ifndef TRAZADOR_TEXTURE_H
#define TRAZADOR_TEXTURE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

/* The largest side an image may have, and the most texel bytes a scene's images may hold in all
 * (counted after decoding): past them an image is refused before its pixels are decoded, so a
 * small file claiming a huge image (a decompression bomb) costs nothing. */
#define TEXTURE_MAX_SIDE 16384
#define TEXTURE_MAX_SCENE_BYTES (1024u * 1024u * 1024u)
/* The largest image file read (a 16384 x 16384 float EXR, uncompressed, is 3 GiB; JPEG and PNG
 * of that size are far smaller). */
#define TEXTURE_MAX_FILE_BYTES (512u * 1024u * 1024u)

/* A decoded image: format TZ_TEXEL_RGBA8 (a word a texel: R in the low byte, then G, B, A, as
 * stored, sRGB or linear as its use decides) or TZ_TEXEL_RGBA32F (four words a texel, the bits of
 * linear floats); rows top first. */
typedef struct texture_image {
    uint32_t width, height;
    uint32_t format;
    uint32_t *words;
    size_t word_count;
} texture_image;

/* Decodes an image file's bytes (PNG, JPEG or OpenEXR, told by their first bytes); false with the
 * reason in error (no path: the caller names the file) on anything else, a corrupt or truncated
 * image, one over TEXTURE_MAX_SIDE a side or over budget_bytes of texels, or out of memory
 * (*out_of_memory set, when given). */
bool texture_decode(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                    char *error, size_t error_size);
/* Reads and decodes the image file at path (texture_decode); false with the reason in error. */
bool texture_load_file(const char *path, size_t budget_bytes, texture_image *out, char *error,
                       size_t error_size);
/* Frees an image's texels (a zeroed image too). */
void texture_image_free(texture_image *t);

/* The decoders texture_decode picks from (texture_png.c, texture_jpeg.c, texture_exr.c): each
 * false with the reason in error. */
bool texture_decode_png(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                        char *error, size_t error_size);
bool texture_decode_jpeg(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                         char *error, size_t error_size);
bool texture_decode_exr(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                        char *error, size_t error_size);
/* Allocates out's texels for a width x height image of format (TZ_TEXEL_*) after checking the
 * side and the budget; false with the reason in error. */
bool texture_image_alloc(texture_image *out, uint32_t width, uint32_t height, uint32_t format,
                         size_t budget_bytes, char *error, size_t error_size);

#endif
