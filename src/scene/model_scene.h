/* model_scene.h: a model file rendered as the scene itself (`trazador render model.glb`): its
 * camera (or one that frames it), its point lights (or a white background in path mode), the
 * image from the camera's aspect (model_scene.c; scenes/README.md, "A model file as the scene"). */
#ifndef TRAZADOR_MODEL_SCENE_H
#define TRAZADOR_MODEL_SCENE_H

#include <stdbool.h>
#include <stdio.h>

#include "scene/scene.h"

/* Pixels across the image when --width does not say. */
#define MODEL_DEFAULT_WIDTH 640

/* What the command line asks of a model scene. */
typedef struct model_scene_opts {
    const char *camera;      /* an index from 0 or a camera's name; NULL: the file's first */
    long long width;         /* pixels across; -1: MODEL_DEFAULT_WIDTH */
    int mode;                /* a render_mode, or -1: path */
    const char *environment; /* an environment map's path (relative to the working folder) to
                              * light the model by; NULL: a white background without lights */
} model_scene_opts;

/* Loads the model at path and builds its scene into *out; false with *err filled ("path:
 * message", line 0) on a file that cannot be loaded, a camera that cannot be used or is not
 * there (the cameras listed), a light of negative or non-finite intensity. */
bool model_scene_parse(const char *path, const model_scene_opts *o, scene *out, scene_error *err);
/* Prints the model's cameras and lights to out, one a line (`trazador info`); false with *err
 * filled when it cannot be loaded. */
bool model_scene_list(const char *path, FILE *out, scene_error *err);

#endif
