/* scene_instance.c: instances (DESIGN section 3.4). A `mesh` line that names a model an earlier
 * line loaded (the same path, smooth and material words) places that model again: its faces are
 * kept once, in its own space (scene.model_faces), and each line adds a transform
 * (scene.instances). The first line of such a model was loaded as ordinary faces before anyone
 * knew it would repeat: the second makes the model, an instance of the first line's transform
 * and its own, and the parse's end takes the first line's faces out (mesh_placed_finish). */
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/parser.h"

/* A model the parse's mesh lines loaded: the first line's key and where its faces went. */
struct mesh_placed {
    char *path;
    bool smooth, given;
    material m;        /* the line's material, when given */
    bool instanceable; /* nothing that a copy shared with others cannot show (mesh_placed_note) */
    int first, count;  /* the first line's faces in scene.triangles */
    int normals_first; /* and their normals in scene.normals, when smooth */
    int normals_count;
    double to_world[3][4]; /* the first line's transform */
    int model;             /* its scene.models index, -1 before a second line */
    double lo[3], hi[3];   /* its model's box, in the model's space (once it has one) */
};

/* The model of key path, smooth and material given (NULL: the file's own), NULL when new. */
mesh_placed *mesh_placed_find(parser *p, const char *path, bool smooth, const material *given) {
    for (size_t k = 0; k < p->placed_count; k++) {
        mesh_placed *r = &p->placed[k];
        if (r->smooth == smooth && r->given == (given != NULL) && !strcmp(r->path, path) &&
            (!given || material_same(&r->m, given)))
            return r;
    }
    return NULL;
}

bool mesh_placed_note(parser *p, const char *path, bool smooth, const material *given,
                      bool instanceable, int first, int normals_first, const mesh_transform *xf) {
    if (mesh_placed_find(p, path, smooth, given)) return true;
    mesh_placed *grown = realloc(p->placed, (p->placed_count + 1) * sizeof *grown);
    char *copy = strdup(path);
    if (grown) p->placed = grown;
    if (!grown || !copy) {
        free(copy);
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, p->tokens[0].col, "out of memory");
    }
    mesh_placed *r = &p->placed[p->placed_count++];
    *r = (mesh_placed){.path = copy,
                       .smooth = smooth,
                       .given = given != NULL,
                       .instanceable = instanceable,
                       .first = first,
                       .count = p->s.triangle_count - first,
                       .normals_first = normals_first,
                       .normals_count = p->s.normals_count - normals_first,
                       .model = -1};
    if (given) r->m = *given;
    mesh_transform_rows(xf, r->to_world);
    return true;
}

bool mesh_placed_instanceable(const mesh_placed *r) { return r->instanceable; }

bool mesh_placed_has_model(const mesh_placed *r) { return r->model >= 0; }

/* Bits of the largest model's face count: an instance's keys are shifted by them. */
static int key_bits(const scene *s) {
    int largest = 1, bits = 0;
    for (int k = 0; k < s->model_count; k++)
        largest = s->models[k].count > largest ? s->models[k].count : largest;
    while ((1LL << bits) < largest) bits++;
    return bits;
}

bool scene_rows_invertible(double rows[3][4]) {
    double(*a)[4] = rows;
    double det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                 a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                 a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    double lengths = 1.0, largest = 0.0;
    for (int i = 0; i < 3; i++) {
        lengths *= sqrt(a[i][0] * a[i][0] + a[i][1] * a[i][1] + a[i][2] * a[i][2]);
        for (int j = 0; j < 3; j++) largest = fmax(largest, fabs(a[i][j]));
    }
    return fabs(det) > 1e-12 * lengths && fabs(det) > 1e-300 &&
           2.0 * largest * largest / fabs(det) < 1e38;
}

/* The box lo..hi of model `model`'s faces, in its space. */
static void model_box(const scene *s, int model, double lo[3], double hi[3]) {
    const scene_model *m = &s->models[model];
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (int f = m->first; f < m->first + m->count; f++) {
        for (int c = 0; c < 3; c++) {
            const vec3 *v = &s->model_faces[f].v[c];
            double x[3] = {v->x, v->y, v->z};
            for (int a = 0; a < 3; a++) lo[a] = fmin(lo[a], x[a]), hi[a] = fmax(hi[a], x[a]);
        }
    }
}

void scene_box_moved(const double lo[3], const double hi[3], double rows[3][4], double wlo[3],
                     double whi[3]) {
    for (int corner = 0; corner < 8; corner++) {
        double x[3] = {corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1],
                       corner & 4 ? hi[2] : lo[2]};
        for (int i = 0; i < 3; i++) {
            double w = rows[i][0] * x[0] + rows[i][1] * x[1] + rows[i][2] * x[2] + rows[i][3];
            wlo[i] = fmin(wlo[i], w), whi[i] = fmax(whi[i], w);
        }
    }
}

/* Notes the mesh line's box (parser_note_mesh): r's model's box moved by rows, corner by
 * corner. */
static bool note_box(parser *p, const mesh_placed *r, double rows[3][4], int col) {
    double wlo[3] = {INFINITY, INFINITY, INFINITY}, whi[3] = {-INFINITY, -INFINITY, -INFINITY};
    scene_box_moved(r->lo, r->hi, rows, wlo, whi);
    return parser_note_mesh(p, col, (size_t)p->s.models[r->model].count,
                            v3((float)wlo[0], (float)wlo[1], (float)wlo[2]),
                            v3((float)whi[0], (float)whi[1], (float)whi[2]), r->path);
}

bool scene_instance_add(parser *p, int model, double to_world[3][4], int col, const char *path) {
    if (!scene_rows_invertible(to_world))
        return parser_fail(p, col,
                           "mesh '%s': its transform is singular (an instance needs one that "
                           "inverts in single precision)",
                           path);
    scene *s = &p->s;
    long long keys = (long long)(s->instance_count + 1) << key_bits(s);
    if (keys > SCENE_MAX_INSTANCE_KEYS)
        return parser_fail(p, col,
                           "too many instances: %d of models of up to %d faces (instances times "
                           "the largest instanced model's face count, rounded up to a power of "
                           "two, may reach %lld)",
                           s->instance_count + 1, 1 << key_bits(s), SCENE_MAX_INSTANCE_KEYS);
    scene_instance *grown = realloc(s->instances, (size_t)(s->instance_count + 1) * sizeof *grown);
    if (!grown) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, col, "out of memory");
    }
    s->instances = grown;
    scene_instance *in = &s->instances[s->instance_count++];
    in->model = model;
    memcpy(in->to_world, to_world, sizeof in->to_world);
    return true;
}

bool mesh_placed_instance(parser *p, mesh_placed *r, const mesh_transform *xf, int col) {
    double rows[3][4];
    mesh_transform_rows(xf, rows);
    return scene_instance_add(p, r->model, rows, col, r->path) && note_box(p, r, rows, col);
}

bool scene_model_take(parser *p, int first, int col, int *model, double lo[3], double hi[3]) {
    scene *s = &p->s;
    int count = s->triangle_count - first;
    triangle *faces =
        realloc(s->model_faces, (size_t)(s->model_face_count + count) * sizeof *faces);
    scene_model *models = realloc(s->models, (size_t)(s->model_count + 1) * sizeof *models);
    if (faces) s->model_faces = faces;
    if (models) s->models = models;
    if (!faces || !models) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, col, "out of memory");
    }
    memcpy(s->model_faces + s->model_face_count, s->triangles + first,
           (size_t)count * sizeof *faces);
    s->models[s->model_count] = (scene_model){.first = s->model_face_count, .count = count};
    s->model_face_count += count;
    s->triangle_count = first; /* the faces moved: the model holds them (their normals stay) */
    *model = s->model_count++;
    model_box(s, *model, lo, hi);
    return true;
}

bool mesh_placed_make_model(parser *p, mesh_placed *r, int first, int col) {
    return scene_model_take(p, first, col, &r->model, r->lo, r->hi) &&
           scene_instance_add(p, r->model, r->to_world, col, r->path);
}

/* The removed ranges in scene order. */
static int placed_order(const void *a, const void *b) {
    const mesh_placed *x = *(mesh_placed *const *)a, *y = *(mesh_placed *const *)b;
    return (x->first > y->first) - (x->first < y->first);
}

/* Normals index x once the removed ranges' normals are gone (x is none of theirs). */
static uint32_t normals_after(mesh_placed *const *gone, size_t n, uint32_t x) {
    uint32_t drop = 0;
    for (size_t g = 0; g < n && (uint32_t)gone[g]->normals_first < x; g++)
        drop += (uint32_t)gone[g]->normals_count;
    return x - drop;
}

bool mesh_placed_finish(parser *p) {
    scene *s = &p->s;
    size_t n = 0;
    mesh_placed **gone = malloc((p->placed_count ? p->placed_count : 1) * sizeof *gone);
    if (!gone) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, 1, "out of memory");
    }
    for (size_t k = 0; k < p->placed_count; k++)
        if (p->placed[k].model >= 0) gone[n++] = &p->placed[k];
    if (n == 0) {
        free(gone);
        return true;
    }
    /* A range's normals are its own, appended in scene order like its faces. */
    qsort(gone, n, sizeof *gone, placed_order);
    int out = 0, in = 0;
    for (size_t g = 0; g <= n; g++) {
        int end = g < n ? gone[g]->first : s->triangle_count;
        for (; in < end; in++) {
            triangle t = s->triangles[in];
            if (t.normals != TRIANGLE_FLAT) t.normals = normals_after(gone, n, t.normals);
            s->triangles[out++] = t;
        }
        if (g < n) in += gone[g]->count;
    }
    s->triangle_count = out;
    for (int k = 0; k < s->model_face_count; k++) {
        triangle *t = &s->model_faces[k];
        if (t->normals != TRIANGLE_FLAT) t->normals = normals_after(gone, n, t->normals);
    }
    int kept = 0, next = 0;
    for (size_t g = 0; g <= n; g++) {
        int end = g < n ? gone[g]->normals_first : s->normals_count;
        while (next < end) s->normals[kept++] = s->normals[next++];
        if (g < n) next += gone[g]->normals_count;
    }
    s->normals_count = kept;
    free(gone);
    /* The first lines' faces are gone: their room goes back before the scene is packed (the
     * one copy of a big model's faces it held is most of what instances cost in memory). */
    triangle *t = realloc(s->triangles, (size_t)(out ? out : 1) * sizeof *t);
    face_normals *nn = realloc(s->normals, (size_t)(kept ? kept : 1) * sizeof *nn);
    if (t) s->triangles = t, p->triangle_capacity = (size_t)(out ? out : 1);
    if (nn) s->normals = nn, p->normals_capacity = (size_t)(kept ? kept : 1);
    return true;
}

void mesh_placed_free(parser *p) {
    for (size_t k = 0; k < p->placed_count; k++) free(p->placed[k].path);
    free(p->placed);
    p->placed = NULL;
    p->placed_count = 0;
}
