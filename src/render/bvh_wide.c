/* bvh_wide.c: the binary BVH collapsed into nodes of up to four children with quantized boxes
 * (struct gpu_wide_node), for the shaders' walk per invocation (see bvh_wide.h). */
#include "render/bvh_wide.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "util/big_memory.h"
#include "util/log.h"

/* trace_bvh (shaders/intersect.glsl) walks either tree with one stack of TZ_WIDE_STACK. */
_Static_assert(TZ_WIDE_STACK >= TZ_BVH_MAX_DEPTH, "the wide walk's stack holds the binary one's");

static uint32_t bits_of(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

static float float_of(uint32_t u) {
    float f;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* A child of a node being collapsed: its exact box, its reference and, for an inner child, the
 * binary node it is and that node's depth. */
typedef struct wide_child {
    float lo[3], hi[3];
    uint32_t ref;
    uint32_t depth;
} wide_child;

typedef struct widener {
    const struct gpu_bvh_node *binary;
    uint32_t depth; /* of the binary tree's deepest inner node */
    struct gpu_wide_node *out;
    uint32_t count;
} widener;

static bool is_inner(const wide_child *c) { return c->ref >> TZ_BVH_COUNT_SHIFT == 0; }

/* The children of binary node k at depth (the empty child of a leaf root left out) appended to
 * list from *n on. */
static void binary_children(const widener *w, uint32_t k, uint32_t depth, wide_child *list,
                            int *n) {
    const tz_vec4 *lo[2] = {&w->binary[k].left_lo, &w->binary[k].right_lo};
    const tz_vec4 *hi[2] = {&w->binary[k].left_hi, &w->binary[k].right_hi};
    for (int c = 0; c < 2; c++) {
        uint32_t ref = bits_of(lo[c]->w);
        if (ref == 0u) continue; /* the root is no one's child: an empty slot */
        list[(*n)++] = (wide_child){
            {lo[c]->x, lo[c]->y, lo[c]->z}, {hi[c]->x, hi[c]->y, hi[c]->z}, ref, depth + 1u};
    }
}

static float half_area(const wide_child *c) {
    float x = c->hi[0] - c->lo[0], y = c->hi[1] - c->lo[1], z = c->hi[2] - c->lo[2];
    return x * y + y * z + z * x;
}

/* True when a walk that reaches this node with pending children on its stack stays within
 * TZ_WIDE_STACK below every child of list: pushing n - 1 of them, then at most one at an inner
 * child and at each level of the binary tree below it (which every node can fall back to). */
static bool fits_stack(const widener *w, uint32_t pending, const wide_child *list, int n) {
    for (int c = 0; c < n; c++) {
        uint32_t below = is_inner(&list[c]) ? w->depth - list[c].depth + 1u : 0u;
        if (pending + (uint32_t)(n - 1) + below > TZ_WIDE_STACK) return false;
    }
    return true;
}

/* origin + q * 2^(exponent - 127) in float, as the shaders decode it. */
static float decoded(float origin, uint32_t q, uint32_t exponent) {
    return origin + (float)q * float_of(exponent << 23);
}

/* The smallest biased exponent whose 255 steps from origin reach top. */
static uint32_t scale_exponent(float origin, float top) {
    double extent = (double)top - (double)origin;
    int e = extent > 0.0 ? ilogb(extent / 255.0) + 127 : 1;
    e = e < 1 ? 1 : e > 254 ? 254 : e;
    while (e > 1 && decoded(origin, 255u, (uint32_t)e - 1u) >= top) e--;
    while (e < 254 && decoded(origin, 255u, (uint32_t)e) < top) e++;
    return (uint32_t)e;
}

/* The largest q whose decoded value is at most lo, or the smallest one at least hi (up). */
static uint32_t quantize(float origin, uint32_t exponent, float value, bool up) {
    double step = ldexp(1.0, (int)exponent - 127);
    double q = ((double)value - (double)origin) / step;
    q = up ? ceil(q) : floor(q);
    uint32_t k = q < 0.0 ? 0u : q > 255.0 ? 255u : (uint32_t)q;
    if (up)
        while (k < 255u && decoded(origin, k, exponent) < value) k++;
    else
        while (k > 0u && decoded(origin, k, exponent) > value) k--;
    return k;
}

/* Writes the node of list's n children into *node (references already wide). */
static void write_node(const wide_child *list, int n, struct gpu_wide_node *node) {
    float origin[3], top[3];
    uint32_t exponent[3];
    for (int a = 0; a < 3; a++) {
        origin[a] = list[0].lo[a], top[a] = list[0].hi[a];
        for (int c = 1; c < n; c++) {
            origin[a] = fminf(origin[a], list[c].lo[a]);
            top[a] = fmaxf(top[a], list[c].hi[a]);
        }
        /* A subnormal origin outwards to a normal float or zero: a GPU may flush it. */
        if (origin[a] != 0.0f && fabsf(origin[a]) < FLT_MIN)
            origin[a] = origin[a] < 0.0f ? -FLT_MIN : 0.0f;
        exponent[a] = scale_exponent(origin[a], top[a]);
    }
    memset(node, 0, sizeof *node);
    node->origin_exponents = (tz_uvec4){bits_of(origin[0]), bits_of(origin[1]), bits_of(origin[2]),
                                        exponent[0] | exponent[1] << 8 | exponent[2] << 16};
    uint32_t *refs = &node->refs.x;
    uint32_t *lo[3] = {&node->lo.x, &node->lo.y, &node->lo.z};
    uint32_t *hi[3] = {&node->lo.w, &node->hi.x, &node->hi.y};
    for (int c = 0; c < n; c++) {
        refs[c] = list[c].ref;
        for (int a = 0; a < 3; a++) {
            *lo[a] |= quantize(origin[a], exponent[a], list[c].lo[a], false) << (8 * c);
            *hi[a] |= quantize(origin[a], exponent[a], list[c].hi[a], true) << (8 * c);
        }
    }
}

/* Collapses binary node k at depth, reached with pending children on the walk's stack, and the
 * nodes below it, depth first, from w->count on; returns its index. The inner child with the
 * largest surface is opened first while there is room in the node and on the stack. */
static uint32_t widen(widener *w, uint32_t k, uint32_t depth, uint32_t pending) {
    uint32_t id = w->count++;
    wide_child list[TZ_WIDE_CHILDREN + 1];
    int n = 0;
    binary_children(w, k, depth, list, &n);
    while (n < TZ_WIDE_CHILDREN) {
        int open = -1;
        for (int c = 0; c < n; c++)
            if (is_inner(&list[c]) && (open < 0 || half_area(&list[c]) > half_area(&list[open])))
                open = c;
        if (open < 0) break;
        wide_child trial[TZ_WIDE_CHILDREN + 1];
        int m = 0;
        for (int c = 0; c < n; c++)
            if (c != open) trial[m++] = list[c];
        binary_children(w, list[open].ref, list[open].depth, trial, &m);
        if (m > TZ_WIDE_CHILDREN || !fits_stack(w, pending, trial, m)) break;
        memcpy(list, trial, sizeof list), n = m;
    }
    for (int c = 0; c < n; c++)
        if (is_inner(&list[c]))
            list[c].ref = widen(w, list[c].ref, list[c].depth, pending + (uint32_t)(n - 1));
    write_node(list, n, &w->out[id]);
    return id;
}

/* The depth of the deepest inner node: nodes come depth first, so each parent before its
 * children. */
static bool inner_depth(const struct gpu_bvh_node *nodes, uint32_t count, uint32_t *out) {
    uint8_t *depth = calloc(count, 1);
    if (!depth) return false;
    *out = 0;
    for (uint32_t k = 0; k < count; k++) {
        const tz_vec4 *lo[2] = {&nodes[k].left_lo, &nodes[k].right_lo};
        *out = depth[k] > *out ? depth[k] : *out;
        for (int c = 0; c < 2; c++) {
            uint32_t ref = bits_of(lo[c]->w);
            if (ref != 0u && ref >> TZ_BVH_COUNT_SHIFT == 0) depth[ref] = depth[k] + 1;
        }
    }
    free(depth);
    return true;
}

bool bvh_widen(const struct gpu_bvh_node *nodes, uint32_t count, struct gpu_wide_node **out,
               uint32_t *out_count) {
    *out = NULL, *out_count = 0;
    if (count == 0) return true;
    widener w = {.binary = nodes, .out = big_malloc(count * sizeof *w.out)};
    if (!w.out || !inner_depth(nodes, count, &w.depth)) {
        free(w.out);
        log_error("out of memory for the wide BVH of %u nodes", count);
        return false;
    }
    widen(&w, 0, 0, 0);
    *out = w.out, *out_count = w.count;
    return true;
}
