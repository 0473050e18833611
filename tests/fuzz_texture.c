/* fuzz_texture.c: libFuzzer target of the texture decoders (src/scene/texture.h): any bytes, as a
 * file or a model's embedded image would give them, decode or are refused with a reason, never
 * a crash, a leak or a read past the bytes; a decoded image has the words its size says.
 * Seeds: tests/corpus_texture/. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/texture.h"
#include "shared_layout.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    texture_image image;
    char error[320] = "";
    /* A budget of 64 MB keeps each input fast while the side limit is still reached. */
    if (texture_decode(data, size, 64u * 1024u * 1024u, &image, error, sizeof error)) {
        size_t per = image.format == TZ_TEXEL_RGBA8 ? 1 : 4;
        if (image.word_count != (size_t)image.width * image.height * per) abort();
        texture_image_free(&image);
    } else if (!error[0]) {
        abort(); /* every refusal says why */
    }
    return 0;
}
