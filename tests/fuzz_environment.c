/* fuzz_environment.c: libFuzzer target for the environment map's reader: an input is the bytes
 * of a map file, loaded through a scene's `environment file` line as a user's map is: the
 * OpenEXR reader (image/image_hdr.c over OpenEXRCore), then the map's checks (2:1, finite and
 * >= 0, the intensity) and its rotation. A crash, leak, hang or UB is a bug. Its corpus
 * (.ci/run): tests/corpus_environment/, small maps the tests' writer made. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene/scene.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char folder[64];

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    (void)argc, (void)argv;
    snprintf(folder, sizeof folder, "/tmp/fuzz_environment.XXXXXX");
    if (!mkdtemp(folder)) abort();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char path[128];
    snprintf(path, sizeof path, "%s/map.exr", folder);
    FILE *f = fopen(path, "wb");
    if (!f) abort();
    if (size > 0 && fwrite(data, 1, size, f) != size) abort();
    if (fclose(f) != 0) abort();
    char text[512];
    int n = snprintf(text, sizeof text,
                     "camera position 0 0 -5\nplane width 4 height 3 pixel 0.05\n"
                     "environment file %s rotate 1 2 3 40 intensity 1e30\nrender mode path\n",
                     path);
    scene s;
    scene_error err;
    if (scene_parse_string(text, (size_t)n, "fuzz.scene", &s, &err)) scene_free(&s);
    unlink(path);
    return 0;
}
