/* mesh_gltf.h: what a glTF file names that assimp does not read (mesh_gltf.c), for the loader's
 * child process (mesh_load.c) to say what is lost. */
#ifndef TRAZADOR_MESH_GLTF_H
#define TRAZADOR_MESH_GLTF_H

#include <stdbool.h>

/* Whether the JSON of glTF file path (a .gltf file, or a GLB's JSON chunk) holds `text` (at most
 * 128 bytes), such as an extension's name; false for other files and on any read error. */
bool mesh_gltf_names(const char *path, const char *text);

#endif
