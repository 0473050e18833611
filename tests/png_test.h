/* png_test.h: PNG files the tests write, through libpng (link PkgConfig::PNG). */
#ifndef TRAZADOR_PNG_TEST_H
#define TRAZADOR_PNG_TEST_H

#include <png.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

/* Writes a w x h PNG of colour type `type` (PNG_COLOR_TYPE_*) from rows of bytes, top first. */
static inline void write_png(const char *path, int w, int h, int type, const uint8_t *bytes) {
    int channels = type == PNG_COLOR_TYPE_GRAY   ? 1
                   : type == PNG_COLOR_TYPE_RGB  ? 3
                   : type == PNG_COLOR_TYPE_RGBA ? 4
                                                 : 2;
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!fp || !png || !info || setjmp(png_jmpbuf(png))) exit(1);
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, type, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < h; y++) png_write_row(png, bytes + (size_t)y * w * channels);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

#endif
