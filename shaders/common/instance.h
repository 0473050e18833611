/* instance.h: instances (DESIGN section 3.4), one text for C and GLSL (dialect.h) over the
 * includer's accessors instance_to_object(i, r), instance_to_world(i, r) (rows of struct
 * gpu_instance) and instance_model(i): a ray moved into a model's space for its walk, a hit's
 * face found from its key, and its corners and normals moved back to world space. */
#ifndef TRAZADOR_COMMON_INSTANCE_H
#define TRAZADOR_COMMON_INSTANCE_H

#include "affine.h"
#include "dialect.h"

/* Whether the scene has instances, from the flags. */
#define TZ_HAS_INSTANCES ((TZ_FLAGS & TZ_FLAG_INSTANCES) != 0u)

/* Whether primitive id is a face of an instance (a key, TZ_INSTANCE_KEY on). */
TZ_FN TZ_BOOL is_instance_key(TZ_SCENE_PARAM int id) {
    return TZ_HAS_INSTANCES TZ_AND(id >= TZ_INSTANCE_KEY);
}

/* The instance of key id. */
TZ_FN int instance_of_key(TZ_SCENE_PARAM int id) {
    return (id - TZ_INSTANCE_KEY) >> TZ_INT(TZ_FRAME.instance_shift);
}

/* The triangle index of key id's face: its instance's model's first face plus the key's low
 * bits. */
TZ_FN int triangle_of_key(TZ_SCENE_PARAM int id) {
    int local = (id - TZ_INSTANCE_KEY) & ((1 << TZ_INT(TZ_FRAME.instance_shift)) - 1);
    return TZ_INT(instance_model(TZ_SCENE_ARG instance_of_key(TZ_SCENE_ARG id)).y) + local;
}

/* Whether instance i's transform is the identity, never applied (a flattened copy's bits). */
TZ_FN TZ_BOOL instance_is_identity(TZ_SCENE_PARAM int i) {
    return instance_model(TZ_SCENE_ARG i).z != 0u;
}

/* Model point p of instance i in world space. */
TZ_FN vec3 instance_point(TZ_SCENE_PARAM int i, vec3 p) {
    return affine_point(instance_to_world(TZ_SCENE_ARG i, 0), instance_to_world(TZ_SCENE_ARG i, 1),
                        instance_to_world(TZ_SCENE_ARG i, 2), p);
}

/* Model normal n of instance i in world space (not normalized). */
TZ_FN vec3 instance_normal(TZ_SCENE_PARAM int i, vec3 n) {
    return affine_normal(instance_to_object(TZ_SCENE_ARG i, 0),
                         instance_to_object(TZ_SCENE_ARG i, 1),
                         instance_to_object(TZ_SCENE_ARG i, 2), n);
}

#endif
