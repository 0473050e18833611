/* mesh_closed.c: whether a loaded mesh's glass bounds a volume (DESIGN section 3.4), part by
 * part: faces joined by their edges (corners compared by their float bits, edges sorted so that
 * each edge's faces meet) make the parts; each part with glass is closed or named open, and each
 * closed one wound outward. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_load.h"

/* An edge of face `face` by its corners' bits, the smaller corner first; reversed: the
 * face runs b to a. */
typedef struct edge {
    uint32_t a[3], b[3];
    uint32_t face;
    bool reversed;
} edge;

static int corner_compare(const uint32_t *x, const uint32_t *y) {
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return x[k] < y[k] ? -1 : 1;
    return 0;
}

static int edge_compare(const void *x, const void *y) {
    const edge *e = x, *f = y;
    int c = corner_compare(e->a, f->a);
    return c ? c : corner_compare(e->b, f->b);
}

/* The part (a face standing for it) that face f belongs to, paths halved on the way. */
static uint32_t part_of(uint32_t *parent, uint32_t f) {
    while (parent[f] != f) {
        parent[f] = parent[parent[f]];
        f = parent[f];
    }
    return f;
}

/* Whether face f is glass: glass[its material], the last entry for faces without one. */
static bool face_glass(const mesh *m, const bool *glass, size_t f) {
    int material = m->faces[f].material;
    return glass[material >= 0 && material < m->material_count ? material : m->material_count];
}

/* Whether edges i (the first of its run) to j - 1, one edge of their faces, leave a part open:
 * not two faces running along it the opposite ways. */
static bool edge_open(const edge *edges, size_t i, size_t j) {
    return j - i != 2 || edges[i].reversed == edges[i + 1].reversed;
}

/* The open part of the first glass face that is in one, described in *open (the material of
 * that face) with the first of its open edges (in the sorted order). */
static void describe_open(const mesh *m, const bool *glass, uint32_t *parent, const bool *open_at,
                          const edge *edges, size_t count, mesh_open_part *open) {
    uint32_t chosen = UINT32_MAX;
    int material = -1;
    for (size_t f = 0; f < m->face_count && chosen == UINT32_MAX; f++) {
        if (face_glass(m, glass, f) && open_at[part_of(parent, (uint32_t)f)]) {
            chosen = part_of(parent, (uint32_t)f);
            material = m->faces[f].material;
        }
    }
    *open = (mesh_open_part){.material = material};
    for (size_t f = 0; f < m->face_count; f++) {
        if (part_of(parent, (uint32_t)f) != chosen) continue;
        if (!open->faces++) {
            open->first_face = f;
            open->lo = open->hi = m->faces[f].v[0];
        }
        for (int k = 0; k < 3; k++) {
            vec3 v = m->faces[f].v[k];
            open->lo = v3(fminf(open->lo.x, v.x), fminf(open->lo.y, v.y), fminf(open->lo.z, v.z));
            open->hi = v3(fmaxf(open->hi.x, v.x), fmaxf(open->hi.y, v.y), fmaxf(open->hi.z, v.z));
        }
    }
    for (size_t i = 0, j; i < count; i = j) {
        for (j = i + 1; j < count && !edge_compare(&edges[i], &edges[j]); j++) continue;
        if (!edge_open(edges, i, j) || part_of(parent, edges[i].face) != chosen) continue;
        memcpy(&open->edge[0], edges[i].a, sizeof open->edge[0]);
        memcpy(&open->edge[1], edges[i].b, sizeof open->edge[1]);
        break;
    }
}

/* Six times the signed volume of the tetrahedron of the origin and face f's corners, in double. */
static double face_volume(const mesh_face *face) {
    const vec3 *v = face->v;
    double a[3] = {v[0].x, v[0].y, v[0].z}, b[3] = {v[1].x, v[1].y, v[1].z},
           c[3] = {v[2].x, v[2].y, v[2].z};
    return a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) +
           a[2] * (b[0] * c[1] - b[1] * c[0]);
}

/* Winds each part with glass (has_glass, by its root) outward: its faces flipped where its
 * signed volume, once mirrored or not by the line's transform, is negative. */
static bool wind_outward(mesh *m, const bool *has_glass, uint32_t *parent, bool mirrored) {
    double *volume = calloc(m->face_count, sizeof *volume);
    if (!volume) return false;
    for (size_t f = 0; f < m->face_count; f++)
        volume[part_of(parent, (uint32_t)f)] += face_volume(&m->faces[f]);
    for (size_t f = 0; f < m->face_count; f++) {
        uint32_t part = part_of(parent, (uint32_t)f);
        if (!has_glass[part]) continue;
        double v = volume[part];
        if (!(mirrored ? v > 0.0 : v < 0.0)) continue;
        mesh_face *face = &m->faces[f];
        vec3 p = face->v[1], n = face->n[1];
        face->v[1] = face->v[2], face->n[1] = face->n[2];
        face->v[2] = p, face->n[2] = n;
        float uv[2] = {face->uv[1][0], face->uv[1][1]};
        memcpy(face->uv[1], face->uv[2], sizeof uv);
        memcpy(face->uv[2], uv, sizeof uv);
    }
    free(volume);
    return true;
}

mesh_glass_outcome mesh_glass_parts(mesh *m, const bool *glass, bool mirrored,
                                    mesh_open_part *open) {
    size_t count = m->face_count * 3;
    edge *edges = malloc(count * sizeof *edges);
    uint32_t *parent = malloc(m->face_count * sizeof *parent);
    bool *open_at = calloc(m->face_count, sizeof *open_at),
         *has_glass = calloc(m->face_count, sizeof *has_glass);
    mesh_glass_outcome outcome = MESH_GLASS_NO_MEMORY;
    if (!edges || !parent || !open_at || !has_glass) goto done;
    for (size_t f = 0; f < m->face_count; f++) {
        parent[f] = (uint32_t)f;
        for (int k = 0; k < 3; k++) {
            edge *e = &edges[f * 3 + k];
            uint32_t p[3], q[3];
            mesh_corner_bits(m->faces[f].v[k], p);
            mesh_corner_bits(m->faces[f].v[(k + 1) % 3], q);
            bool swap = corner_compare(p, q) > 0;
            memcpy(e->a, swap ? q : p, sizeof p);
            memcpy(e->b, swap ? p : q, sizeof q);
            e->face = (uint32_t)f;
            e->reversed = swap;
        }
    }
    qsort(edges, count, sizeof *edges, edge_compare);
    /* Faces that share an edge are one part; an edge not shared by exactly two faces running
     * along it the opposite ways opens the part (marked once all are joined). */
    for (size_t i = 0, j; i < count; i = j) {
        for (j = i + 1; j < count && !edge_compare(&edges[i], &edges[j]); j++) {
            uint32_t x = part_of(parent, edges[i].face), y = part_of(parent, edges[j].face);
            parent[x > y ? x : y] = x > y ? y : x;
        }
    }
    for (size_t f = 0; f < m->face_count; f++)
        if (face_glass(m, glass, f)) has_glass[part_of(parent, (uint32_t)f)] = true;
    bool any_open = false;
    for (size_t i = 0, j; i < count; i = j) {
        for (j = i + 1; j < count && !edge_compare(&edges[i], &edges[j]); j++) continue;
        uint32_t part = part_of(parent, edges[i].face);
        if (edge_open(edges, i, j) && has_glass[part]) open_at[part] = any_open = true;
    }
    if (any_open) {
        describe_open(m, glass, parent, open_at, edges, count, open);
        outcome = MESH_GLASS_OPEN;
    } else {
        outcome =
            wind_outward(m, has_glass, parent, mirrored) ? MESH_GLASS_CLOSED : MESH_GLASS_NO_MEMORY;
    }
done:
    free(edges);
    free(parent);
    free(open_at);
    free(has_glass);
    return outcome;
}
