/* fuzz_mesh.c: libFuzzer target for the mesh loader's input path: an input is a model file whose
 * first byte picks its format (the extension assimp goes by) and the mesh line's options, loaded
 * through a scene's `mesh` line as a user's file is: assimp in its child process, the faces and
 * materials received, transformed, checked and turned into triangles, its cameras and lights
 * (`camera file`, `lights on`) too. A crash, leak, hang or UB
 * in trazador is a bug; assimp's own crashes and hangs end in its child as an error message.
 * Its corpus (.ci/run): tests/corpus_mesh/, small models behind their format byte. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "scene/scene.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The formats the first byte picks (its low three bits), as assimp knows them by extension. */
static const char *const formats[] = {".obj",  ".ply", ".stl", ".off",
                                      ".gltf", ".glb", ".dae", ".3ds"};

static char folder[64];

int LLVMFuzzerInitialize(int *argc, char ***argv) {
    (void)argc, (void)argv;
    /* An input can load its file twice (`camera file` and `mesh`), each import that hangs ending
     * at the child's limit of processor time: one second each keeps a hang's input well inside
     * libFuzzer's -timeout of 10 s on the wall clock. */
    setenv("TRAZADOR_MESH_SECONDS", "1", 1);
    snprintf(folder, sizeof folder, "/tmp/fuzz_mesh.XXXXXX");
    if (!mkdtemp(folder)) abort();
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    if (size < 1) return 0;
    uint8_t pick = data[0];
    char path[128];
    snprintf(path, sizeof path, "%s/model%s", folder, formats[pick & 7u]);
    FILE *f = fopen(path, "wb");
    if (!f) abort();
    if (size > 1 && fwrite(data + 1, 1, size - 1, f) != size - 1) abort();
    if (fclose(f) != 0) abort();
    /* Bit 3: the file's own materials or one of trazador's; bit 4: smooth; bit 5: a transform;
     * bit 6: the file's lights (`lights on`); bit 7: the file's camera (`camera file`). */
    const char *transform = pick & 32u ? "scale 2 0.5 1 rotate 1 1 0 30 translate 0 1 2" : "";
    char text[1024], camera[512];
    if (pick & 128u)
        snprintf(camera, sizeof camera, "camera file %s %s", path, transform);
    else
        snprintf(camera, sizeof camera, "camera position 0 0 -5");
    int n = snprintf(text, sizeof text,
                     "%s\nplane width 4 height 3 pixel 0.05\n"
                     "render mode path\nmesh %s file %s smooth %s lights %s %s\n",
                     camera, pick & 8u ? "lambertian" : "", path, pick & 16u ? "on" : "off",
                     pick & 64u ? "on" : "off", transform);
    scene s;
    scene_error err;
    if (scene_parse_string(text, (size_t)n, "fuzz.scene", &s, &err)) scene_free(&s);
    unlink(path);
    return 0;
}
