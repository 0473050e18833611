/* mesh_cameras.c: a model file's cameras and lights in trazador's space, read from assimp's scene
 * before post-processing: each by its node's whole transform (the parents' too) in the file's
 * right-handed space, then z negated as the faces' is (mesh_load.c), so that a camera shows what
 * its author saw and not its mirror image. */
#include <assimp/camera.h>
#include <assimp/light.h>
#include <assimp/scene.h>
#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_load.h"

/* A row-major 4x4 transform in double: the products of a deep hierarchy keep their digits. */
typedef struct dmat4 {
    double m[4][4];
} dmat4;

static dmat4 of_assimp(const struct aiMatrix4x4 *a) {
    return (dmat4){{{a->a1, a->a2, a->a3, a->a4},
                    {a->b1, a->b2, a->b3, a->b4},
                    {a->c1, a->c2, a->c3, a->c4},
                    {a->d1, a->d2, a->d3, a->d4}}};
}

static dmat4 times(const dmat4 *a, const dmat4 *b) {
    dmat4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] +
                        a->m[i][2] * b->m[2][j] + a->m[i][3] * b->m[3][j];
    return r;
}

/* The whole transform of the node named name under node (whose parents' is *above) into *out;
 * false when no node has that name. */
static bool find_node(const struct aiNode *node, const dmat4 *above, const struct aiString *name,
                      dmat4 *out) {
    dmat4 local = of_assimp(&node->mTransformation), whole = times(above, &local);
    if (node->mName.length == name->length && !memcmp(node->mName.data, name->data, name->length)) {
        *out = whole;
        return true;
    }
    for (unsigned k = 0; k < node->mNumChildren; k++)
        if (find_node(node->mChildren[k], &whole, name, out)) return true;
    return false;
}

/* The transform of the node an assimp camera or light belongs to (by its name); the identity
 * when none has it. */
static dmat4 node_of(const struct aiScene *sc, const struct aiString *name) {
    dmat4 id = {{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}}}, out = id;
    if (sc->mRootNode && !find_node(sc->mRootNode, &id, name, &out)) out = id;
    return out;
}

/* v through t (w = 1 a point, 0 a direction) in the file's space, then into trazador's: z
 * negated. */
static vec3 converted(const dmat4 *t, struct aiVector3D v, double w) {
    double o[3];
    for (int i = 0; i < 3; i++)
        o[i] = t->m[i][0] * v.x + t->m[i][1] * v.y + t->m[i][2] * v.z + t->m[i][3] * w;
    /* + 0.0f: -0 becomes 0, whose reciprocal a ray's slab test takes the sign of */
    return v3((float)o[0] + 0.0f, (float)o[1] + 0.0f, (float)-o[2] + 0.0f);
}

static void copy_name(char *out, size_t size, const struct aiString *name, const char *kind,
                      unsigned index) {
    if (name->length > 0)
        snprintf(out, size, "%.*s", (int)name->length, name->data);
    else
        snprintf(out, size, "%s %u", kind, index);
}

static const char *light_kind(enum aiLightSourceType type) {
    switch (type) {
        case aiLightSource_POINT:
            return "point";
        case aiLightSource_SPOT:
            return "spot";
        case aiLightSource_DIRECTIONAL:
            return "directional";
        case aiLightSource_AMBIENT:
            return "ambient";
        case aiLightSource_AREA:
            return "area";
        default:
            return "undefined";
    }
}

bool mesh_read_views(const struct aiScene *sc, bool gltf, mesh *m) {
    unsigned cameras = sc->mNumCameras < MESH_MAX_CAMERAS ? sc->mNumCameras : MESH_MAX_CAMERAS;
    unsigned lights = sc->mNumLights < MESH_MAX_LIGHTS ? sc->mNumLights : MESH_MAX_LIGHTS;
    m->cameras = calloc(cameras ? cameras : 1, sizeof *m->cameras);
    m->lights = calloc(lights ? lights : 1, sizeof *m->lights);
    if (!m->cameras || !m->lights) return false;
    for (unsigned k = 0; k < cameras; k++) {
        const struct aiCamera *c = sc->mCameras[k];
        mesh_camera *out = &m->cameras[m->camera_count++];
        dmat4 t = node_of(sc, &c->mName);
        copy_name(out->name, sizeof out->name, &c->mName, "camera", k);
        /* glTF cameras sit at their node's origin: assimp 5.2.5 gives the node's translation as
         * the position, which the node's transform would then add a second time. */
        struct aiVector3D at = gltf ? (struct aiVector3D){0, 0, 0} : c->mPosition;
        out->position = converted(&t, at, 1.0);
        out->direction = converted(&t, c->mLookAt, 0.0);
        out->up = converted(&t, c->mUp, 0.0);
        out->aspect = c->mAspect;
        out->orthographic = c->mHorizontalFOV == 0.0f && c->mOrthographicWidth > 0.0f;
        /* assimp's mOrthographicWidth is half the view's width (glTF's xmag) */
        out->view_width = out->orthographic ? 2.0 * (double)c->mOrthographicWidth : 0.0;
        double fov = c->mHorizontalFOV;
        /* assimp 5.2.5 gives a glTF camera's yfov times its aspect: the horizontal fov that
         * shows what the file's vertical one does is 2 atan(aspect tan(yfov / 2)). */
        if (gltf && c->mAspect > 0.0f && isfinite(c->mAspect))
            fov = 2.0 * atan((double)c->mAspect * tan(fov / c->mAspect / 2.0));
        out->fov = fov * (180.0 / 3.14159265358979323846);
    }
    for (unsigned k = 0; k < lights; k++) {
        const struct aiLight *l = sc->mLights[k];
        mesh_light *out = &m->lights[m->light_count++];
        dmat4 t = node_of(sc, &l->mName);
        copy_name(out->name, sizeof out->name, &l->mName, "light", k);
        snprintf(out->kind, sizeof out->kind, "%s", light_kind(l->mType));
        out->position = converted(&t, l->mPosition, 1.0);
        out->direction = converted(&t, l->mDirection, 0.0);
        out->inner = l->mAngleInnerCone;
        out->outer = l->mAngleOuterCone;
        /* glTF's KHR_lights_punctual: assimp gives colour x intensity (candela or lux) */
        out->color[0] = l->mColorDiffuse.r;
        out->color[1] = l->mColorDiffuse.g;
        out->color[2] = l->mColorDiffuse.b;
    }
    return true;
}

bool mesh_light_power(const mesh_light *l, float *power, vec3 *color) {
    const double *c = l->color;
    for (int j = 0; j < 3; j++)
        if (!isfinite(c[j]) || c[j] < 0.0 || c[j] > FLT_MAX) return false;
    /* glTF's intensity is in candela, light arriving as I cos / d^2: trazador's power is that I */
    double most = fmax(c[0], fmax(c[1], c[2]));
    *power = (float)most;
    *color = most > 0.0 ? v3((float)(c[0] / most), (float)(c[1] / most), (float)(c[2] / most))
                        : v3(1, 1, 1);
    return true;
}
