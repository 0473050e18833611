/* scene_mesh_glass.c: a mesh line's glass (DESIGN section 3.4): each part closed, wound
 * outward, and a warning for one too small for the ray offset. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "scene/scene_mesh.h"

/* Warns, once a scene as for spheres (tiny_warned), when glass mesh `path` has a bounding box
 * lo..hi whose smallest half-extent is under SCENE_TINY_OFFSETS ray offsets at the box's largest
 * |coordinate|: rays that enter it start near or past its far side. */
void mesh_warn_tiny_glass(parser *p, vec3 lo, vec3 hi, const char *path, int col) {
    if (p->tiny_warned) return;
    double half = 0.5 * fmin((double)hi.x - lo.x, fmin((double)hi.y - lo.y, (double)hi.z - lo.z));
    vec3 largest = v3(fmaxf(-lo.x, hi.x), fmaxf(-lo.y, hi.y), fmaxf(-lo.z, hi.z));
    float offset = TZ_EPS * parser_largest_coordinate(largest);
    if (!(half < SCENE_TINY_OFFSETS * offset)) return;
    p->tiny_warned = true;
    parser_warn(p, p->line, col,
                "mesh '%s' is glass of half-size %g (its bounding box's smallest half-extent), "
                "under %g times the ray offset here (%g: %g times the largest coordinate, at "
                "least %g): rays that enter it start near or past its far side, so it is shaded "
                "wrongly (glass turns black first)",
                path, half, (double)SCENE_TINY_OFFSETS, (double)offset, (double)TZ_EPS,
                (double)TZ_EPS);
}

/* (mesh_glass_parts: an open part is refused naming it, its material, first face, box and an
 * open edge, in the file's own coordinates: z as the file has it; closed parts are wound
 * outward, as glass tells entering from leaving by the geometric normal) */
bool mesh_faces_check_glass(parser *p, mesh *me, const material_spec *m, const double scale[3],
                            const char *path, int col, bool *glass) {
    bool *is_glass = calloc((size_t)me->material_count + 1, sizeof *is_glass);
    if (!is_glass) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, col, "out of memory");
    }
    for (int k = 0; k <= me->material_count; k++) {
        is_glass[k] =
            m ? m->kind == TZ_MATERIAL_REFRACTIVE
              : k < me->material_count && (me->materials[k].kind == TZ_MATERIAL_REFRACTIVE ||
                                           me->materials[k].kind == TZ_MATERIAL_DIELECTRIC);
        *glass |= is_glass[k];
    }
    mesh_open_part open;
    mesh_glass_outcome outcome =
        *glass ? mesh_glass_parts(me, is_glass, scale[0] * scale[1] * scale[2] < 0.0, &open)
               : MESH_GLASS_CLOSED;
    free(is_glass);
    if (outcome == MESH_GLASS_NO_MEMORY) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, col, "out of memory checking mesh '%s''s glass", path);
    }
    if (outcome == MESH_GLASS_CLOSED) return true;
    char material[96] = "faces without a material";
    if (open.material >= 0 && open.material < me->material_count &&
        me->materials[open.material].name[0])
        snprintf(material, sizeof material, "material '%s'", me->materials[open.material].name);
    else if (open.material >= 0 && open.material < me->material_count)
        snprintf(material, sizeof material, "material %d (unnamed)", open.material);
    return parser_fail(
        p, col,
        "mesh '%s': a refractive part is not closed: %zu face%s of %s from face %zu, between "
        "%g %g %g and %g %g %g; its edge %g %g %g to %g %g %g is not shared by exactly two faces "
        "wound the opposite ways (coordinates as in the file): glass needs a surface that bounds "
        "its inside",
        path, open.faces, open.faces == 1 ? "" : "s", material, open.first_face + 1,
        (double)open.lo.x, (double)open.lo.y, (double)-open.hi.z, (double)open.hi.x,
        (double)open.hi.y, (double)-open.lo.z, (double)open.edge[0].x, (double)open.edge[0].y,
        (double)-open.edge[0].z, (double)open.edge[1].x, (double)open.edge[1].y,
        (double)-open.edge[1].z);
}
