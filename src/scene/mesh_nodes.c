/* mesh_nodes.c: a model file's node hierarchy (DESIGN section 3.4, instances). A file whose
 * nodes place one mesh several times (glTF, COLLADA) is read without PreTransformVertices: each
 * mesh one node places is moved by that node's world transform here, as that step would have
 * moved it, and each mesh several nodes place becomes a part, its faces once, with an instance
 * (the node's transform) per placement, which the mesh line makes scene instances of
 * (scene_mesh_nodes.c). A file without such a mesh is read as before, so its faces keep their
 * bits. */
#include <assimp/scene.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_import.h"
#include "scene/mesh_load.h"

/* Deeper node hierarchies are refused (the walks recurse). */
#define MAX_NODE_DEPTH 1024

/* Adds the placements of node and its children to refs (a count per mesh); false past
 * MAX_NODE_DEPTH. */
static bool count_refs(const struct aiScene *sc, const struct aiNode *node, int depth,
                       unsigned *refs) {
    if (depth > MAX_NODE_DEPTH) return false;
    for (unsigned k = 0; k < node->mNumMeshes; k++)
        if (node->mMeshes[k] < sc->mNumMeshes && refs[node->mMeshes[k]] < 2)
            refs[node->mMeshes[k]]++;
    for (unsigned c = 0; c < node->mNumChildren; c++)
        if (node->mChildren[c] && !count_refs(sc, node->mChildren[c], depth + 1, refs))
            return false;
    return true;
}

/* refs (calloc'd, one per mesh, capped at 2) of sc's placements; NULL out of memory or when the
 * hierarchy is too deep. */
static unsigned *placements(const struct aiScene *sc) {
    unsigned *refs = calloc(sc->mNumMeshes ? sc->mNumMeshes : 1, sizeof *refs);
    if (refs && sc->mRootNode && !count_refs(sc, sc->mRootNode, 0, refs)) {
        free(refs);
        return NULL;
    }
    return refs;
}

bool mesh_nodes_shared(const struct aiScene *sc) {
    unsigned *refs = placements(sc);
    bool shared = false;
    for (unsigned i = 0; refs && i < sc->mNumMeshes; i++) shared |= refs[i] >= 2;
    free(refs);
    return shared;
}

/* An affine map in the file's space: rows [A | t]. */
typedef struct affine {
    double m[3][4];
} affine;

static affine compose(const affine *a, const struct aiMatrix4x4 *b) {
    const double r[3][4] = {
        {b->a1, b->a2, b->a3, b->a4}, {b->b1, b->b2, b->b3, b->b4}, {b->c1, b->c2, b->c3, b->c4}};
    affine out;
    mesh_rows_compose(a->m, r, out.m);
    return out;
}

/* The walk's state: where the faces go and what failed. */
typedef struct gather {
    const struct aiScene *sc;
    unsigned *refs;
    mesh *out;
    size_t capacity;
    int *part_of; /* per file mesh: its part, -1 none yet */
    size_t instance_capacity;
    char *error;
    size_t error_size;
} gather;

static bool fail(gather *g, const char *what, unsigned a, unsigned b) {
    snprintf(g->error, g->error_size, what, a, b);
    return false;
}

/* Appends mesh i's triangles moved by x (NULL: as they are), in trazador's left-handed space as
 * gather_run (mesh_gather.c) writes them; a mirroring x winds them back, as PreTransformVertices
 * does. */
static bool add_mesh(gather *g, unsigned i, const affine *x) {
    const struct aiMesh *me = g->sc->mMeshes[i];
    if (!(me->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) return true;
    mesh *out = g->out;
    size_t total = out->face_count + out->part_face_count;
    if (total + me->mNumFaces > g->capacity) {
        size_t capacity = 2 * g->capacity + me->mNumFaces;
        mesh_face *grown = realloc(out->faces, capacity * sizeof *grown);
        if (!grown) return fail(g, "out of memory", 0, 0);
        out->faces = grown, g->capacity = capacity;
    }
    double nm[3][3];
    bool mirrored = x && mesh_rows_determinant(x->m) < 0.0;
    if (x) mesh_rows_normal_matrix(x->m, nm);
    const int flat_corners[3] = {0, 2, 1}, mirrored_corners[3] = {0, 1, 2};
    const int *corner_of = mirrored ? mirrored_corners : flat_corners;
    mesh_face *mf = out->faces + total;
    for (unsigned f = 0; f < me->mNumFaces; f++) {
        const struct aiFace *face = &me->mFaces[f];
        if (face->mNumIndices != 3) continue;
        mf->material = mesh_face_material(g->sc, me);
        for (int k = 0; k < 3; k++) {
            unsigned index = face->mIndices[corner_of[k]];
            struct aiVector3D v = me->mVertices[index];
            if (!isfinite(v.x) || !isfinite(v.y) || !isfinite(v.z))
                return fail(g, "vertex %u of mesh %u has a non-finite position", index, i);
            double p[3] = {v.x, v.y, v.z}, w[3] = {v.x, v.y, v.z};
            if (x) mesh_rows_point(x->m, p, w);
            mf->v[k] = v3((float)w[0], (float)w[1], (float)-w[2]);
            struct aiVector3D n = me->mNormals ? me->mNormals[index] : (struct aiVector3D){0};
            double q[3] = {n.x, n.y, n.z}, u[3] = {n.x, n.y, n.z};
            if (x) mesh_rows_normal(nm, q, u);
            bool finite = isfinite(u[0]) && isfinite(u[1]) && isfinite(u[2]);
            mf->n[k] = finite ? v3((float)u[0], (float)u[1], (float)-u[2]) : v3(0, 0, 0);
            mesh_corner_uv(me, index, mf->uv[k]);
        }
        mf++;
    }
    size_t added = (size_t)(mf - (out->faces + total));
    if (x)
        out->face_count += added; /* (every placed face comes before the parts') */
    else
        out->part_face_count += added;
    return true;
}

/* Places the meshes node and its children place once (pass 0), or notes the instances of the
 * others (pass 1), x the node's parent's world transform. */
static bool walk(gather *g, const struct aiNode *node, const affine *parent, int pass) {
    affine x = compose(parent, &node->mTransformation);
    for (unsigned k = 0; k < node->mNumMeshes; k++) {
        unsigned i = node->mMeshes[k];
        if (i >= g->sc->mNumMeshes) continue;
        if (pass == 0 && g->refs[i] == 1 && !add_mesh(g, i, &x)) return false;
        if (pass == 1 && g->refs[i] >= 2 && g->part_of[i] >= 0) {
            mesh *out = g->out;
            if (out->instance_count == MESH_MAX_INSTANCES)
                return fail(g, "more than %u placements of shared meshes (nodes)",
                            MESH_MAX_INSTANCES, 0);
            if ((size_t)out->instance_count == g->instance_capacity) {
                size_t capacity = 2 * g->instance_capacity + 16;
                mesh_instance *grown = realloc(out->instances, capacity * sizeof *grown);
                if (!grown) return fail(g, "out of memory", 0, 0);
                out->instances = grown, g->instance_capacity = capacity;
            }
            mesh_instance *in = &out->instances[out->instance_count++];
            in->part = g->part_of[i];
            /* the node's map between faces whose z is negated: z negated on both sides */
            const double s[3] = {1, 1, -1};
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 4; c++) in->rows[r][c] = s[r] * x.m[r][c] * (c < 3 ? s[c] : 1);
            snprintf(in->node, sizeof in->node, "%.*s", (int)node->mName.length, node->mName.data);
        }
    }
    for (unsigned c = 0; c < node->mNumChildren; c++)
        if (node->mChildren[c] && !walk(g, node->mChildren[c], &x, pass)) return false;
    return true;
}

bool mesh_nodes_gather(const struct aiScene *sc, mesh *m, char *error, size_t error_size) {
    gather g = {.sc = sc, .out = m, .error = error, .error_size = error_size};
    g.refs = placements(sc);
    g.part_of = malloc((sc->mNumMeshes ? sc->mNumMeshes : 1) * sizeof *g.part_of);
    bool ok = g.refs && g.part_of;
    if (!ok) fail(&g, g.refs || !g.part_of ? "out of memory" : "its nodes nest too deep", 0, 0);
    const affine identity = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}}};
    if (ok && sc->mRootNode) ok = walk(&g, sc->mRootNode, &identity, 0);
    for (unsigned i = 0; ok && i < sc->mNumMeshes; i++) {
        g.part_of[i] = -1;
        if (g.refs[i] < 2) continue;
        size_t before = m->part_face_count;
        mesh_part *grown = realloc(m->parts, ((size_t)m->part_count + 1) * sizeof *grown);
        if (!grown) ok = fail(&g, "out of memory", 0, 0);
        if (ok) m->parts = grown, m->part_count++;
        ok = ok && add_mesh(&g, i, NULL);
        if (ok && m->part_face_count == before) {
            m->part_count--; /* points or lines only */
        } else if (ok) {
            m->parts[m->part_count - 1] =
                (mesh_part){.first = before, .count = m->part_face_count - before, .mesh = (int)i};
            g.part_of[i] = m->part_count - 1;
        }
    }
    if (ok && sc->mRootNode) ok = walk(&g, sc->mRootNode, &identity, 1);
    free(g.refs);
    free(g.part_of);
    return ok;
}
