/* scene_mesh.h: the steps of the mesh directive (scene_mesh.c) that the placement of a file's
 * shared meshes (scene_mesh_nodes.c) takes again for each of them. */
#ifndef TRAZADOR_SCENE_MESH_H
#define TRAZADOR_SCENE_MESH_H

#include <stdbool.h>
#include <stddef.h>

#include "scene/directives.h"
#include "scene/mesh_load.h"
#include "scene/parser.h"

/* The mesh's faces transformed in place, the degenerate ones dropped (counted, the first
 * described) and the kept ones first, in order; on every core when there are many. False with
 * *outside the first face that leaves the coordinate range. */
bool mesh_faces_transform(mesh *me, const mesh_transform *xf, bool smooth, size_t *kept,
                          size_t *dropped, char *first_drop, size_t first_drop_size,
                          size_t *outside);
/* Appends the mesh's first `kept` faces, of material *given or else each of its file's, a file
 * material added to the scene's when a face first takes it; *emits says whether one emits.
 * False (reported) out of memory. */
bool mesh_faces_add(parser *p, const mesh *me, size_t kept, const material *given, const char *path,
                    int col, bool *emits);
/* Checks the mesh's glass (the line's material m or the file's refractive ones) part by part,
 * winding closed parts outward for the scale; *glass: whether there is any. False (reported)
 * when a part is open or out of memory. */
bool mesh_faces_check_glass(parser *p, mesh *me, const material_spec *m, const double scale[3],
                            const char *path, int col, bool *glass);
/* Warns, once a scene as for spheres (tiny_warned), when glass mesh `path` has a bounding box
 * lo..hi whose smallest half-extent is under SCENE_TINY_OFFSETS ray offsets at its largest
 * |coordinate|. */
void mesh_warn_tiny_glass(parser *p, vec3 lo, vec3 hi, const char *path, int col);
/* Flattens the instances of me's shared meshes that cannot stay instances under the line's
 * material (m, given) and mirror: those of a mesh that emits (instances are not lights) and the
 * mirrored ones of a glass mesh (its faces are wound outward once, in its own space). False
 * (reported at col) out of memory. */
bool mesh_nodes_choose(parser *p, mesh *me, const material_spec *m, const material *given,
                       bool mirror, int col);
/* What a line placed: its faces kept once and placed (instances count their model's faces
 * each), its instances and the shared meshes they place. */
typedef struct mesh_nodes_count {
    size_t unique, placed;
    int instances, shared_meshes;
} mesh_nodes_count;
/* Places me's shared meshes: each one a model of its faces (checked, untransformed) and an
 * instance per node that places it, moved by the node's and the line's transform xf; a node
 * whose transform does not invert is skipped with a warning. lo..hi grows by their boxes, and
 * count by what they add. False (reported at col). */
bool mesh_nodes_place(parser *p, mesh *me, const material_spec *m, const material *given,
                      bool smooth, const mesh_transform *xf, const char *path, int col,
                      double lo[3], double hi[3], mesh_nodes_count *count);

#endif
