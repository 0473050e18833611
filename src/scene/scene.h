/* scene.h: struct scene, the one input of both back ends, its limits, and the parser API. */
#ifndef TRAZADOR_SCENE_H
#define TRAZADOR_SCENE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include "scene/texture.h"
#include "shared_layout.h"
#include "util/vec3.h"

#define SCENE_MAX_RESOLUTION 16384
#define SCENE_MAX_SPHERES 16777216 /* the GPU addresses spheres with 24-bit-exact floats */
/* Spheres and triangles share one primitive index (spheres first), at most this many in all. */
#define SCENE_MAX_PRIMITIVES 16777216
/* A face (triangle or quad half) whose height over its longest edge, |cross(v1 - v0, v2 - v0)|
 * over the squared longest edge (in double), is under this is refused as degenerate: the float
 * cross product of float edges is off by at most about 3.1e-7 times the squared longest edge, so
 * above this its length is within 3.1% and its direction within 1.8 degrees. */
#define SCENE_FACE_MIN_SHAPE 1e-5
/* |cross(v1 - v0, v2 - v0)| (twice the area) must lie in [MIN, MAX], so that its square, within
 * 6.3% in float (above), is a normal float: normalizing it in single precision cannot fail. */
#define SCENE_FACE_MIN_CROSS 1.5334e-19 /* sqrt(2 FLT_MIN) */
#define SCENE_FACE_MAX_CROSS 1.3043e19  /* sqrt(FLT_MAX / 2) */
/* A quad's v3 may lie at most this times its longest diagonal off the plane of v0 v1 v2. */
#define SCENE_QUAD_PLANE_TOLERANCE 1e-5
#define SCENE_MAX_LIGHTS 4096
#define SCENE_MAX_SAMPLES 1048576
#define SCENE_MAX_BOUNCES 64
#define SCENE_MAX_LIGHT_SAMPLES 16
#define SCENE_MAX_LINE 4096 /* longer lines are an error, not a slowdown */
/* Rays leaving a sphere start TZ_EPS times its largest |coordinate| (at least 1) off it: a
 * sphere whose radius is under this many offsets is shaded wrongly (a closed one renders black),
 * so it warns; so does a glass mesh whose bounding box's smallest half-extent is. */
#define SCENE_TINY_OFFSETS 2.0f
/* Camera rays start EPS scaled by the camera's distance from the origin along their path (a near
 * clip of 10 units at 1e5): a surface within this many times that of the camera warns. */
#define SCENE_NEAR_CLIP_FACTOR 10.0f
/* A sphere whose surface is within this many float spacings (at its size) of the camera warns:
 * single precision cannot place it there. */
#define SCENE_PRECISION_STEPS 4.0
/* A face whose corners reach this many times the camera's largest |coordinate| (at least 1)
 * warns: near the camera the watertight test finds its distance less exactly than the ray offset
 * there. */
#define SCENE_FACE_SPAN 131072.0
/* Warnings kept (past it, dropped): the last ones of a parse (a mesh out of view) still fit beside
 * a mesh's own two (what it cannot show, its dropped faces). */
#define SCENE_MAX_WARNINGS 4
/* Farthest image plane a fov may ask for: camera rays square their direction in single
 * precision, which overflows past about 1.8e19 (every pixel then the background). */
#define SCENE_MAX_PLANE_DISTANCE 1e19

/* A material: TZ_MATERIAL_LAMBERTIAN, _PHONG, _MIRROR, _REFRACTIVE, _CONDUCTOR or _PBR
 * (shared_layout.h), the
 * numbers the shaders read. */
typedef int material_kind;

/* The integrator: the course report's model ("report", called "seed" before, a word still
 * accepted) or physically based path tracing. */
typedef enum render_mode { RENDER_MODE_REPORT = 0, RENDER_MODE_PATH = 1 } render_mode;
/* The mode a word of `render mode` or `--mode` names at `index` in "report path seed". */
static inline render_mode scene_mode_of_word(int index) {
    return index == 1 ? RENDER_MODE_PATH : RENDER_MODE_REPORT;
}

/* Where a sample's numbers come from (shaders/common/sampler.h); auto: the mode's default. */
typedef enum render_sampler {
    RENDER_SAMPLER_AUTO = 0,
    RENDER_SAMPLER_RANDOM = 1,
    RENDER_SAMPLER_SOBOL = 2
} render_sampler;

/* The sampler a render uses: the one named, else sobol in path mode (lower error at equal
 * samples, docs/PERF.md) and random in report mode (the course report's images). */
static inline render_sampler scene_sampler_of(render_sampler named, render_mode mode) {
    if (named != RENDER_SAMPLER_AUTO) return named;
    return mode == RENDER_MODE_PATH ? RENDER_SAMPLER_SOBOL : RENDER_SAMPLER_RANDOM;
}

/* The bounces of a mode when the scene and the command line name none. */
static inline int scene_default_bounces(render_mode mode) {
    return mode == RENDER_MODE_PATH ? 16 : 5;
}

/* Bytes of an image's name kept for messages. */
#define SCENE_IMAGE_NAME 256

/* The texture maps a material may have (material.maps), each a slot of scene.slots; the order
 * of shared_layout.h's TZ_MAP_* (gpu_material.maps). */
enum {
    MAP_COLOR,
    MAP_EMISSION,
    MAP_NORMAL,
    MAP_ALPHA,
    MAP_METALLIC_ROUGHNESS,
    MAP_ROUGHNESS, /* MTL's map_Pr: a grey image alone */
    MAP_METALLIC,  /* MTL's map_Pm */
    MATERIAL_MAP_COUNT
};

/* How a material reads an image (a slot of the texture table, shared_layout.h): the image
 * (scene.images), TZ_WRAP_* of u and v and TZ_SLOT_SRGB in flags, a parameter (the alpha
 * cutoff, the normal scale) and the transform of the UVs (u' = t0 u + t1 v + t2, v' = t3 u +
 * t4 v + t5; KHR_texture_transform). */
typedef struct texture_slot {
    uint32_t image;
    uint32_t flags;
    float param;
    float transform[6];
} texture_slot;

/* An image file decoded once however many slots read it: its texels, its identity (device and
 * inode; 0 and 0 for an image embedded in a model, then keyed by its model and index in name)
 * and its path for messages. */
typedef struct scene_image {
    texture_image texels;
    uint64_t device, inode;
    char name[SCENE_IMAGE_NAME];
} scene_image;

/* A material (DESIGN section 2): what a sphere's or a face's line gives, or a model file's
 * material mapped. Held once, in scene.materials; spheres and faces refer to theirs by index,
 * and consecutive shapes that give the same share one (a quad's halves, a mesh's faces). */
typedef struct material {
    material_kind kind; /* a face's: lambertian, phong, mirror, conductor or pbr (glass needs a
                         * closed mesh); conductor is a mirror of roughness above 0 */
    vec3 color;         /* kd for lambertian/phong, tint for mirror/refractive */
    float ks;           /* phong specular weight, 0 for the others */
    float alpha;        /* phong exponent */
    float ior;          /* refractive index, 1 for the others; pbr's dielectric index */
    float roughness;    /* conductor and pbr: the GGX roughness (alpha = roughness^2), else 0 */
    float metallic;     /* pbr: the metal's share (glTF metallicFactor), else 0 */
    vec3 emission;      /* radiance emitted (path mode; an error in report mode); a face's is
                         * emitted from both sides */
    uint32_t maps[MATERIAL_MAP_COUNT]; /* scene.slots index + 1 of each map, 0 for none */
} material;

typedef struct sphere {
    vec3 center;
    float radius;
    uint32_t material; /* scene.materials[material] */
} sphere;

/* The unit shading normals at a face's corners, interpolated across it, and the corners' texture
 * coordinates (u, v). A flat face with UVs has zero normals here (the shaders then take its
 * geometric normal). */
typedef struct face_normals {
    vec3 n[3];
    float uv[3][2];
} face_normals;

/* triangle.normals of a flat face. */
#define TRIANGLE_FLAT UINT32_MAX

/* A triangle (a `triangle` line, half of a `quad`, or a face of a mesh). Its geometric normal
 * is normalize(cross(v[1] - v[0], v[2] - v[0])); both sides are seen. 44 bytes: a million faces
 * held 116 MB when each carried its material and its normals. */
typedef struct triangle {
    vec3 v[3];
    uint32_t material; /* scene.materials[material] */
    uint32_t normals;  /* scene.normals[normals], or TRIANGLE_FLAT */
} triangle;

/* Instances (DESIGN section 3.4): `mesh` lines that name one model again share one copy of its
 * faces, each placing it by its own transform. A model's faces are scene.model_faces[first,
 * first + count), in the model's own space. */
typedef struct scene_model {
    int first, count;
} scene_model;
/* At most this many instances: a hit on one is a primitive id TZ_INSTANCE_KEY + (instance <<
 * bits) + face, where bits is the bits of the largest instanced model's face count, under 2^31. */
#define SCENE_MAX_INSTANCE_KEYS 1073741824LL
/* One placement of scene.models[model]: world = to_world x (its 3 x 3 part, then column 3). */
typedef struct scene_instance {
    int model;
    double to_world[3][4];
} scene_instance;
/* What a light is: a point light, a spot (a point light within a cone) or a sun (a distant
 * light, a disc in the sky). */
typedef enum light_type { LIGHT_POINT, LIGHT_SPOT, LIGHT_SUN } light_type;

typedef struct light {
    vec3 position; /* point lights and spots */
    float power;   /* point lights and spots: the intensity (`power`); a sun: its irradiance */
    vec3 color;
    light_type kind;
    vec3 direction;             /* spots and suns: the unit direction the light travels along */
    float cos_inner, cos_outer; /* spots: the cosines of the cone's half-angles */
    float angle;                /* suns: the disc's angular diameter in degrees (0: a delta) */
} light;

/* Where and why parsing failed: "file:line:col: message". */
typedef struct scene_error {
    char file[256];
    int line, col;
    char message[512];
    bool out_of_memory; /* not the scene's fault: a runtime failure (exit 1), not a scene error */
} scene_error;

/* A file the render reads besides the scene's text: a mesh's model file or one the model names
 * (an OBJ's MTL, a glTF's buffers), by identity (device and inode) and the path it was opened
 * by: the CLI refuses to write its output over it. */
#define SCENE_INPUT_PATH 256
typedef struct scene_input {
    uint64_t device, inode;
    char path[SCENE_INPUT_PATH];
} scene_input;
/* Whether input in is the file of this device and inode. */
static inline bool scene_input_is(const scene_input *in, uint64_t device, uint64_t inode) {
    return in->device == device && in->inode == inode;
}

/* An environment map (`environment file`): the radiance of every direction as an equirectangular
 * image, 2:1, rows top (+y) down, its centre column facing +z (scenes/README.md); rgb NULL
 * without one (the background is seen). */
typedef struct environment_map {
    float *rgb; /* width * height * 3 floats, the intensity applied, finite and >= 0 */
    int width, height;
    float to_map[3][3]; /* rows: world directions to the map's (the inverse of its rotate) */
} environment_map;

typedef struct scene {
    vec3 camera_position, camera_direction, camera_up;
    float camera_fov;  /* horizontal field of view in degrees; 0: the plane sits 2 x width away */
    float camera_near; /* camera rays start this far along their direction */
    float camera_aperture;    /* the thin lens's radius; 0: a pinhole */
    float camera_focus;       /* the distance to the plane in focus (with an aperture) */
    bool camera_orthographic; /* `projection orthographic`: parallel rays from the plane */
    float plane_width, plane_height, pixel_size;
    int width, height; /* pixels: plane size / pixel size */
    vec3 background;
    environment_map environment;
    /* render settings; command-line flags override them */
    int spp; /* samples per pixel (`render samples`) */
    bool indirect;
    int bounces; /* scene_default_bounces(mode) unless the scene names it */
    bool bounces_given;
    bool roulette;          /* path mode: Russian roulette from the fourth vertex */
    int light_samples;      /* path mode: emitter samples a diffuse vertex (`light_samples`) */
    float noise_threshold;  /* adaptive sampling's threshold (`noise_threshold`); 0: off */
    render_sampler sampler; /* auto unless the scene names one */
    uint32_t seed;
    render_mode mode;
    sphere *spheres;
    int sphere_count;
    triangle *triangles;
    int triangle_count;
    material *materials; /* the spheres' and the triangles' */
    int material_count;
    face_normals *normals; /* the smooth triangles', and those of the faces with UVs */
    int normals_count;
    triangle *model_faces; /* the instanced models' faces (scene_model) */
    int model_face_count;
    scene_model *models;
    int model_count;
    scene_instance *instances;
    int instance_count;
    scene_image *images; /* the textures' images, each once */
    int image_count;
    texture_slot *slots; /* how materials read them (material.maps) */
    int slot_count;
    size_t texel_bytes; /* of every image, against TEXTURE_MAX_SCENE_BYTES */
    light *lights;
    int light_count;
    scene_input *inputs; /* the meshes' files, each once */
    int input_count;
    /* What the CLI warns about: the first sphere of radius, or glass mesh of bounding-box
     * half-extent, under SCENE_TINY_OFFSETS ray offsets; the sphere surface or triangle nearest
     * the camera when closer than SCENE_NEAR_CLIP_FACTOR times its rays' offset, or a sphere
     * surface closer than SCENE_PRECISION_STEPS float spacings at its size, or a face reaching
     * SCENE_FACE_SPAN times as far from the origin as the camera; the mesh files' dropped faces and
     * what trazador cannot show of them; settings the render's mode ignores; the first mesh wholly
     * outside the camera's view. */
    scene_error warnings[SCENE_MAX_WARNINGS];
    int warning_count;
} scene;

/* Parses scene text; false with *err filled (when non-NULL) and *out untouched on any error. */
bool scene_parse_string(const char *text, size_t length, const char *filename, scene *out,
                        scene_error *err);
/* scene_parse_string on up to threads threads (0: one per online processor); the scene, the
 * warnings and the error are the same for every thread count. */
bool scene_parse_string_threads(const char *text, size_t length, const char *filename, int threads,
                                scene *out, scene_error *err);
/* Reads and parses a file ("-": standard input, named <stdin>); false with *err filled on a
 * read or parse error. */
bool scene_parse_file(const char *path, scene *out, scene_error *err);
/* scene_parse_string and scene_parse_file for a render in mode, a render_mode, whatever the
 * scene's own (-1: the scene's own): emission is an error only where that mode is report. */
bool scene_parse_string_in_mode(const char *text, size_t length, const char *filename, int mode,
                                scene *out, scene_error *err);
bool scene_parse_file_in_mode(const char *path, int mode, scene *out, scene_error *err);
/* Prints err to stderr as "file:line:col: message" ("file: message" for errors about the file
 * itself, which have line 0); never fails. */
void scene_error_print(const scene_error *err);
/* The material of sphere sp of scene s. */
static inline const material *sphere_material(const scene *s, const sphere *sp) {
    return &s->materials[sp->material];
}
/* The material of triangle t of scene s. */
static inline const material *triangle_material(const scene *s, const triangle *t) {
    return &s->materials[t->material];
}
/* Whether two materials are the same, field by field, bit for bit. */
static inline bool material_same(const material *a, const material *b) {
    return a->kind == b->kind && !memcmp(&a->color, &b->color, sizeof a->color) &&
           !memcmp(&a->ks, &b->ks, sizeof a->ks) &&
           !memcmp(&a->alpha, &b->alpha, sizeof a->alpha) &&
           !memcmp(&a->ior, &b->ior, sizeof a->ior) &&
           !memcmp(&a->roughness, &b->roughness, sizeof a->roughness) &&
           !memcmp(&a->metallic, &b->metallic, sizeof a->metallic) &&
           !memcmp(&a->emission, &b->emission, sizeof a->emission) &&
           !memcmp(a->maps, b->maps, sizeof a->maps);
}
/* Whether material m has a texture map. */
static inline bool material_textured(const material *m) {
    for (int k = 0; k < MATERIAL_MAP_COUNT; k++)
        if (m->maps[k]) return true;
    return false;
}
/* Whether material m is of a GGX microfacet kind (conductor, pbr, rough glass); never fails. */
static inline bool material_is_microfacet(const material *m) {
    return m->kind == TZ_MATERIAL_CONDUCTOR || m->kind == TZ_MATERIAL_PBR ||
           m->kind == TZ_MATERIAL_DIELECTRIC;
}
/* Whether shapes of material m emit light (path mode's emitters); never fails. */
static inline bool material_emits(const material *m) {
    return m->emission.x > 0.0f || m->emission.y > 0.0f || m->emission.z > 0.0f;
}
/* Whether sphere sp of scene s emits light (path mode's emitters); never fails. */
static inline bool sphere_emits(const scene *s, const sphere *sp) {
    return material_emits(sphere_material(s, sp));
}
/* Whether triangle t of scene s emits light (path mode's emitters); never fails. */
static inline bool triangle_emits(const scene *s, const triangle *t) {
    return material_emits(triangle_material(s, t));
}
/* Whether a material of scene s is of a microfacet kind (TZ_FLAG_MICROFACET); never fails. */
static inline bool scene_has_microfacet(const scene *s) {
    for (int k = 0; k < s->material_count; k++)
        if (material_is_microfacet(&s->materials[k])) return true;
    return false;
}
/* Whether a material of scene s has an alpha map (TZ_FLAG_CUTOUTS: faces cut away where it
 * says); never fails. */
static inline bool scene_has_cutouts(const scene *s) {
    for (int k = 0; k < s->material_count; k++)
        if (s->materials[k].maps[MAP_ALPHA]) return true;
    return false;
}
/* Whether some sphere or face emits light (path mode's emitters); never fails. */
bool scene_emits(const scene *s);
/* Whether anything can light the image: a point light of some power and colour (both modes), an
 * emitting sphere or face (path mode: report mode refuses emission), an environment map or a
 * background that is not black (seen by camera and mirror rays, and by report mode's indirect
 * bounce); never fails. */
bool scene_has_light(const scene *s);
/* Releases the arrays of a parsed scene; safe on a zeroed scene. */
void scene_free(scene *s);

#endif
