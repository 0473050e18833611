/* scene_pack_instances.c: the instances of a scene packed (DESIGN section 3.4): each model's
 * faces, stored after the scene's own, sorted into the order of a tree of their own whose nodes
 * follow the scene's tree; each instance its transform both ways and its model's root, in the
 * order of the scene's tree, whose leaves hold them as a third kind of primitive. */
#include "render/scene_pack_instances.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/bvh.h"
#include "util/big_memory.h"
#include "util/log.h"

/* The box of triangles [first, first + count) of p. */
static void faces_box(const struct gpu_triangle *t, uint32_t count, double lo[3], double hi[3]) {
    for (int a = 0; a < 3; a++) lo[a] = INFINITY, hi[a] = -INFINITY;
    for (uint32_t k = 0; k < count; k++) {
        const tz_vec4 *v[3] = {&t[k].v0, &t[k].v1, &t[k].v2};
        for (int c = 0; c < 3; c++) {
            for (int a = 0; a < 3; a++) {
                lo[a] = fmin(lo[a], (double)(&v[c]->x)[a]);
                hi[a] = fmax(hi[a], (double)(&v[c]->x)[a]);
            }
        }
    }
}

/* The world box of instance in: its model's box lo..hi moved by its transform, corner by corner,
 * in double, rounded outward to float. */
static bvh_box world_box(const scene_instance *in, const double lo[3], const double hi[3]) {
    double wlo[3] = {INFINITY, INFINITY, INFINITY}, whi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int corner = 0; corner < 8; corner++) {
        double p[3] = {corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1],
                       corner & 4 ? hi[2] : lo[2]};
        for (int i = 0; i < 3; i++) {
            const double *r = in->to_world[i];
            double x = r[0] * p[0] + r[1] * p[1] + r[2] * p[2] + r[3];
            wlo[i] = fmin(wlo[i], x);
            whi[i] = fmax(whi[i], x);
        }
    }
    bvh_box b;
    for (int i = 0; i < 3; i++) {
        b.lo[i] = nextafterf((float)wlo[i], -INFINITY);
        b.hi[i] = nextafterf((float)whi[i], INFINITY);
    }
    return b;
}

/* Whether rows are exactly [I | 0]. */
static bool is_identity(const double rows[3][4]) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 4; j++)
            if (rows[i][j] != (i == j ? 1.0 : 0.0)) return false;
    return true;
}

/* The gpu_instance of in, whose model's root node is root and first triangle first. */
static struct gpu_instance gpu_instance_of(const scene_instance *in, uint32_t root,
                                           uint32_t first) {
    const double(*a)[4] = in->to_world;
    double inv[3][3], det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
                            a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
                            a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) { /* the cofactor of (j, i) over the determinant */
            int r0 = (j + 1) % 3, r1 = (j + 2) % 3, c0 = (i + 1) % 3, c1 = (i + 2) % 3;
            inv[i][j] = (a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]) / det;
        }
    }
    struct gpu_instance g;
    for (int i = 0; i < 3; i++) {
        double t = -(inv[i][0] * a[0][3] + inv[i][1] * a[1][3] + inv[i][2] * a[2][3]);
        g.to_object[i] = (tz_vec4){(float)inv[i][0], (float)inv[i][1], (float)inv[i][2], (float)t};
        g.to_world[i] = (tz_vec4){(float)a[i][0], (float)a[i][1], (float)a[i][2], (float)a[i][3]};
    }
    g.model = (tz_uvec4){root, first, is_identity(in->to_world) ? 1u : 0u, 0u};
    return g;
}

/* Sorts model m's faces (triangles [first, first + count) of out) into the order of a tree of
 * their own and appends its nodes to out->nodes (leaves renumbered to the faces' primitive ids,
 * inner references moved by where the nodes land); *root its root's node. False (logged) out of
 * memory. */
static bool pack_model(packed_scene *out, uint32_t first, uint32_t count, uint32_t *root) {
    bvh tree;
    bvh_input in = {.triangles = out->triangles + first, .triangle_count = count};
    if (!bvh_build_primitives(&in, TZ_BVH_MAX_DEPTH, 0, &tree)) return false;
    struct gpu_triangle *sorted = big_malloc((size_t)count * sizeof *sorted);
    struct gpu_bvh_node *nodes =
        realloc(out->nodes, ((size_t)out->frame.node_count + tree.node_count) * sizeof *nodes);
    if (nodes) out->nodes = nodes;
    if (!sorted || !nodes) {
        log_error("out of memory packing a model of %u faces", count);
        free(sorted);
        bvh_free(&tree);
        return false;
    }
    for (uint32_t k = 0; k < count; k++) sorted[k] = out->triangles[first + tree.order[k]];
    memcpy(out->triangles + first, sorted, (size_t)count * sizeof *sorted);
    free(sorted);
    uint32_t base = out->frame.node_count, id = out->frame.sphere_count + first;
    for (uint32_t k = 0; k < tree.node_count; k++) {
        struct gpu_bvh_node n = tree.nodes[k];
        tz_vec4 *lo[2] = {&n.left_lo, &n.right_lo};
        for (int c = 0; c < 2; c++) {
            uint32_t ref;
            memcpy(&ref, &lo[c]->w, sizeof ref);
            /* 0 is no child (a one-leaf tree's right one): no inner child is the root */
            if (ref != 0) ref += ref >> TZ_BVH_COUNT_SHIFT ? id : base;
            memcpy(&lo[c]->w, &ref, sizeof ref);
        }
        out->nodes[base + k] = n;
    }
    *root = base;
    out->frame.node_count += tree.node_count;
    if (tree.depth > out->bvh_depth) out->bvh_depth = tree.depth;
    bvh_free(&tree);
    return true;
}

bool pack_instance_boxes(const packed_scene *out, const scene *s, bvh_box **boxes) {
    uint32_t flat = (uint32_t)s->triangle_count;
    *boxes = malloc((size_t)(s->instance_count ? s->instance_count : 1) * sizeof **boxes);
    double(*model_box)[6] =
        malloc((size_t)(s->model_count ? s->model_count : 1) * sizeof *model_box);
    if (!*boxes || !model_box) {
        log_error("out of memory packing %d instances", s->instance_count);
        free(*boxes), free(model_box);
        *boxes = NULL;
        return false;
    }
    for (int m = 0; m < s->model_count; m++)
        faces_box(out->triangles + flat + s->models[m].first, (uint32_t)s->models[m].count,
                  model_box[m], model_box[m] + 3);
    for (int k = 0; k < s->instance_count; k++) {
        const scene_instance *in = &s->instances[k];
        (*boxes)[k] = world_box(in, model_box[in->model], model_box[in->model] + 3);
    }
    free(model_box);
    return true;
}

bool pack_instances(packed_scene *out, const scene *s, const uint32_t *instance_order) {
    uint32_t flat = (uint32_t)s->triangle_count;
    uint32_t *roots = malloc((size_t)(s->model_count ? s->model_count : 1) * sizeof *roots);
    out->instances = big_calloc((size_t)s->instance_count, sizeof *out->instances);
    if (!roots || !out->instances) {
        log_error("out of memory packing %d instances", s->instance_count);
        free(roots);
        return false;
    }
    uint32_t largest = 1;
    for (int m = 0; m < s->model_count; m++) {
        const scene_model *model = &s->models[m];
        if (!pack_model(out, flat + (uint32_t)model->first, (uint32_t)model->count, &roots[m])) {
            free(roots);
            return false;
        }
        if ((uint32_t)model->count > largest) largest = (uint32_t)model->count;
    }
    for (int k = 0; k < s->instance_count; k++) {
        const scene_instance *in = &s->instances[instance_order[k]];
        out->instances[k] =
            gpu_instance_of(in, roots[in->model], flat + (uint32_t)s->models[in->model].first);
    }
    free(roots);
    uint32_t shift = 0;
    while ((1u << shift) < largest) shift++;
    out->frame.instance_count = (uint32_t)s->instance_count;
    out->frame.instance_shift = shift;
    out->frame.instance_leaf = out->frame.sphere_count + out->frame.triangle_count;
    out->frame.flags |= TZ_FLAG_INSTANCES;
    return true;
}
