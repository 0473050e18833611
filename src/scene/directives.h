/* directives.h: what the directive files share (not an API): each directive's parser, for the
 * table in scene_directives.c; the key ranges and the material keys every shape takes; the
 * material words and the surface read from a shape's line (scene_material.c); the face checks
 * and appends of the triangle directives, which mesh lines reuse (scene_primitives.c); and
 * growing the scene's arrays (scene_directives.c). */
#ifndef TRAZADOR_SCENE_DIRECTIVES_H
#define TRAZADOR_SCENE_DIRECTIVES_H

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stddef.h>

#include "scene/parser.h"

#define NO_RANGE -FLT_MAX, FLT_MAX, false
#define UNIT_RANGE 0.0, 1.0, false
/* Positions and radii: the renderer squares their differences in float, which overflows past
 * about 1.8e19 (a sphere of radius 2e19 vanished). */
#define COORD_RANGE -1e18, 1e18, false

/* The keys of a surface's material, the same for every shape: each shape's key table holds its
 * own keys, then these, so that one material table and one reader serve spheres and faces. */
enum {
    MAT_COLOR,
    MAT_KS,
    MAT_ALPHA,
    MAT_IOR,
    MAT_EMISSION,
    MAT_ROUGHNESS,
    MAT_METALLIC,
    MAT_COLOR_MAP, /* the texture keys (scene_texture.c), MAT_COLOR_MAP to MAT_WRAP */
    MAT_EMISSION_MAP,
    MAT_NORMAL_MAP,
    MAT_NORMAL_SCALE,
    MAT_ALPHA_MAP,
    MAT_ALPHA_CUTOFF,
    MAT_METALLIC_ROUGHNESS_MAP,
    MAT_WRAP,
    MAT_KEY_COUNT
};
/* clang-format off */
#define MATERIAL_KEY_SPECS                                          \
    {"color", "r g b", VALUE_NUMBER, UNIT_RANGE},                   \
    {"ks", NULL, VALUE_NUMBER, UNIT_RANGE},                         \
    {"alpha", NULL, VALUE_NUMBER, 0.0, FLT_MAX, false},             \
    {"ior", NULL, VALUE_NUMBER, 1.0, FLT_MAX, false},               \
    {"emission", "r g b", VALUE_NUMBER, 0.0, FLT_MAX, false},       \
    {"roughness", NULL, VALUE_NUMBER, UNIT_RANGE},                  \
    {"metallic", NULL, VALUE_NUMBER, UNIT_RANGE},                   \
    {"color_map", NULL, VALUE_PATH, NO_RANGE},                      \
    {"emission_map", NULL, VALUE_PATH, NO_RANGE},                   \
    {"normal_map", NULL, VALUE_PATH, NO_RANGE},                     \
    {"normal_scale", NULL, VALUE_NUMBER, 0.0, 1e6, false},          \
    {"alpha_map", NULL, VALUE_PATH, NO_RANGE},                      \
    {"alpha_cutoff", NULL, VALUE_NUMBER, UNIT_RANGE},               \
    {"metallic_roughness_map", NULL, VALUE_PATH, NO_RANGE},         \
    {"wrap", "repeat clamp mirror", VALUE_WORD, NO_RANGE}
/* clang-format on */
/* The texture keys, which every material takes. */
#define MATERIAL_TEXTURE_KEYS (LOW_BITS(MAT_KEY_COUNT) & ~LOW_BITS(MAT_COLOR_MAP))

/* A shape directive (sphere, triangle, quad, mesh) as the shared readers (shape_read,
 * shape_material_of) see it. */
typedef struct shape_spec {
    const char *word;
    const key_spec *keys;
    int key_count;
    int material_first; /* index in keys of the first material key */
    unsigned own_keys;  /* bits of keys the shape takes whatever its material */
    unsigned required;
    bool glass; /* takes refractive: only a closed surface bounds a medium */
} shape_spec;

#define LOW_BITS(n) ((1u << (n)) - 1u)

typedef struct material_spec {
    const char *word;
    material_kind kind;
    unsigned keys; /* bits of the material keys (MAT_*) this material accepts */
    float default_color;
    bool alias; /* one of the seed's Spanish names */
} material_spec;

/* Gives material m the texture maps of a shape's line (its keys from kv's key first on: the
 * MAT_* texture keys), each image loaded once a scene (scene_texture.c). False (reported) on an
 * image that cannot be read; false, silently, in a chunk parsed ahead (the line is then parsed in
 * order, where files may be read). */
bool material_maps_read(parser *p, int first, const key_values *kv, material *m);
/* The slot of image file path (loaded once a scene) read with flags and param and transform;
 * *slot its index + 1. False (reported at col) when the image cannot be read. */
bool texture_slot_of_file(parser *p, int col, const char *path, uint32_t flags, float param,
                          const float transform[6], uint32_t *slot);
/* The slot of an image decoded from bytes in memory (a model's embedded one), named name for
 * messages and keyed by it; as texture_slot_of_file. */
bool texture_slot_of_bytes(parser *p, int col, const char *name, const uint8_t *bytes, size_t size,
                           uint32_t flags, float param, const float transform[6], uint32_t *slot);

/* Double-precision vectors: the face checks must not overflow or cancel where float would. */
typedef struct dvec3 {
    double x, y, z;
} dvec3;
static inline dvec3 d3_sub(vec3 a, vec3 b) {
    return (dvec3){(double)a.x - b.x, (double)a.y - b.y, (double)a.z - b.z};
}
static inline dvec3 d3_cross(dvec3 a, dvec3 b) {
    return (dvec3){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
static inline double d3_dot(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double d3_length(dvec3 a) { return sqrt(d3_dot(a, a)); }

/* A model's transform on a mesh or `camera file` line: scale, then rotation about a unit axis,
 * then translation (mesh_transform.c). */
typedef struct mesh_transform {
    double scale[3], r[3][3], translate[3];
} mesh_transform;
/* The transform of scale (per axis), rotate (axis and degrees, right-handed) and translate. */
mesh_transform mesh_transform_make(const double scale[3], const double rotate[4],
                                   const double translate[3]);
/* A point moved by the transform; false when it leaves the coordinate range (1e18). */
bool mesh_transform_point(const mesh_transform *m, vec3 v, vec3 *out);
/* A direction (a camera's) by the transform's scale and rotation, in double rounded once. */
vec3 mesh_transform_direction(const mesh_transform *m, vec3 v);
/* A normal by the inverse transpose, R S^-1, renormalized; false when it is zero. */
bool mesh_transform_normal(const mesh_transform *m, vec3 n, vec3 *out);
/* The transform as affine rows [R S | t]. */
void mesh_transform_rows(const mesh_transform *m, double out[3][4]);
/* Instances (scene_instance.c): the models the parse's mesh lines loaded, by their key (path,
 * smooth and the line's material, NULL for the file's own). */
typedef struct mesh_placed mesh_placed;
/* The model an earlier line loaded with this key, NULL when none did. */
mesh_placed *mesh_placed_find(parser *p, const char *path, bool smooth, const material *given);
/* Keeps the key of a mesh line loaded as faces, scene.triangles[first, end) and its normals from
 * normals_first, moved by xf, unless an earlier line has it; instanceable: whether later lines
 * may share its faces. False (reported) out of memory. */
bool mesh_placed_note(parser *p, const char *path, bool smooth, const material *given,
                      bool instanceable, int first, int normals_first, const mesh_transform *xf);
/* Whether later lines may place r's model as instances. */
bool mesh_placed_instanceable(const mesh_placed *r);
/* Whether r's model is made (a second line placed it). */
bool mesh_placed_has_model(const mesh_placed *r);
/* Moves scene.triangles[first, end), a line's faces loaded untransformed, into a new model of
 * r and places it where r's first line was; false (reported at col) out of memory or when
 * instance_add refuses. */
bool mesh_placed_make_model(parser *p, mesh_placed *r, int first, int col);
/* Places r's model by xf; false (reported at col) when xf is singular or the instances pass
 * their limit (SCENE_MAX_INSTANCE_KEYS). */
bool mesh_placed_instance(parser *p, mesh_placed *r, const mesh_transform *xf, int col);
/* Whether the 3 x 3 part of rows inverts in single precision: its determinant is not lost to
 * rounding against the product of its rows' lengths, and the inverse's entries (each a 2 x 2
 * cofactor over the determinant, at most 2 largest^2 / |det|) are finite floats. */
bool scene_rows_invertible(double rows[3][4]);
/* Grows the box wlo..whi by the box lo..hi moved by rows, corner by corner. */
void scene_box_moved(const double lo[3], const double hi[3], double rows[3][4], double wlo[3],
                     double whi[3]);
/* Moves scene.triangles[first, end), faces loaded untransformed, into a new model: its index in
 * *model, its box in lo..hi; false (reported at col) out of memory. */
bool scene_model_take(parser *p, int first, int col, int *model, double lo[3], double hi[3]);
/* Appends an instance of model `model` with rows to_world; false (reported at col, naming path)
 * when the transform is singular or past the instances' limit (SCENE_MAX_INSTANCE_KEYS). */
bool scene_instance_add(parser *p, int model, double to_world[3][4], int col, const char *path);
/* Takes out the faces (and their normals) of the first lines whose models became instances;
 * false (reported) out of memory. */
bool mesh_placed_finish(parser *p);
/* Releases the keys; safe when there are none. */
void mesh_placed_free(parser *p);
struct mesh;
/* With `lights on`, the model's lights moved by the line's transform xf into the scene's
 * lights (mesh_lights.c); the ones it cannot take warned of by name. False (reported at col) on
 * a light of negative or non-finite intensity, a bad cone or direction, past the coordinate
 * range or the lights' limit. */
bool mesh_lights_add(parser *p, const struct mesh *me, const mesh_transform *xf, const char *path,
                     int col);
/* A `camera file PATH` line (scene_camera_file.c), the camera directive's word checked. */
bool directive_camera_file(parser *p);

/* The directives' parsers (scene_setup.c, scene_lights.c, scene_primitives.c, scene_mesh.c): each
 * parses the tokenized line p->tokens into p->s; false (reported) on any error. */
bool directive_camera(parser *p);
bool directive_plane(parser *p);
bool directive_light(parser *p);
bool directive_sun(parser *p);
bool directive_background(parser *p);
bool directive_environment(parser *p);
bool directive_render(parser *p);
bool directive_sphere(parser *p);
bool directive_triangle(parser *p);
bool directive_quad(parser *p);
bool directive_mesh(parser *p);

/* The path token t names (bare or quoted: parser_path): absolute as given, else relative to the
 * scene file's folder (the working folder for text that is not a file: standard input,
 * strings); false (reported, `what` naming the directive) when it is empty or does not fit. */
bool directive_file_path(parser *p, const token *t, const char *what, char *out, size_t size);
/* Appends to a message, dropping what does not fit. */
void directive_append(char *message, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
/* Grows *array (count items of *capacity) by doubling, for room for `adding` more items; false
 * (reported at the directive word) past max or out of memory. */
bool directive_grow(parser *p, void **array, size_t *capacity, int count, int adding, int max,
                    size_t item, const char *what);

/* The material the token names, aliases included; NULL for none. */
const material_spec *material_lookup(const token *word);
/* The materials the shape takes, for messages, joined by sep; aliases after ", or " if asked. */
void material_list(char *out, size_t size, const shape_spec *shape, const char *sep, bool aliases);
/* Reads a shape's line: its material word (token 1), then its keys and the material's into kv;
 * false (reported) on a bad material or a bad or missing key. */
bool shape_read(parser *p, const shape_spec *shape, const material_spec **material, key_values *kv);
/* The material of a shape's line, defaults filled in; records the line's emission for report mode.
 */
material shape_material_of(parser *p, const shape_spec *shape, const material_spec *m,
                           const key_values *kv);

/* Records, if it is the first, a Phong material (colour, ks) that reflects more light than it
 * receives (max(colour) + ks above 1) at column col of the line, `what` describing it for the
 * path-mode warning (scene_parse.c). */
void phong_note_bright(parser *p, int col, vec3 color, float ks, const char *what);

/* True, with the reason in why, unless face a b c is one the renderer can normalize in single
 * precision; `what` names the face in the reason. */
bool face_problem(vec3 a, vec3 b, vec3 c, const char *what, char *why, size_t size);
/* Room for `adding` triangles; false (reported) past the limits or out of memory. */
bool faces_reserve(parser *p, int adding);
/* Appends one face of material `material` and shading normals `normals` (TRIANGLE_FLAT: none)
 * to the scene's triangles (room reserved by faces_reserve). */
void face_add(parser *p, vec3 a, vec3 b, vec3 c, uint32_t material, uint32_t normals);
/* The index in the scene's materials of m (a sphere's or a face's): the last one's when it is
 * the same, else a new one; false (reported) out of memory. */
bool material_add(parser *p, const material *m, uint32_t *index);
/* Room for `adding` sets of shading normals; false (reported) past the limits or out of memory. */
bool normals_reserve(parser *p, int adding);
/* Appends shading normals n (room reserved by normals_reserve); returns their index. */
uint32_t normals_add(parser *p, const vec3 n[3]);

#endif
