/* scene.c: ownership of a parsed scene's arrays. */
#include "scene.h"

#include <stdlib.h>
#include <string.h>

void scene_free(scene *s) {
    free(s->spheres);
    free(s->lights);
    s->spheres = NULL;
    s->lights = NULL;
    s->sphere_count = 0;
    s->light_count = 0;
}
