/* mesh_material.h: a model file's materials mapped to trazador's (mesh_material.c), for the
 * loader's child process (mesh_load.c). */
#ifndef TRAZADOR_MESH_MATERIAL_H
#define TRAZADOR_MESH_MATERIAL_H

#include <stdbool.h>
#include <stddef.h>

#include "scene/assimp_lib.h"
#include "scene/mesh_load.h"

/* Material m (number index of its file) as trazador's into *out, textures and the like it
 * cannot show named into unsupported; false with the value it refuses (a colour not finite or
 * negative, a number not finite) and the material's name in error. */
bool mesh_map_material(const assimp_lib *ai, const struct aiMaterial *m, unsigned index,
                       mesh_material *out, char *unsupported, size_t size, char *error,
                       size_t error_size);
/* Adds `what` to the comma-separated list of what a file holds that trazador cannot show, once. */
void mesh_note_unsupported(char *list, size_t size, const char *what);

#endif
