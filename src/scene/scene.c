/* scene.c: ownership of a parsed scene's arrays, and how its parse errors read. */
#include "scene/scene.h"

#include <stdio.h>
#include <stdlib.h>

void scene_free(scene *s) {
    free(s->spheres);
    free(s->triangles);
    free(s->materials);
    free(s->normals);
    free(s->lights);
    free(s->inputs);
    s->spheres = NULL;
    s->triangles = NULL;
    s->materials = NULL;
    s->normals = NULL;
    s->lights = NULL;
    s->inputs = NULL;
    s->sphere_count = 0;
    s->triangle_count = 0;
    s->material_count = 0;
    s->normals_count = 0;
    s->light_count = 0;
    s->input_count = 0;
}

void scene_error_print(const scene_error *err) {
    if (err->line > 0)
        fprintf(stderr, "%s:%d:%d: %s\n", err->file, err->line, err->col, err->message);
    else
        fprintf(stderr, "%s: %s\n", err->file, err->message);
}
