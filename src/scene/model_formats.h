/* model_formats.h: the model formats this assimp reads, as assimp itself lists them (`trazador
 * formats`), and whether a file that does not parse as a scene is a model file (render's message
 * in place of the parser's byte or directive error). */
#ifndef TRAZADOR_MODEL_FORMATS_H
#define TRAZADOR_MODEL_FORMATS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

/* What to do with a Blender file: assimp 5.2 reads Blender 2.7x and older only, and a newer one
 * fails with assimp's internal text ("Did not find a field named `no`..."). */
#define MODEL_BLENDER_ADVICE                                                                       \
    "assimp reads no Blender file newer than 2.7x: export it from Blender as glTF (File > Export " \
    "> glTF 2.0, a .glb) and load that"

/* Prints the formats assimp reads to out, one a line: its extensions, then its name; false
 * (logged) when assimp cannot be opened. */
bool model_formats_print(FILE *out);
/* Whether the file at path, which failed to parse as a scene at line error_line, is a model file:
 * the error is on its first line that is neither blank nor a comment, and its first bytes are a
 * model format's (glTF binary, PLY, Blender, FBX, COLLADA, STL) or its extension one that assimp
 * reads; *kind then names the format ("glTF binary", "OBJ"). False otherwise, and for a `.scene`
 * file. */
bool model_file_kind(const char *path, int error_line, char *kind, size_t size);

#endif
