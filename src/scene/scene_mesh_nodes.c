/* scene_mesh_nodes.c: a mesh line's file whose nodes place one mesh several times (mesh_nodes.c)
 * makes instances (DESIGN section 3.4): each such mesh a model of its faces, kept once, and an
 * instance per node, by the machinery of repeated mesh lines (scene_instance.c). */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/scene_mesh.h"

/* Whether part k of me emits, or holds glass, under the line's material (given: its own). */
static void part_kinds(const mesh *me, int k, const material_spec *m, const material *given,
                       bool *emits, bool *glass) {
    *emits = given && material_emits(given);
    *glass = m && m->kind == TZ_MATERIAL_REFRACTIVE;
    if (given) return;
    const mesh_part *part = &me->parts[k];
    const mesh_face *faces = me->faces + me->face_count + part->first;
    int last = -2; /* faces of one material follow each other: each run looked at once */
    for (size_t f = 0; f < part->count; f++) {
        int index = faces[f].material;
        if (index == last || index < 0 || index >= me->material_count) continue;
        last = index;
        const mesh_material *mm = &me->materials[index];
        *emits |= mm->emission.x > 0.0f || mm->emission.y > 0.0f || mm->emission.z > 0.0f;
        *glass |= mm->kind == TZ_MATERIAL_REFRACTIVE || mm->kind == TZ_MATERIAL_DIELECTRIC;
    }
}

bool mesh_nodes_choose(parser *p, mesh *me, const material_spec *m, const material *given,
                       bool mirror, int col) {
    bool *flatten = calloc((size_t)me->instance_count + 1, sizeof *flatten);
    bool *emits = calloc((size_t)me->part_count + 1, sizeof *emits);
    bool *glass = calloc((size_t)me->part_count + 1, sizeof *glass);
    bool ok = flatten && emits && glass;
    for (int k = 0; ok && k < me->part_count; k++)
        part_kinds(me, k, m, given, &emits[k], &glass[k]);
    for (int k = 0; ok && k < me->instance_count; k++) {
        const mesh_instance *in = &me->instances[k];
        bool mirrored = (mesh_rows_determinant(in->rows) < 0.0) != mirror;
        flatten[k] = emits[in->part] || (glass[in->part] && mirrored);
    }
    ok = ok && mesh_nodes_flatten(me, flatten);
    free(flatten), free(emits), free(glass);
    if (ok) return true;
    if (p->err) p->err->out_of_memory = true;
    return parser_fail(p, col, "out of memory");
}

/* rows: the line's transform xf after the node's rows. */
static void line_after_node(const mesh_transform *xf, const double node[3][4], double rows[3][4]) {
    double line[3][4];
    mesh_transform_rows(xf, line);
    mesh_rows_compose((const double(*)[4])line, node, rows);
}

/* Degenerate faces dropped from the parts: how many, and the first described. */
typedef struct dropped_faces {
    size_t count;
    int mesh; /* the file's mesh of the first */
    char first[320];
} dropped_faces;

/* Makes part k of me a model (its faces checked, their degenerate ones dropped and noted in
 * *dropped), its index in *model and box in lo..hi; *model -1 when every face is degenerate.
 * False (reported). */
static bool part_model(parser *p, mesh *me, int k, const material_spec *m, const material *given,
                       bool smooth, const char *path, int col, int *model, double lo[3],
                       double hi[3], dropped_faces *dropped) {
    *model = -1;
    mesh part = mesh_part_view(me, k);
    const double unit_scale[3] = {1, 1, 1}, unit_rotate[4] = {0, 0, 1, 0}, origin[3] = {0, 0, 0};
    mesh_transform identity = mesh_transform_make(unit_scale, unit_rotate, origin);
    bool glass = false, emits = false;
    if (!mesh_faces_check_glass(p, &part, m, unit_scale, path, col, &glass)) return false;
    size_t kept = 0, drops = 0, outside = 0;
    char first_drop[320] = "";
    if (!mesh_faces_transform(&part, &identity, smooth, &kept, &drops, first_drop,
                              sizeof first_drop, &outside))
        return parser_fail(p, col, "mesh '%s': face %zu of its mesh %d leaves the coordinate range",
                           path, outside, me->parts[k].mesh);
    if (drops && !dropped->count) {
        dropped->mesh = me->parts[k].mesh;
        snprintf(dropped->first, sizeof dropped->first, "%s", first_drop);
    }
    dropped->count += drops;
    if (kept == 0) return true;
    bool uvs = given && material_textured(given);
    for (int j = 0; !given && j < me->material_count; j++)
        for (int t = 0; t < MATERIAL_MAP_COUNT; t++) uvs |= me->materials[j].maps[t].path[0] != 0;
    int first = p->s.triangle_count;
    int room = kept > (size_t)INT_MAX / 2 ? INT_MAX / 2 : (int)kept;
    return faces_reserve(p, room) && ((!smooth && !uvs) || normals_reserve(p, room)) &&
           mesh_faces_add(p, &part, kept, given, path, col, &emits) &&
           scene_model_take(p, first, col, model, lo, hi);
}

bool mesh_nodes_place(parser *p, mesh *me, const material_spec *m, const material *given,
                      bool smooth, const mesh_transform *xf, const char *path, int col,
                      double lo[3], double hi[3], mesh_nodes_count *count) {
    int skipped = 0;
    const char *first_skipped = "";
    dropped_faces dropped = {0};
    for (int k = 0; k < me->part_count; k++) {
        bool used = false;
        for (int i = 0; i < me->instance_count && !used; i++) used = me->instances[i].part == k;
        if (!used) continue; /* every placement flattened (mesh_nodes_choose) */
        int model;
        double mlo[3], mhi[3];
        if (!part_model(p, me, k, m, given, smooth, path, col, &model, mlo, mhi, &dropped))
            return false;
        if (model < 0) continue;
        count->shared_meshes++;
        int faces = p->s.models[model].count;
        count->unique += (size_t)faces;
        for (int i = 0; i < me->instance_count; i++) {
            const mesh_instance *in = &me->instances[i];
            if (in->part != k) continue;
            double rows[3][4];
            line_after_node(xf, in->rows, rows);
            if (!scene_rows_invertible(rows)) {
                if (!skipped++) first_skipped = in->node;
                continue;
            }
            double wlo[3] = {INFINITY, INFINITY, INFINITY};
            double whi[3] = {-INFINITY, -INFINITY, -INFINITY};
            scene_box_moved(mlo, mhi, rows, wlo, whi);
            for (int a = 0; a < 3; a++)
                if (!(fabs(wlo[a]) <= 1e18 && fabs(whi[a]) <= 1e18))
                    return parser_fail(p, col,
                                       "mesh '%s': node '%s' moves its mesh %d out of the "
                                       "coordinate range (1e18)",
                                       path, in->node, me->parts[k].mesh);
            if (!scene_instance_add(p, model, rows, col, path)) return false;
            for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], wlo[a]), hi[a] = fmax(hi[a], whi[a]);
            count->placed += (size_t)faces;
            count->instances++;
        }
    }
    if (dropped.count)
        parser_warn(p, p->line, col,
                    "mesh '%s': %zu degenerate face%s of the meshes its nodes share dropped (the "
                    "first, of its mesh %d, face %s)",
                    path, dropped.count, dropped.count == 1 ? "" : "s", dropped.mesh,
                    dropped.first);
    if (skipped)
        parser_warn(p, p->line, col,
                    "mesh '%s': %d node%s (the first '%s') place%s a shared mesh by a transform "
                    "that does not invert (a scale of zero): skipped, as their faces would all be "
                    "degenerate",
                    path, skipped, skipped == 1 ? "" : "s", first_skipped, skipped == 1 ? "s" : "");
    return true;
}
