/* mesh_cache.h: the models a parse has loaded, kept as the loader gave them, so that `mesh`
 * lines naming one file import it once (mesh_cache.c). */
#ifndef TRAZADOR_MESH_CACHE_H
#define TRAZADOR_MESH_CACHE_H

#include <stdbool.h>
#include <stddef.h>

#include "scene/mesh_load.h"

typedef struct mesh_cache mesh_cache;

/* mesh_load's result for path and smooth into *out, a copy of the model an earlier call of the
 * same parse loaded where it is the same file (device, inode, size and modification time) with
 * the same smooth; *cache is created on first use (NULL before). False as mesh_load. */
bool mesh_cache_load(mesh_cache **cache, const char *path, bool smooth, mesh *out, char *error,
                     size_t error_size);
/* Gives the cache (created when *cache is NULL) the model *model loaded from path with smooth,
 * whatever its size, for the next mesh_cache_load of that file to take as it is (not a copy);
 * *model is then empty. False out of memory (*model kept). */
bool mesh_cache_adopt(mesh_cache **cache, const char *path, bool smooth, mesh *model);
/* Releases the cache and its models; safe on NULL. */
void mesh_cache_free(mesh_cache *cache);

#endif
