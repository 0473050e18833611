/* scene.c: ownership of a parsed scene's arrays, how its parse errors read, and whether anything
 * in it gives light. */
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
    free(s->model_faces);
    free(s->models);
    free(s->instances);
    s->model_faces = NULL;
    s->models = NULL;
    s->instances = NULL;
    s->model_face_count = s->model_count = s->instance_count = 0;
    for (int k = 0; k < s->image_count; k++) texture_image_free(&s->images[k].texels);
    free(s->images);
    free(s->slots);
    s->images = NULL;
    s->slots = NULL;
    s->image_count = s->slot_count = 0;
    s->texel_bytes = 0;
    free(s->environment.rgb);
    s->environment = (environment_map){0};
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

bool scene_emits(const scene *s) {
    /* a material is in the scene's table only when some sphere or face takes it */
    for (int k = 0; k < s->material_count; k++)
        if (material_emits(&s->materials[k])) return true;
    return false;
}

bool scene_has_light(const scene *s) {
    if (s->background.x > 0.0f || s->background.y > 0.0f || s->background.z > 0.0f) return true;
    if (s->environment.rgb) return true;
    for (int k = 0; k < s->light_count; k++) {
        const light *l = &s->lights[k];
        if (l->power > 0.0f && (l->color.x > 0.0f || l->color.y > 0.0f || l->color.z > 0.0f))
            return true;
    }
    return scene_emits(s);
}

void scene_error_print(const scene_error *err) {
    if (err->line > 0)
        fprintf(stderr, "%s:%d:%d: %s\n", err->file, err->line, err->col, err->message);
    else
        fprintf(stderr, "%s: %s\n", err->file, err->message);
}
