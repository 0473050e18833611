/* fuzz_image_stub.c: the HDR image reader of the parser fuzzers, which refuses every file: fuzzed
 * text names arbitrary paths, and those fuzzers must not open them (fuzz_environment reads maps).
 */
#include <stdio.h>

#include "image/image_hdr.h"

bool image_load_hdr(const char *path, image *out, char *why, size_t size) {
    (void)path;
    *out = (image){0};
    snprintf(why, size, "the fuzzer loads no images");
    return false;
}

void image_free(image *img) { *img = (image){0}; }
