/* mesh_load.h: a model file read through assimp (OBJ, PLY, glTF, COLLADA, ...) into faces and
 * the file's materials mapped to trazador's (scenes/README.md, `mesh`); the `mesh` directive
 * (scene_mesh.c) transforms and checks them. */
#ifndef TRAZADOR_MESH_LOAD_H
#define TRAZADOR_MESH_LOAD_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "scene/scene.h"

/* A texture a file's material names: its path as the file gives it (relative to the model's
 * folder), or "*N" for the file's embedded image N (mesh.embedded); TZ_WRAP_* of u and v and
 * TZ_SLOT_SRGB in flags. An empty path: none. */
#define MESH_MAP_PATH 200
typedef struct mesh_map {
    char path[MESH_MAP_PATH];
    uint32_t flags;
    float param;        /* the slot's parameter: an alpha map's cutoff (over glTF's factor) */
    float transform[6]; /* the UVs' affine map, texture_slot.transform's rows (glTF's
                         * KHR_texture_transform), the identity when the file gives none */
} mesh_map;

/* A material of the file as trazador renders it, its textures (MAP_*), and its name in the file
 * (for messages). */
typedef struct mesh_material {
    material_kind kind;
    vec3 color;
    float ks, alpha, ior;
    float roughness, metallic; /* pbr's */
    vec3 emission;
    mesh_map maps[MATERIAL_MAP_COUNT];
    char name[64];
} mesh_material;

/* The most bytes of embedded images a model may carry to the parser. */
#define MESH_MAX_EMBEDDED_BYTES ((size_t)256 << 20)
#define MESH_MAX_EMBEDDED 256

/* The most files of one model whose identities are kept (scene_input): a model and its MTL, or
 * a glTF and its buffers, need a few. */
#define MESH_MAX_INPUTS 16

/* One triangle of the file, node transforms applied. */
typedef struct mesh_face {
    vec3 v[3];
    vec3 n[3];      /* the file's (or generated) normals; zero when the file gives none */
    float uv[3][2]; /* the first texture coordinates (OpenGL's: v up), zero without any */
    int material;
} mesh_face;

/* A camera of the file in trazador's space (mesh_cameras.c): its node's transform applied in the
 * file's right-handed space, then z negated. */
typedef struct mesh_camera {
    char name[64];
    vec3 position, direction, up;
    double fov;    /* horizontal field of view, degrees (0: orthographic or none given) */
    double aspect; /* width over height, as the file gives it (0: none) */
    bool orthographic;
    double view_width; /* orthographic: the view's width in the file's units (2 xmag) */
} mesh_camera;

/* A light of the file in trazador's space, as mesh_camera; its colour times its intensity
 * (candela for points and spots, lux for directional lights: glTF's KHR_lights_punctual). */
typedef struct mesh_light {
    char name[64];
    char kind[16]; /* "point", "spot", "directional", "ambient", "area" or "undefined" */
    vec3 position;
    vec3 direction;      /* spots and directional lights: the way the light travels */
    double inner, outer; /* spots: the cone's half-angles, radians (glTF's, assimp's) */
    double color[3];
} mesh_light;

/* The most cameras and lights kept of a file (a scene takes SCENE_MAX_LIGHTS lights). */
#define MESH_MAX_CAMERAS 256
#define MESH_MAX_LIGHTS SCENE_MAX_LIGHTS

/* A mesh of the file that two or more nodes place (mesh_nodes.c): its faces, in the file's
 * space made left-handed and no node's transform applied, are part_faces first to first + count
 * of the faces that follow the placed ones (mesh.faces + mesh.face_count). */
typedef struct mesh_part {
    size_t first, count;
    int mesh; /* the file's mesh index, for messages */
} mesh_part;

/* A node's placement of a part: rows [A | t] that move the part's faces where the node puts
 * them in trazador's space (the node's world transform with z negated on both sides). */
typedef struct mesh_instance {
    int part;
    double rows[3][4];
    char node[64];
} mesh_instance;

/* The most node placements of shared meshes kept of a file (scene_instance.c has the scene's
 * own limit). */
#define MESH_MAX_INSTANCES (1 << 20)

typedef struct mesh {
    mesh_face *faces; /* face_count placed faces, then part_face_count of the parts */
    size_t face_count;
    size_t part_face_count;
    mesh_part *parts; /* the meshes two or more nodes place, none without such */
    int part_count;
    mesh_instance *instances;
    int instance_count;
    mesh_material *materials;
    int material_count;
    /* What the file holds that trazador cannot show ("textures (diffuse), vertex colours"),
     * empty when nothing. */
    char unsupported[384];
    /* The files the import read (the model and those it names), the first MESH_MAX_INPUTS. */
    scene_input inputs[MESH_MAX_INPUTS];
    int input_count;
    mesh_camera *cameras; /* the file's, in its order */
    int camera_count;
    mesh_light *lights;
    int light_count;
    /* The compressed bytes (PNG, JPEG, ...) of the embedded images its materials use: image k
     * is embedded[embedded_at[k]] to embedded[embedded_at[k + 1]]. */
    uint8_t *embedded;
    size_t embedded_at[MESH_MAX_EMBEDDED + 1];
    int embedded_count;
} mesh;

/* Loads path; smooth: generate normals (by angle) where the file has none. False with a message
 * (assimp's own where it failed) in error on a file that cannot be read, holds no triangles or
 * a non-finite position; *out is then empty. */
bool mesh_load(const char *path, bool smooth, mesh *out, char *error, size_t error_size);
/* A corner's position as its coordinates' bits, -0 and +0 one position: corners are the same
 * where these are (mesh_glass_parts, mesh_smooth_normals). */
static inline void mesh_corner_bits(vec3 v, uint32_t out[3]) {
    float c[3] = {v.x + 0.0f, v.y + 0.0f, v.z + 0.0f};
    memcpy(out, c, sizeof c);
}

/* A part with glass that is not closed: its first face (from 0), how many faces it has, their
 * bounding box, the material of its first glass face (-1: none), and one edge of it not shared
 * by exactly two faces running along it the opposite ways. */
typedef struct mesh_open_part {
    size_t first_face, faces;
    int material;
    vec3 lo, hi, edge[2];
} mesh_open_part;

/* What mesh_glass_parts found: every part with glass closed, one open, or no memory to look. */
typedef enum mesh_glass_outcome {
    MESH_GLASS_CLOSED,
    MESH_GLASS_OPEN,
    MESH_GLASS_NO_MEMORY
} mesh_glass_outcome;

/* Checks that each part (faces joined by the edges they share, corners compared by position)
 * holding a glass face (glass[material], the last entry, material_count, for faces without one)
 * is closed: every edge shared by exactly two faces running along it the opposite ways, so that
 * it bounds a medium. Then winds each such part outward, so that its signed volume is positive
 * once the line's transform applies (mirrored: its scale has a negative determinant). Open: the
 * part of the first glass face in an open one in *open, nothing flipped. Parts without glass may
 * be open. */
mesh_glass_outcome mesh_glass_parts(mesh *m, const bool *glass, bool mirrored,
                                    mesh_open_part *open);
/* Gives the corners that have no normal (zero) the mean normal of the faces at their position
 * that meet their own face at under max_angle_degrees; false out of memory. */
bool mesh_smooth_normals(mesh *m, float max_angle_degrees);
/* Reads sc's cameras and lights (before any post-processing, whose PreTransformVertices renames
 * them and, for glTF, applies a camera's node twice) into m; gltf: the file is glTF, whose
 * assimp 5.2.5 importer gives the camera's node translation as its position and yfov x aspect as
 * its horizontal fov. False out of memory. */
struct aiScene;
bool mesh_read_views(const struct aiScene *sc, bool gltf, mesh *m);
/* File light l's power and colour: power the largest of its colour x intensity, colour that
 * over the power (white at power 0); false when a component is negative, not finite or past the
 * float range. */
bool mesh_light_power(const mesh_light *l, float *power, vec3 *color);
/* Whether a node of sc (as imported, before any post-processing) places a mesh that another
 * placement places too: then mesh_nodes_gather reads the file rather than PreTransformVertices. */
bool mesh_nodes_shared(const struct aiScene *sc);
/* The faces of sc (post-processed without PreTransformVertices) into m: each mesh one node
 * places moved by that node's world transform, as PreTransformVertices would, then the parts,
 * the meshes several nodes place, once each with an instance per placement; false (error) out of
 * memory, on a non-finite corner or past MESH_MAX_INSTANCES. */
bool mesh_nodes_gather(const struct aiScene *sc, mesh *m, char *error, size_t error_size);
/* The determinant of rows' 3 x 3 part. */
double mesh_rows_determinant(const double rows[3][4]);
/* The inverse transpose of rows' 3 x 3 part (cofactors over the determinant), for normals. */
void mesh_rows_normal_matrix(const double rows[3][4], double out[3][3]);
/* out = a after b: the rows of b's map followed by a's. */
void mesh_rows_compose(const double a[3][4], const double b[3][4], double out[3][4]);
/* Point p moved by rows, in double. */
void mesh_rows_point(const double rows[3][4], const double p[3], double out[3]);
/* Normal n by the normal matrix nm (mesh_rows_normal_matrix), normalized where not zero. */
void mesh_rows_normal(double nm[3][3], const double n[3], double out[3]);
/* Moves the instances for which flatten[k] is true out of m: their part's faces placed by their
 * rows join the placed faces (as PreTransformVertices would place them: a mirroring node's
 * faces wound back). False out of memory (m kept). */
bool mesh_nodes_flatten(mesh *m, const bool *flatten);
/* The box of m's faces as placed: the placed ones and every instance's part moved by its rows
 * (past many, a box around it: its part's box moved); false when m has no face. */
bool mesh_bounds(const mesh *m, vec3 *lo, vec3 *hi);
/* A view of part k of m as a mesh of its own (its faces, m's materials and embedded images),
 * owning nothing: never to be freed. */
mesh mesh_part_view(const mesh *m, int k);
/* Releases a loaded mesh; safe on a zeroed one. */
void mesh_free(mesh *m);

#endif
