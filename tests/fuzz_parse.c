/* fuzz_parse.c: libFuzzer target for the scene parser; any crash, leak, hang or UB is a bug.
 * Its corpus (.ci/run): every .scene file of scenes/ and of tests/corpus/ (triangles, quads). */
#include <stddef.h>
#include <stdint.h>

#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    scene s;
    scene_error err;
    if (scene_parse_string((const char *)data, size, "fuzz", &s, &err)) scene_free(&s);
    return 0;
}
