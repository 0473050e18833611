/* fuzz_texture_stub.c: the image decoders of the parser fuzzers, which refuse every image: fuzzed
 * text names arbitrary paths, which the fuzzer must not open (fuzz_texture fuzzes the decoders). */
#include <stdio.h>
#include <string.h>

#include "scene/texture.h"

bool texture_decode(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                    char *error, size_t error_size) {
    (void)bytes, (void)size, (void)budget_bytes;
    memset(out, 0, sizeof *out);
    snprintf(error, error_size, "the fuzzer decodes no images");
    return false;
}

bool texture_load_file(const char *path, size_t budget_bytes, texture_image *out, char *error,
                       size_t error_size) {
    (void)path;
    return texture_decode(NULL, 0, budget_bytes, out, error, error_size);
}

void texture_image_free(texture_image *t) { memset(t, 0, sizeof *t); }
