/* scene_pack_instances.h: the instances of a scene packed (scene_pack_instances.c), for
 * scene_pack.c. */
#ifndef TRAZADOR_SCENE_PACK_INSTANCES_H
#define TRAZADOR_SCENE_PACK_INSTANCES_H

#include <stdbool.h>
#include <stdint.h>

#include "render/bvh.h"
#include "render/scene_pack.h"

/* The world boxes of s's instances into *boxes (malloc'd), from out's triangles, where the
 * models' faces follow the scene's own; false (logged) out of memory. */
bool pack_instance_boxes(const packed_scene *out, const scene *s, bvh_box **boxes);
/* Sorts each model's faces into the order of its own tree, appends the trees to out->nodes and
 * packs the instances, instance k being s's instance_order[k]; the frame's instance fields set.
 * False (logged) out of memory. */
bool pack_instances(packed_scene *out, const scene *s, const uint32_t *instance_order);

#endif
