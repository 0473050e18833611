/* mesh_parts.c: a loaded model's shared meshes (mesh_nodes.c) on the parser's side: their
 * placements' arithmetic, views of them, those flattened, and the model's box. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_load.h"

/* Up to this many faces placed by instances, mesh_bounds moves each one's corners (a tenth of
 * a second); past it, each instance's box. */
#define BOUNDS_EXACT_FACES ((size_t)1 << 24)

double mesh_rows_determinant(const double a[3][4]) {
    return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
           a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
           a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

void mesh_rows_normal_matrix(const double a[3][4], double out[3][3]) {
    double det = mesh_rows_determinant(a);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int r0 = (i + 1) % 3, r1 = (i + 2) % 3, c0 = (j + 1) % 3, c1 = (j + 2) % 3;
            out[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
        }
}

void mesh_rows_compose(const double a[3][4], const double b[3][4], double out[3][4]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            out[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] +
                        (j == 3 ? a[i][3] : 0.0);
}

void mesh_rows_point(const double rows[3][4], const double p[3], double out[3]) {
    for (int r = 0; r < 3; r++)
        out[r] = rows[r][0] * p[0] + rows[r][1] * p[1] + rows[r][2] * p[2] + rows[r][3];
}

void mesh_rows_normal(double nm[3][3], const double n[3], double out[3]) {
    double len = 0.0;
    for (int r = 0; r < 3; r++) {
        out[r] = nm[r][0] * n[0] + nm[r][1] * n[1] + nm[r][2] * n[2];
        len += out[r] * out[r];
    }
    for (int r = 0; len > 0.0 && r < 3; r++) out[r] /= sqrt(len);
}

/* Point p moved by rows, rounded to float. */
static vec3 moved(const double rows[3][4], vec3 p) {
    double x[3] = {p.x, p.y, p.z}, w[3];
    mesh_rows_point(rows, x, w);
    return v3((float)w[0], (float)w[1], (float)w[2]);
}

bool mesh_nodes_flatten(mesh *m, const bool *flatten) {
    size_t more = 0;
    for (int k = 0; k < m->instance_count; k++)
        if (flatten[k]) more += m->parts[m->instances[k].part].count;
    if (more == 0) return true;
    size_t total = m->face_count + more + m->part_face_count;
    mesh_face *faces = malloc(total * sizeof *faces);
    mesh_instance *kept = malloc(((size_t)m->instance_count + 1) * sizeof *kept);
    if (!faces || !kept) {
        free(faces), free(kept);
        return false;
    }
    const mesh_face *part_faces = m->faces + m->face_count;
    memcpy(faces, m->faces, m->face_count * sizeof *faces);
    memcpy(faces + m->face_count + more, part_faces, m->part_face_count * sizeof *faces);
    size_t next = m->face_count;
    int instances = 0;
    for (int k = 0; k < m->instance_count; k++) {
        const mesh_instance *in = &m->instances[k];
        if (!flatten[k]) {
            kept[instances++] = *in;
            continue;
        }
        const mesh_part *part = &m->parts[in->part];
        double nm[3][3];
        mesh_rows_normal_matrix(in->rows, nm);
        bool mirrored = mesh_rows_determinant(in->rows) < 0.0;
        for (size_t f = 0; f < part->count; f++) {
            const mesh_face *from = &part_faces[part->first + f];
            mesh_face *to = &faces[next++];
            to->material = from->material;
            for (int c = 0; c < 3; c++) {
                int k2 = mirrored && c ? 3 - c : c; /* a mirroring node's faces wound back */
                to->v[c] = moved(in->rows, from->v[k2]);
                vec3 n = from->n[k2];
                double q[3] = {n.x, n.y, n.z}, u[3];
                mesh_rows_normal(nm, q, u);
                to->n[c] = v3((float)u[0], (float)u[1], (float)u[2]);
                memcpy(to->uv[c], from->uv[k2], sizeof to->uv[c]);
            }
        }
    }
    free(m->faces);
    free(m->instances);
    m->faces = faces, m->face_count += more;
    m->instances = kept, m->instance_count = instances;
    return true;
}

/* Grows the box lo..hi (empty when !*any) by v. */
static void grow(vec3 v, vec3 *lo, vec3 *hi, bool *any) {
    *lo = *any ? v3(fminf(lo->x, v.x), fminf(lo->y, v.y), fminf(lo->z, v.z)) : v;
    *hi = *any ? v3(fmaxf(hi->x, v.x), fmaxf(hi->y, v.y), fmaxf(hi->z, v.z)) : v;
    *any = true;
}

bool mesh_bounds(const mesh *m, vec3 *lo, vec3 *hi) {
    bool any = false;
    for (size_t f = 0; f < m->face_count; f++)
        for (int j = 0; j < 3; j++) grow(m->faces[f].v[j], lo, hi, &any);
    const mesh_face *part_faces = m->faces + m->face_count;
    size_t placed = 0;
    for (int k = 0; k < m->instance_count; k++) placed += m->parts[m->instances[k].part].count;
    if (placed <= BOUNDS_EXACT_FACES) { /* every corner moved: the box flattened faces have */
        for (int k = 0; k < m->instance_count; k++) {
            const mesh_instance *in = &m->instances[k];
            const mesh_part *part = &m->parts[in->part];
            for (size_t f = part->first; f < part->first + part->count; f++)
                for (int j = 0; j < 3; j++) grow(moved(in->rows, part_faces[f].v[j]), lo, hi, &any);
        }
        return any;
    }
    /* past that, an instance by its part's box's corners moved (a box around its faces) */
    vec3 *boxes = malloc(((size_t)m->part_count + 1) * 2 * sizeof *boxes);
    for (int k = 0; boxes && k < m->part_count; k++) {
        bool some = false;
        for (size_t f = m->parts[k].first; f < m->parts[k].first + m->parts[k].count; f++)
            for (int j = 0; j < 3; j++)
                grow(part_faces[f].v[j], &boxes[2 * k], &boxes[2 * k + 1], &some);
    }
    for (int k = 0; boxes && k < m->instance_count; k++) {
        const mesh_instance *in = &m->instances[k];
        vec3 plo = boxes[2 * in->part], phi = boxes[2 * in->part + 1];
        for (int c = 0; c < 8; c++)
            grow(moved(in->rows,
                       v3(c & 1 ? phi.x : plo.x, c & 2 ? phi.y : plo.y, c & 4 ? phi.z : plo.z)),
                 lo, hi, &any);
    }
    free(boxes);
    return any;
}

mesh mesh_part_view(const mesh *m, int k) {
    mesh view = *m;
    view.faces = m->faces + m->face_count + m->parts[k].first;
    view.face_count = m->parts[k].count;
    view.part_face_count = 0;
    view.part_count = view.instance_count = 0;
    view.parts = NULL, view.instances = NULL;
    return view;
}
