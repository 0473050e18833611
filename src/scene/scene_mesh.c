/* scene_mesh.c: the mesh directive (DESIGN section 3.4; scenes/README.md): a model file loaded
 * (mesh_load.c), moved by the line's scale, rotate and translate, its degenerate faces dropped,
 * glass only when it is closed, appended to the scene's triangles. */
#include "scene/scene_mesh.h"

#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "scene/directives.h"
#include "scene/mesh_cache.h"
#include "scene/mesh_load.h"
#include "scene/model_formats.h"
#include "scene/parser.h"
#include "util/threads.h"

/* From this many faces a mesh is transformed on every core. */
#define TRANSFORM_MIN_FACES 65536

/* A mesh's own keys (file, scale and rotate are read by directive_mesh: a path, 1 or 3 numbers, 4
 * numbers), then the material keys. */
enum {
    MESH_FILE,
    MESH_SCALE,
    MESH_ROTATE,
    MESH_TRANSLATE,
    MESH_SMOOTH,
    MESH_LIGHTS,
    MESH_MATERIAL,
    MESH_KEY_COUNT = MESH_MATERIAL + MAT_KEY_COUNT
};
static const key_spec mesh_keys[MESH_KEY_COUNT] = {
    {"file", NULL, VALUE_WORD, NO_RANGE},
    {"scale", NULL, VALUE_NUMBER, COORD_RANGE},
    {"rotate", NULL, VALUE_NUMBER, NO_RANGE},
    {"translate", "x y z", VALUE_NUMBER, COORD_RANGE},
    {"smooth", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    {"lights", NULL, VALUE_SWITCH, 0.0, 1.0, false},
    MATERIAL_KEY_SPECS,
};
_Static_assert(MESH_KEY_COUNT <= MAX_KEYS, "raise MAX_KEYS");

static const shape_spec mesh_shape = {
    .word = "mesh",
    .keys = mesh_keys,
    .key_count = MESH_KEY_COUNT,
    .material_first = MESH_MATERIAL,
    .own_keys = LOW_BITS(MESH_MATERIAL),
    .required = BIT(MESH_FILE),
    .glass = true, /* when the mesh is closed (directive_mesh checks) */
};

/* Whether the token can start a number (scale's second value or the next key). */
static bool looks_numeric(const token *t) {
    char c = t->text[0];
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
}

/* Reads a mesh line's keys after the optional material word (in any order; scale takes 1 or 3
 * numbers, rotate 4). False (reported) on a bad key or value. */
static bool read_mesh_keys(parser *p, const material_spec *m, int next, key_values *kv,
                           double scale[3], double rotate[4]) {
    unsigned accepted = mesh_shape.own_keys | (m ? m->keys << MESH_MATERIAL : 0u);
    memset(kv, 0, sizeof *kv);
    while (next < p->token_count) {
        const token *t = &p->tokens[next++];
        int key = 0;
        while (key < MESH_KEY_COUNT && !parser_token_is(t, mesh_keys[key].name)) key++;
        if (key < MESH_KEY_COUNT && key >= MESH_MATERIAL && !m) {
            return parser_fail(p, t->col,
                               "mesh '%s' needs a material word (mesh lambertian file ... %s ...): "
                               "without one every face takes the file's own material",
                               parser_quote(p, t), mesh_keys[key].name);
        }
        if (key == MESH_KEY_COUNT || !(accepted & BIT(key))) {
            char list[128] = "";
            for (int k = 0; k < MESH_KEY_COUNT; k++) {
                if (accepted & BIT(k))
                    directive_append(list, sizeof list, "%s%s", list[0] ? " " : "",
                                     mesh_keys[k].name);
            }
            return parser_fail(p, t->col, "unknown key '%s' for mesh%s%s (expected one of: %s)",
                               parser_quote(p, t), m ? " " : "", m ? m->word : "", list);
        }
        if (kv->given & BIT(key))
            return parser_fail(p, t->col, "'%s' given twice", mesh_keys[key].name);
        kv->given |= BIT(key);
        kv->key_token[key] = next - 1;
        if (key == MESH_FILE) {
            if (next >= p->token_count)
                return parser_fail(p, parser_end_col(p), "expected a path after 'file'");
            kv->value_token[key][0] = next++;
        } else if (key == MESH_SCALE || key == MESH_ROTATE) {
            int count = key == MESH_ROTATE ? 4 : 3;
            double *out = key == MESH_ROTATE ? rotate : scale;
            for (int c = 0; c < count; c++) {
                if (key == MESH_SCALE && c == 1 &&
                    (next >= p->token_count || !looks_numeric(&p->tokens[next]))) {
                    out[1] = out[2] = out[0];
                    break;
                }
                double value[3];
                int value_token[3];
                if (!parser_values(p, &mesh_keys[key], &next, value, value_token)) return false;
                out[c] = value[0];
            }
        } else if (!parser_values(p, &mesh_keys[key], &next, kv->value[key],
                                  kv->value_token[key])) {
            return false;
        }
    }
    if (!parser_require_keys(p, "mesh", mesh_keys, MESH_KEY_COUNT, mesh_shape.required, kv))
        return false;
    if (scale[0] == 0.0 || scale[1] == 0.0 || scale[2] == 0.0) {
        return parser_fail(p, p->tokens[kv->key_token[MESH_SCALE]].col,
                           "mesh scale must not be zero (it would flatten every face)");
    }
    if (rotate[0] == 0.0 && rotate[1] == 0.0 && rotate[2] == 0.0) {
        return parser_fail(p, p->tokens[kv->key_token[MESH_ROTATE]].col,
                           "mesh rotate axis must not be zero");
    }
    return true;
}

/* A file material as trazador's (a lambertian grey when the face has none), its textures loaded
 * (a path relative to the model's folder, or an image embedded in model `path`); false
 * (reported at col) when one cannot be read. */
static bool mapped_material(parser *p, const mesh *me, int index, const char *path, int col,
                            material *out) {
    if (index < 0 || index >= me->material_count) {
        *out = (material){.kind = TZ_MATERIAL_LAMBERTIAN, .color = v3(0.8f, 0.8f, 0.8f), .ior = 1};
        return true;
    }
    const mesh_material *mm = &me->materials[index];
    *out = (material){.kind = mm->kind,
                      .color = mm->color,
                      .ks = mm->ks,
                      .alpha = mm->alpha,
                      .ior = mm->ior,
                      .roughness = mm->roughness,
                      .metallic = mm->metallic,
                      .emission = mm->emission};
    for (int k = 0; k < MATERIAL_MAP_COUNT; k++) {
        const mesh_map *map = &mm->maps[k];
        if (!map->path[0]) continue;
        char named[PATH_MAX + MESH_MAP_PATH];
        char *end;
        long n = map->path[0] == '*' ? strtol(map->path + 1, &end, 10) : -1;
        bool ok;
        p->textures_optional = true;
        if (map->path[0] == '*') {
            if (*end || n < 0 || n >= me->embedded_count) {
                p->textures_optional = false;
                return parser_fail(p, col, "mesh '%s': texture '%s' is not in the file", path,
                                   map->path);
            }
            snprintf(named, sizeof named, "%s#%ld", path, n);
            ok = texture_slot_of_bytes(p, col, named, me->embedded + me->embedded_at[n],
                                       me->embedded_at[n + 1] - me->embedded_at[n], map->flags,
                                       map->param, map->transform, &out->maps[k]);
        } else {
            const char *slash = strrchr(path, '/');
            int dir = map->path[0] == '/' || !slash ? 0 : (int)(slash - path) + 1;
            snprintf(named, sizeof named, "%.*s%s", dir, path, map->path);
            ok = texture_slot_of_file(p, col, named, map->flags, map->param, map->transform,
                                      &out->maps[k]);
        }
        p->textures_optional = false;
        if (!ok) return false;
    }
    return true;
}

/* Whether a material of the file has a texture. */
static bool mesh_has_maps(const mesh *me) {
    for (int m = 0; m < me->material_count; m++)
        for (int k = 0; k < MATERIAL_MAP_COUNT; k++)
            if (me->materials[m].maps[k].path[0]) return true;
    return false;
}

/* One thread's share of mesh_faces_transform: faces [begin, end), its kept ones first. */
typedef struct transform_share {
    mesh_face *faces;
    const mesh_transform *xf;
    bool smooth;
    size_t begin, end, kept, dropped;
    size_t outside; /* the first face (from 1) that leaves the coordinate range, 0 none */
    char first_drop[320];
} transform_share;

static void *transform_run(void *arg) {
    transform_share *t = arg;
    for (size_t f = t->begin; f < t->end; f++) {
        mesh_face face = t->faces[f];
        for (int k = 0; k < 3; k++) {
            if (!mesh_transform_point(t->xf, t->faces[f].v[k], &face.v[k])) {
                t->outside = f + 1;
                return NULL;
            }
        }
        char why[256];
        if (face_problem(face.v[0], face.v[1], face.v[2], "face", why, sizeof why)) {
            if (!t->dropped++) snprintf(t->first_drop, sizeof t->first_drop, "%zu: %s", f + 1, why);
            continue;
        }
        bool normals = t->smooth;
        for (int k = 0; k < 3 && normals; k++)
            normals = mesh_transform_normal(t->xf, t->faces[f].n[k], &face.n[k]);
        for (int k = 0; k < 3 && !normals; k++) face.n[k] = v3(0, 0, 0); /* flat */
        t->faces[t->begin + t->kept++] = face;
    }
    return NULL;
}

/* (a million faces took 0.1 s on one core) */
bool mesh_faces_transform(mesh *me, const mesh_transform *xf, bool smooth, size_t *kept,
                          size_t *dropped, char *first_drop, size_t first_drop_size,
                          size_t *outside) {
    int shares = me->face_count >= TRANSFORM_MIN_FACES ? thread_count(0, THREADS_MAX) : 1;
    transform_share t[THREADS_MAX];
    for (int k = 0; k < shares; k++)
        t[k] = (transform_share){.faces = me->faces,
                                 .xf = xf,
                                 .smooth = smooth,
                                 .begin = me->face_count * (size_t)k / (size_t)shares,
                                 .end = me->face_count * (size_t)(k + 1) / (size_t)shares};
    threads_run(transform_run, t, sizeof t[0], shares);
    for (int k = 0; k < shares; k++) {
        if (t[k].outside) {
            *outside = t[k].outside;
            return false;
        }
        if (t[k].dropped && !*dropped) snprintf(first_drop, first_drop_size, "%s", t[k].first_drop);
        if (*kept != t[k].begin)
            memmove(me->faces + *kept, me->faces + t[k].begin, t[k].kept * sizeof *me->faces);
        *kept += t[k].kept;
        *dropped += t[k].dropped;
    }
    return true;
}

/* (a Phong material brighter than the light it receives is noted, by its name, for path mode's
 * warning) */
bool mesh_faces_add(parser *p, const mesh *me, size_t kept, const material *given, const char *path,
                    int col, bool *emits) {
    uint32_t index = 0, *mapped = NULL; /* mapped[k]: the scene's index of file material k */
    if (given && !material_add(p, given, &index)) return false;
    if (!given) {
        mapped = malloc(((size_t)me->material_count + 1) * sizeof *mapped);
        if (!mapped) {
            if (p->err) p->err->out_of_memory = true;
            return parser_fail(p, p->tokens[0].col, "out of memory");
        }
        for (int k = 0; k <= me->material_count; k++) mapped[k] = UINT32_MAX; /* none yet */
    }
    for (size_t f = 0; f < kept; f++) {
        const mesh_face *face = &me->faces[f];
        if (!given) {
            int slot = face->material >= 0 && face->material < me->material_count
                           ? face->material
                           : me->material_count; /* the last: no material */
            if (mapped[slot] == UINT32_MAX) {
                material s;
                if (!mapped_material(p, me, face->material, path, col, &s)) {
                    free(mapped);
                    return false;
                }
                *emits |= material_emits(&s);
                if (s.kind == TZ_MATERIAL_PHONG && slot < me->material_count) {
                    char what[PATH_MAX + 96];
                    snprintf(what, sizeof what, "mesh '%s': its material '%s'", path,
                             me->materials[face->material].name);
                    phong_note_bright(p, col, s.color, s.ks, what);
                }
                if (!material_add(p, &s, &mapped[slot])) {
                    free(mapped);
                    return false;
                }
            }
            index = mapped[slot];
        }
        bool flat = v3_is_zero(face->n[0]);
        /* A textured face keeps its UVs beside its normals (zero normals when flat). */
        bool textured = material_textured(&p->s.materials[index]);
        uint32_t corners = flat && !textured ? TRIANGLE_FLAT : normals_add(p, face->n);
        if (textured) memcpy(p->s.normals[corners].uv, face->uv, sizeof face->uv);
        face_add(p, face->v[0], face->v[1], face->v[2], index, corners);
    }
    free(mapped);
    return true;
}

/* Adds the files the mesh's import read to the scene's inputs, each file once; false (reported)
 * out of memory. */
static bool add_inputs(parser *p, const mesh *me) {
    for (int k = 0; k < me->input_count; k++) {
        const scene_input *in = &me->inputs[k];
        bool known = false;
        for (int j = 0; j < p->s.input_count && !known; j++)
            known = scene_input_is(&p->s.inputs[j], in->device, in->inode);
        if (known) continue;
        scene_input *grown = realloc(p->s.inputs, (size_t)(p->s.input_count + 1) * sizeof *grown);
        if (!grown) {
            if (p->err) p->err->out_of_memory = true;
            return parser_fail(p, p->tokens[0].col, "out of memory");
        }
        p->s.inputs = grown;
        p->s.inputs[p->s.input_count++] = *in;
    }
    return true;
}

/* The bounding box lo..hi of the mesh's first `kept` faces. */
static void mesh_box(const mesh *me, size_t kept, vec3 *lo, vec3 *hi) {
    *lo = *hi = me->faces[0].v[0];
    for (size_t f = 0; f < kept; f++) {
        for (int k = 0; k < 3; k++) {
            vec3 v = me->faces[f].v[k];
            *lo = v3(fminf(lo->x, v.x), fminf(lo->y, v.y), fminf(lo->z, v.z));
            *hi = v3(fmaxf(hi->x, v.x), fmaxf(hi->y, v.y), fmaxf(hi->z, v.z));
        }
    }
}

/* A mesh from a model file (mesh_load.c): transformed, its degenerate faces dropped (one
 * warning), glass only when each of its parts is closed. */
bool directive_mesh(parser *p) {
    const material_spec *m = NULL;
    int next = 1;
    if (p->token_count > 1 && !parser_token_is(&p->tokens[1], "file")) {
        const token *word = &p->tokens[1];
        m = material_lookup(word);
        if (!m) {
            char list[128];
            material_list(list, sizeof list, &mesh_shape, " ", true);
            return parser_fail(p, word->col,
                               "unknown material '%s' for mesh (expected 'file' or one of: %s)",
                               parser_quote(p, word), list);
        }
        next = 2;
    }
    key_values kv;
    double scale[3] = {1, 1, 1}, rotate[4] = {0, 0, 1, 0};
    if (!read_mesh_keys(p, m, next, &kv, scale, rotate)) return false;
    const token *file = &p->tokens[kv.value_token[MESH_FILE][0]];
    char path[PATH_MAX];
    if (!directive_file_path(p, file, "mesh", path, sizeof path)) return false;
    bool smooth = parser_value_or(&kv, MESH_SMOOTH, 0) != 0;
    bool lights = parser_value_or(&kv, MESH_LIGHTS, 0) != 0;
    double translate[3] = {0, 0, 0};
    for (int k = 0; k < 3 && (kv.given & BIT(MESH_TRANSLATE)); k++)
        translate[k] = kv.value[MESH_TRANSLATE][k];
    mesh_transform xf = mesh_transform_make(scale, rotate, translate);
    material given = {0};
    if (m) given = shape_material_of(p, &mesh_shape, m, &kv);
    if (m && !material_maps_read(p, MESH_MATERIAL, &kv, &given)) return false;
    /* A model an earlier line loaded, placed again: an instance (scene_instance.c). A mirroring
     * scale would turn glass inside out and `lights on` needs the file: those load faces. */
    bool mirror = scale[0] * scale[1] * scale[2] < 0.0;
    mesh_placed *placed = mesh_placed_find(p, path, smooth, m ? &given : NULL);
    bool instance = placed && mesh_placed_instanceable(placed) && !mirror && !lights;
    if (instance && mesh_placed_has_model(placed))
        return mesh_placed_instance(p, placed, &xf, file->col);
    /* The model's own faces are loaded untransformed for the instances to share. */
    const double unit_scale[3] = {1, 1, 1}, unit_rotate[4] = {0, 0, 1, 0}, origin[3] = {0, 0, 0};
    mesh_transform faces_xf = instance ? mesh_transform_make(unit_scale, unit_rotate, origin) : xf;
    int first = p->s.triangle_count, normals_first = p->s.normals_count;
    mesh me;
    char error[512];
    if (!mesh_cache_load(&p->meshes, path, smooth, &me, error, sizeof error)) {
        /* assimp's own words for a newer Blender file ("Did not find a field named `no`") say
         * nothing of the version */
        const char *dot = strrchr(path, '.');
        if (dot && !strcasecmp(dot, ".blend") && !strncmp(error, "cannot load", 11))
            return parser_fail(p, file->col, "mesh '%s': %s (assimp: %s)", path,
                               MODEL_BLENDER_ADVICE, error);
        return parser_fail(p, file->col, "mesh '%s': %s", path, error);
    }
    if (!add_inputs(p, &me) ||
        (me.instance_count &&
         !mesh_nodes_choose(p, &me, m, m ? &given : NULL, mirror, file->col))) {
        mesh_free(&me);
        return false;
    }
    bool nodes = me.instance_count > 0; /* meshes that several nodes place: instances */
    bool glass = false, emits = false;
    if (!mesh_faces_check_glass(p, &me, m, instance ? unit_scale : scale, path, file->col,
                                &glass)) {
        mesh_free(&me);
        return false;
    }
    /* Transformed in place; kept faces first. */
    size_t kept = 0, dropped = 0, outside = 0;
    char first_drop[320] = "";
    if (!mesh_faces_transform(&me, &faces_xf, smooth, &kept, &dropped, first_drop,
                              sizeof first_drop, &outside)) {
        mesh_free(&me);
        return parser_fail(p, file->col,
                           "mesh '%s': face %zu leaves the coordinate range (1e18) once "
                           "transformed",
                           path, outside);
    }
    if (kept == 0 && !nodes) {
        mesh_free(&me);
        return parser_fail(p, file->col, "mesh '%s': every face is degenerate (face %s)", path,
                           first_drop);
    }
    int room = kept > (size_t)INT_MAX / 2 ? INT_MAX / 2 : (int)kept;
    bool uvs = m ? material_textured(&given) : mesh_has_maps(&me);
    if (!faces_reserve(p, room) || ((smooth || uvs) && !normals_reserve(p, room)) ||
        !mesh_faces_add(p, &me, kept, m ? &given : NULL, path, file->col, &emits)) {
        mesh_free(&me);
        return false;
    }
    if (lights && !mesh_lights_add(p, &me, &xf, path, file->col)) {
        mesh_free(&me);
        return false;
    }
    if (emits && !m && !p->emission_line) {
        p->emission_line = p->line;
        p->emission_col = file->col;
    }
    vec3 lo = v3(INFINITY, INFINITY, INFINITY), hi = v3(-INFINITY, -INFINITY, -INFINITY);
    if (kept) mesh_box(&me, kept, &lo, &hi);
    if (glass && !instance && kept) mesh_warn_tiny_glass(p, lo, hi, path, file->col);
    bool noted;
    if (instance) {
        noted = mesh_placed_make_model(p, placed, first, file->col) &&
                mesh_placed_instance(p, placed, &xf, file->col);
    } else {
        bool instanceable = !emits && !(m && material_emits(&given)) && !mirror && !lights;
        double blo[3] = {lo.x, lo.y, lo.z}, bhi[3] = {hi.x, hi.y, hi.z};
        mesh_nodes_count count = {.unique = kept, .placed = kept};
        noted = mesh_placed_note(p, path, smooth, m ? &given : NULL, instanceable && !nodes, first,
                                 normals_first, &xf) &&
                (!nodes || mesh_nodes_place(p, &me, m, m ? &given : NULL, smooth, &xf, path,
                                            file->col, blo, bhi, &count));
        if (noted && count.placed == 0)
            noted = parser_fail(p, file->col,
                                "mesh '%s': places no face (every node that places one has a "
                                "transform that does not invert)",
                                path);
        lo = v3((float)blo[0], (float)blo[1], (float)blo[2]);
        hi = v3((float)bhi[0], (float)bhi[1], (float)bhi[2]);
        noted = noted && parser_note_mesh(p, file->col, count.placed, lo, hi, path);
        if (noted && nodes)
            parser_note_mesh_nodes(p, kept, count.unique - kept, count.shared_meshes,
                                   count.instances);
    }
    if (!noted) {
        mesh_free(&me);
        return false;
    }
    if (!m && me.unsupported[0]) {
        parser_warn(p, p->line, file->col, "mesh '%s': trazador cannot show its %s (ignored)", path,
                    me.unsupported);
    }
    if (dropped) {
        parser_warn(p, p->line, file->col,
                    "mesh '%s': %zu degenerate face%s dropped (the first, face %s)", path, dropped,
                    dropped == 1 ? "" : "s", first_drop);
    }
    mesh_free(&me);
    return true;
}
