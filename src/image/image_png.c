/* image_png.c: PNG through libpng: 8-bit RGB out at a fast zlib level, and in every bit depth and
 * color type the diff can compare, with libpng checking each chunk's CRC. */
#include "image/image_png.h"

#include <errno.h>
#include <math.h>
#include <png.h>
#include <setjmp.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

#include "util/big_memory.h"
#include "util/log.h"

/* What libpng's error and warning handlers keep for the caller. */
typedef struct png_state {
    jmp_buf jump;
    char message[200];
    int err;     /* errno of a failed write, 0 for none */
    bool logged; /* the failure was logged before the jump */
} png_state;

static void on_png_error(png_structp png, png_const_charp message) {
    png_state *state = png_get_error_ptr(png);
    snprintf(state->message, sizeof state->message, "%s", message);
    longjmp(state->jump, 1);
}

/* Warnings (an ancillary chunk with a bad CRC, which libpng then skips) are details. */
static void on_png_warning(png_structp png, png_const_charp message) {
    (void)png;
    log_debug("libpng: %s", message);
}

static void on_png_write(png_structp png, png_bytep data, size_t size) {
    png_state *state = png_get_error_ptr(png);
    FILE *fp = png_get_io_ptr(png);
    if (fwrite(data, 1, size, fp) != size) {
        state->err = errno ? errno : EIO;
        png_error(png, "write failed");
    }
}

static void on_png_flush(png_structp png) { (void)png; }

int image_png_write(FILE *fp, const image *img, tonemap tm) {
    png_state state = {0};
    png_structp png =
        png_create_write_struct(PNG_LIBPNG_VER_STRING, &state, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile row = malloc((size_t)img->width * 3);
    if (!png || !info || !row) {
        png_destroy_write_struct(&png, &info);
        free(row);
        return ENOMEM;
    }
    if (setjmp(state.jump)) {
        png_destroy_write_struct(&png, &info);
        free(row);
        if (!state.err) log_error("libpng: %s", state.message);
        return state.err ? state.err : EIO;
    }
    png_set_write_fn(png, fp, on_png_write, on_png_flush);
    /* Run-length matches after the Sub filter: as small as zlib level 1-3 on renders, two to
     * three times faster (docs/PERF.md, "Image output"). */
    png_set_compression_level(png, IMAGE_PNG_LEVEL);
    png_set_compression_strategy(png, Z_RLE);
    png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
    png_set_IHDR(png, info, (png_uint_32)img->width, (png_uint_32)img->height, 8,
                 PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE,
                 PNG_FILTER_TYPE_BASE);
    png_set_sRGB(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    png_write_info(png, info);
    tonemap_table table;
    tonemap_table_init(&table, tm);
    size_t row_values = (size_t)img->width * 3;
    for (int y = 0; y < img->height; y++) {
        const float *src = img->rgb + (size_t)y * row_values;
        for (size_t i = 0; i < row_values; i++) row[i] = tonemap_table_channel(&table, src[i]);
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    free(row);
    return 0;
}

/* Linear values of every code of `bits` bits, decoded with tm. */
static float *decode_table(int bits, tonemap tm) {
    size_t count = (size_t)1 << bits;
    float *lut = malloc(count * sizeof *lut);
    if (!lut) return NULL;
    if (bits == 8) {
        for (size_t i = 0; i < count; i++) lut[i] = tonemap_decode((uint8_t)i, tm);
        return lut;
    }
    for (size_t i = 0; i < count; i++) {
        double c = (double)i / (double)(count - 1);
        if (tm == TONEMAP_SRGB) c = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
        lut[i] = (float)c;
    }
    return lut;
}

/* Sample k of a row of 8- or 16-bit (big-endian) samples. */
static unsigned sample_at(const uint8_t *row, size_t k, bool wide) {
    return wide ? (unsigned)row[2 * k] << 8 | row[2 * k + 1] : row[k];
}

bool image_png_read(FILE *fp, const char *path, image *out, tonemap tm) {
    png_state state = {0};
    png_structp png =
        png_create_read_struct(PNG_LIBPNG_VER_STRING, &state, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    uint8_t *volatile pixels = NULL;
    png_bytep *volatile rows = NULL;
    float *volatile lut = NULL;
    if (!png || !info) {
        png_destroy_read_struct(&png, &info, NULL);
        log_error("%s: %s", path, strerror(ENOMEM));
        return false;
    }
    if (setjmp(state.jump)) {
        png_destroy_read_struct(&png, &info, NULL);
        free(pixels);
        free(rows);
        free(lut);
        if (state.logged) return false;
        if (ferror(fp))
            log_error("%s: %s", path, strerror(errno));
        else
            log_error("%s: not a PNG, or corrupt or truncated (libpng: %s)", path, state.message);
        return false;
    }
    png_init_io(png, fp);
    png_set_user_limits(png, IMAGE_MAX_DIM, IMAGE_MAX_DIM);
    png_read_info(png, info);
    png_uint_32 w = png_get_image_width(png, info), h = png_get_image_height(png, info);
    /* Every color type becomes RGB or RGBA of 8 or 16 bits; tRNS becomes alpha. */
    png_set_expand(png);
    png_set_gray_to_rgb(png);
    png_set_interlace_handling(png);
    png_read_update_info(png, info);
    int bits = png_get_bit_depth(png, info);
    int channels = png_get_channels(png, info);
    bool wide = bits == 16;
    size_t row_bytes = png_get_rowbytes(png, info);
    /* The whole image, since interlaced rows are filled in over seven passes. */
    pixels = big_malloc(row_bytes * h);
    rows = malloc(h * sizeof *rows);
    lut = decode_table(bits, tm);
    if (!pixels || !rows || !lut) {
        log_error("%s: %s", path, strerror(ENOMEM));
        state.logged = true;
        longjmp(state.jump, 1);
    }
    if (!image_init(out, (int)w, (int)h)) {
        state.logged = true;
        longjmp(state.jump, 1);
    }
    for (png_uint_32 y = 0; y < h; y++) rows[y] = pixels + y * row_bytes;
    png_read_image(png, rows);
    png_read_end(png, NULL);
    free(rows);
    rows = NULL;
    png_destroy_read_struct(&png, &info, NULL);
    unsigned opaque = wide ? 65535u : 255u;
    bool transparent = false;
    for (png_uint_32 y = 0; y < h && !transparent; y++) {
        const uint8_t *row = pixels + y * row_bytes;
        float *dst = out->rgb + (size_t)y * w * 3;
        for (png_uint_32 x = 0; x < w; x++) {
            for (int c = 0; c < 3; c++)
                dst[3 * x + c] = lut[sample_at(row, (size_t)x * channels + c, wide)];
            if (channels == 4 && sample_at(row, (size_t)x * 4 + 3, wide) != opaque) {
                transparent = true;
                break;
            }
        }
    }
    free(pixels);
    free(lut);
    if (transparent) {
        log_error("%s: has transparent pixels, and trazador compares opaque images only", path);
        image_free(out);
        return false;
    }
    return true;
}
