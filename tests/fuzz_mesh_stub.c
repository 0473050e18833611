/* fuzz_mesh_stub.c: the mesh loader of the parser fuzzer, which refuses every file: fuzzed text
 * names arbitrary paths, and the fuzzer must neither open them nor reach assimp. */
#include <stdio.h>
#include <string.h>

#include "scene/mesh_load.h"

bool mesh_load(const char *path, bool smooth, mesh *out, char *error, size_t error_size) {
    (void)path;
    (void)smooth;
    memset(out, 0, sizeof *out);
    snprintf(error, error_size, "the fuzzer loads no mesh files");
    return false;
}

mesh_glass_outcome mesh_glass_parts(mesh *m, const bool *glass, bool mirrored,
                                    mesh_open_part *open) {
    (void)m, (void)glass, (void)mirrored, (void)open;
    return MESH_GLASS_CLOSED;
}

void mesh_free(mesh *m) { memset(m, 0, sizeof *m); }
