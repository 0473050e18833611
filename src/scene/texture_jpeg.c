/* texture_jpeg.c: a JPEG image's bytes as texels through libjpeg-turbo: grey, RGB and YCbCr
 * images become 8-bit RGBA words (alpha 255); CMYK is refused. */
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>

/* clang-format off: jpeglib.h needs FILE and size_t declared before it */
#include <jpeglib.h>
/* clang-format on */

#include "scene/texture.h"
#include "shared_layout.h"

typedef struct jpeg_failure {
    struct jpeg_error_mgr mgr;
    jmp_buf jump;
} jpeg_failure;

static void on_error(j_common_ptr cinfo) { longjmp(((jpeg_failure *)cinfo->err)->jump, 1); }

static void on_message(j_common_ptr cinfo, int level) {
    (void)cinfo;
    (void)level; /* libjpeg's warnings (corrupt data it recovered from) are not ours to print */
}

bool texture_decode_jpeg(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                         char *error, size_t error_size) {
    struct jpeg_decompress_struct cinfo;
    jpeg_failure failure;
    cinfo.err = jpeg_std_error(&failure.mgr);
    failure.mgr.error_exit = on_error;
    failure.mgr.emit_message = on_message;
    volatile bool described = false;
    if (setjmp(failure.jump)) {
        if (!described) {
            char message[JMSG_LENGTH_MAX];
            failure.mgr.format_message((j_common_ptr)&cinfo, message);
            snprintf(error, error_size, "corrupt or truncated JPEG (libjpeg: %s)", message);
        }
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    jpeg_create_decompress(&cinfo);
    jpeg_mem_src(&cinfo, bytes, (unsigned long)size);
    jpeg_read_header(&cinfo, TRUE);
    if (cinfo.num_components != 1 && cinfo.num_components != 3) {
        snprintf(error, error_size, "JPEG of %d components: grey and colour (3) are read",
                 cinfo.num_components);
        described = true;
        longjmp(failure.jump, 1);
    }
    cinfo.out_color_space = JCS_EXT_RGBA;
    if (!texture_image_alloc(out, cinfo.image_width, cinfo.image_height, TZ_TEXEL_RGBA8,
                             budget_bytes, error, error_size)) {
        described = true;
        longjmp(failure.jump, 1);
    }
    jpeg_start_decompress(&cinfo);
    while (cinfo.output_scanline < cinfo.output_height) {
        /* A word a texel, R in its low byte: JCS_EXT_RGBA's byte order on any host. */
        JSAMPROW row = (JSAMPROW)(out->words + (size_t)cinfo.output_scanline * out->width);
        jpeg_read_scanlines(&cinfo, &row, 1);
    }
    jpeg_finish_decompress(&cinfo);
    /* libjpeg fills what a truncated file lacks with grey and warns: a texture must not be. */
    if (failure.mgr.num_warnings > 0) {
        char message[JMSG_LENGTH_MAX];
        failure.mgr.format_message((j_common_ptr)&cinfo, message);
        snprintf(error, error_size, "corrupt or truncated JPEG (libjpeg: %s)", message);
        jpeg_destroy_decompress(&cinfo);
        return false;
    }
    jpeg_destroy_decompress(&cinfo);
    return true;
}
