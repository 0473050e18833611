/* mesh_closed.c: whether a loaded mesh bounds a volume (glass needs one, DESIGN section 3.4):
 * its edges, corners compared by their float bits, sorted so that each edge's faces meet. */
#include <stdlib.h>
#include <string.h>

#include "scene/mesh_load.h"

/* An edge by its corners' bits, the smaller corner first; reversed: its face runs b to a. */
typedef struct edge {
    uint32_t a[3], b[3];
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

bool mesh_closed(const mesh *m) {
    size_t count = m->face_count * 3;
    edge *edges = malloc(count * sizeof *edges);
    if (!edges) return false;
    for (size_t f = 0; f < m->face_count; f++) {
        for (int k = 0; k < 3; k++) {
            edge *e = &edges[f * 3 + k];
            uint32_t p[3], q[3];
            mesh_corner_bits(m->faces[f].v[k], p);
            mesh_corner_bits(m->faces[f].v[(k + 1) % 3], q);
            bool swap = corner_compare(p, q) > 0;
            memcpy(e->a, swap ? q : p, sizeof p);
            memcpy(e->b, swap ? p : q, sizeof q);
            e->reversed = swap;
        }
    }
    qsort(edges, count, sizeof *edges, edge_compare);
    bool closed = true;
    for (size_t i = 0; i < count && closed;) {
        size_t j = i + 1;
        while (j < count && !edge_compare(&edges[i], &edges[j])) j++;
        closed = j - i == 2 && edges[i].reversed != edges[i + 1].reversed;
        i = j;
    }
    free(edges);
    return closed;
}
