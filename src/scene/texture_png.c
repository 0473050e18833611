/* texture_png.c: a PNG image's bytes as texels through libpng: every colour type (grey, grey and
 * alpha, palette, RGB, RGBA; tRNS as alpha) becomes RGBA, 8-bit images a word a texel, 16-bit
 * ones four floats (v / 65535), interlaced or not. */
#include <png.h>
#include <setjmp.h>
#include <stdlib.h>
#include <string.h>

#include "scene/texture.h"
#include "shared_layout.h"

typedef struct png_memory {
    jmp_buf jump;
    const uint8_t *bytes;
    size_t size, at;
    char message[160];
} png_memory;

static void on_error(png_structp png, png_const_charp message) {
    png_memory *m = png_get_error_ptr(png);
    snprintf(m->message, sizeof m->message, "%s", message);
    longjmp(m->jump, 1);
}

static void on_warning(png_structp png, png_const_charp message) {
    (void)png;
    (void)message;
}

static void on_read(png_structp png, png_bytep data, size_t size) {
    png_memory *m = png_get_io_ptr(png);
    if (size > m->size - m->at) png_error(png, "truncated");
    memcpy(data, m->bytes + m->at, size);
    m->at += size;
}

bool texture_decode_png(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                        char *error, size_t error_size) {
    png_memory m = {.bytes = bytes, .size = size};
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &m, on_error, on_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile pixels = NULL;
    png_bytep *volatile rows = NULL;
    if (!png || !info) {
        png_destroy_read_struct(&png, &info, NULL);
        snprintf(error, error_size, "out of memory");
        return false;
    }
    if (setjmp(m.jump)) {
        png_destroy_read_struct(&png, &info, NULL);
        free(pixels);
        free(rows);
        if (m.message[0])
            snprintf(error, error_size, "corrupt or truncated PNG (libpng: %s)", m.message);
        return false;
    }
    png_set_read_fn(png, &m, on_read);
    png_set_user_limits(png, TEXTURE_MAX_SIDE, TEXTURE_MAX_SIDE);
    /* A decompression bomb's chunks are capped too (zTXt, iCCP), not only its pixels. */
    png_set_chunk_malloc_max(png, 64u * 1024u * 1024u);
    png_read_info(png, info);
    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    png_set_expand(png);
    png_set_gray_to_rgb(png);
    int depth = png_get_bit_depth(png, info);
    png_set_filler(png, depth == 16 ? 0xffff : 0xff, PNG_FILLER_AFTER);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    bool wide = png_get_bit_depth(png, info) == 16;
    size_t row_bytes = png_get_rowbytes(png, info);
    if (png_get_channels(png, info) != 4 || row_bytes != (size_t)w * (wide ? 8 : 4)) {
        snprintf(error, error_size, "PNG of a layout libpng did not expand to RGBA");
        m.message[0] = '\0';
        longjmp(m.jump, 1);
    }
    if (!texture_image_alloc(out, w, h, wide ? TZ_TEXEL_RGBA32F : TZ_TEXEL_RGBA8, budget_bytes,
                             error, error_size)) {
        m.message[0] = '\0';
        longjmp(m.jump, 1);
    }
    pixels = malloc(row_bytes * h);
    rows = malloc(h * sizeof *rows);
    if (!pixels || !rows) {
        snprintf(error, error_size, "out of memory");
        m.message[0] = '\0';
        longjmp(m.jump, 1);
    }
    for (png_uint_32 y = 0; y < h; y++) rows[y] = pixels + y * row_bytes;
    png_read_image(png, rows);
    png_read_end(png, NULL);
    png_destroy_read_struct(&png, &info, NULL);
    size_t texels = (size_t)w * h;
    for (size_t k = 0; k < texels; k++) {
        const uint8_t *p = pixels + k * (wide ? 8 : 4);
        if (!wide) {
            out->words[k] =
                (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
            continue;
        }
        for (int c = 0; c < 4; c++) {
            float v = (float)(((unsigned)p[2 * c] << 8 | p[2 * c + 1]) / 65535.0);
            memcpy(&out->words[4 * k + (size_t)c], &v, sizeof v);
        }
    }
    free(pixels);
    free(rows);
    return true;
}
