/* mesh_import.h: the parts of a model's import in mesh_load.c's child process that live in files
 * of their own: the faces and embedded images gathered (mesh_gather.c, whose corner readers
 * mesh_nodes.c shares) and the file system assimp reads through (mesh_files.c). */
#ifndef TRAZADOR_MESH_IMPORT_H
#define TRAZADOR_MESH_IMPORT_H

#include <stdbool.h>
#include <stddef.h>

#include "scene/mesh_load.h"

struct aiScene;
struct aiMesh;
struct aiFileIO;
struct aiFile;

/* The triangle faces of sc (imported with PreTransformVertices) into out->faces (room for all
 * of them), in order: on every core when there are many and every triangle mesh holds triangles
 * alone; false (error) at the first non-finite corner, the one a single pass would meet first. */
bool mesh_gather_faces(const struct aiScene *sc, mesh *out, char *error, size_t error_size);
/* The material index of mesh me's faces, -1 where sc has no such material. */
int mesh_face_material(const struct aiScene *sc, const struct aiMesh *me);
/* The first UV channel of me's vertex index into uv, (0, 0) where it has none or it is not
 * finite. */
void mesh_corner_uv(const struct aiMesh *me, unsigned index, float uv[2]);
/* The compressed bytes of the embedded images ("*N") the materials name into out->embedded, each
 * material's path renamed to its index there; an image assimp holds decoded (its height not 0)
 * or past the limits is named unsupported and its maps dropped. False out of memory. */
bool mesh_gather_embedded(const struct aiScene *sc, mesh *out, char *error, size_t error_size);
/* The import's file system's open and close (aiFileIO; its UserData the mesh whose inputs record
 * each file opened). */
struct aiFile *mesh_file_open(struct aiFileIO *io, const char *path, const char *mode);
void mesh_file_close(struct aiFileIO *io, struct aiFile *f);

#endif
