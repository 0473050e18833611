/* scene_pack.h: struct scene + render options -> the flat GPU layout both back ends consume. */
#ifndef TRAZADOR_SCENE_PACK_H
#define TRAZADOR_SCENE_PACK_H

#include "render.h"
#include "shared_layout.h"

typedef struct packed_scene {
    struct gpu_frame frame;
    struct gpu_sphere *spheres;
    struct gpu_light *lights;
} packed_scene;

/* Packs the scene with the options applied; false (logged) on out-of-memory. */
bool scene_pack(const scene *s, const render_opts *opts, packed_scene *out);
/* Frees the packed arrays; safe on a zeroed packed_scene. */
void packed_scene_free(packed_scene *p);

#endif
