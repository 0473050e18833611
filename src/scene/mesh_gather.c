/* mesh_gather.c: the faces and embedded images of a model file that assimp imported with
 * PreTransformVertices, in the import's child process (mesh_load.c). */
#include <assimp/material.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_import.h"
#include "scene/mesh_material.h"
#include "util/threads.h"

/* From this many faces the child gathers them on every core. */
#define GATHER_MIN_FACES 65536

/* One thread's share of the faces gathered (mesh_gather_faces): faces [begin, end) of the triangle
 * meshes' faces counted in order, written from out + begin on (where they go when every one of
 * them is a triangle; with one share, faces of other sizes are skipped). */
typedef struct gather_share {
    const struct aiScene *sc;
    size_t begin, end;
    mesh_face *out;
    size_t written;
    /* The first non-finite corner met, if any: its mesh, index and value. */
    bool failed;
    unsigned fail_mesh, fail_index;
    struct aiVector3D fail_value;
} gather_share;

/* Gathers a share's faces with their corners' normals (zero where the file gives none), in
 * trazador's left-handed space: model files are right-handed (OBJ, glTF, PLY, STL, COLLADA), so
 * z and the normals' z are negated and each face's winding flipped (corners 0 2 1), as assimp's
 * aiProcess_MakeLeftHanded with FlipWindingOrder would; a model's front (+Z) then faces a camera
 * at -z looking along +z, its geometric normals still point where the file's did. */
static void *gather_run(void *arg) {
    static const int corner_of[3] = {0, 2, 1};
    gather_share *g = arg;
    mesh_face *mf = g->out + g->begin;
    size_t start = 0; /* mesh i's first face among all the triangle meshes' faces */
    for (unsigned i = 0; i < g->sc->mNumMeshes && !g->failed && start < g->end; i++) {
        const struct aiMesh *me = g->sc->mMeshes[i];
        if (!(me->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        size_t from = g->begin > start ? g->begin - start : 0;
        size_t to = g->end - start < me->mNumFaces ? g->end - start : me->mNumFaces;
        start += me->mNumFaces;
        for (size_t f = from; f < to && !g->failed; f++) {
            const struct aiFace *face = &me->mFaces[f];
            if (face->mNumIndices != 3) continue;
            mf->material = mesh_face_material(g->sc, me);
            for (int k = 0; k < 3; k++) {
                unsigned index = face->mIndices[corner_of[k]];
                struct aiVector3D v = me->mVertices[index];
                if (!isfinite(v.x) || !isfinite(v.y) || !isfinite(v.z)) {
                    g->failed = true;
                    g->fail_mesh = i, g->fail_index = index, g->fail_value = v;
                    break;
                }
                mf->v[k] = v3(v.x, v.y, -v.z);
                struct aiVector3D n = me->mNormals ? me->mNormals[index] : (struct aiVector3D){0};
                bool finite = isfinite(n.x) && isfinite(n.y) && isfinite(n.z);
                mf->n[k] = finite ? v3(n.x, n.y, -n.z) : v3(0, 0, 0);
                mesh_corner_uv(me, index, mf->uv[k]);
            }
            mf++;
            g->written++;
        }
    }
    return NULL;
}

int mesh_face_material(const struct aiScene *sc, const struct aiMesh *me) {
    return me->mMaterialIndex < sc->mNumMaterials ? (int)me->mMaterialIndex : -1;
}

void mesh_corner_uv(const struct aiMesh *me, unsigned index, float uv[2]) {
    struct aiVector3D t =
        me->mTextureCoords[0] ? me->mTextureCoords[0][index] : (struct aiVector3D){0};
    bool finite = isfinite(t.x) && isfinite(t.y);
    uv[0] = finite ? t.x : 0.0f;
    uv[1] = finite ? t.y : 0.0f;
}

/* The triangle faces of sc into out->faces (room for all of them), in order: on every core when
 * there are many and every triangle mesh holds triangles alone (so a share knows where its faces
 * go: the reads of assimp's arrays and the 76 MB written took the child 0.1 s for a million
 * faces on one); false (error) at the first non-finite corner,
 * the one a single pass would meet first. */
bool mesh_gather_faces(const struct aiScene *sc, mesh *out, char *error, size_t error_size) {
    size_t total = 0;
    bool pure = true;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *me = sc->mMeshes[i];
        if (!(me->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
        if (me->mColors[0])
            mesh_note_unsupported(out->unsupported, sizeof out->unsupported, "vertex colours");
        total += me->mNumFaces;
        /* (triangulated polygons keep a flag that says so: their faces are triangles) */
        pure &= (me->mPrimitiveTypes & ~(unsigned)aiPrimitiveType_NGONEncodingFlag) ==
                aiPrimitiveType_TRIANGLE;
    }
    int shares = pure && total >= GATHER_MIN_FACES ? thread_count(0, THREADS_MAX) : 1;
    gather_share g[THREADS_MAX];
    for (int t = 0; t < shares; t++)
        g[t] = (gather_share){.sc = sc,
                              .begin = total * (size_t)t / (size_t)shares,
                              .end = total * (size_t)(t + 1) / (size_t)shares,
                              .out = out->faces};
    threads_run(gather_run, g, sizeof g[0], shares);
    for (int t = 0; t < shares; t++) {
        if (g[t].failed) {
            snprintf(error, error_size, "vertex %u of mesh %u has a non-finite position (%g %g %g)",
                     g[t].fail_index, g[t].fail_mesh, (double)g[t].fail_value.x,
                     (double)g[t].fail_value.y, (double)g[t].fail_value.z);
            return false;
        }
        out->face_count += g[t].written;
    }
    return true;
}

/* The compressed bytes of the embedded images ("*N") the materials name into out->embedded, each
 * material's path renamed to its index there; an image assimp holds decoded (its height not 0)
 * or past the limits is named unsupported and its maps dropped. False out of memory. */
bool mesh_gather_embedded(const struct aiScene *sc, mesh *out, char *error, size_t error_size) {
    int index_of[MESH_MAX_EMBEDDED];
    for (int k = 0; k < MESH_MAX_EMBEDDED; k++) index_of[k] = -1;
    for (int m = 0; m < out->material_count; m++) {
        for (int k = 0; k < MATERIAL_MAP_COUNT; k++) {
            mesh_map *map = &out->materials[m].maps[k];
            if (map->path[0] != '*') continue;
            char *end;
            long n = strtol(map->path + 1, &end, 10);
            const struct aiTexture *t =
                !*end && n >= 0 && n < (long)sc->mNumTextures && n < MESH_MAX_EMBEDDED
                    ? sc->mTextures[n]
                    : NULL;
            size_t used = out->embedded_at[out->embedded_count];
            bool room = t && (index_of[n] >= 0 || (out->embedded_count < MESH_MAX_EMBEDDED &&
                                                   t->mWidth <= MESH_MAX_EMBEDDED_BYTES - used));
            if (!t || t->mHeight != 0 || !room) {
                mesh_note_unsupported(out->unsupported, sizeof out->unsupported,
                                      "embedded textures stored decoded or past 256 MB");
                map->path[0] = '\0';
                continue;
            }
            if (index_of[n] < 0) {
                uint8_t *grown = realloc(out->embedded, used + t->mWidth + 1);
                if (!grown) {
                    snprintf(error, error_size, "out of memory for its textures");
                    return false;
                }
                out->embedded = grown;
                memcpy(grown + used, t->pcData, t->mWidth);
                index_of[n] = out->embedded_count++;
                out->embedded_at[out->embedded_count] = used + t->mWidth;
            }
            snprintf(map->path, sizeof map->path, "*%d", index_of[n]);
        }
    }
    return true;
}
