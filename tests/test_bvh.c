/* test_bvh.c: the BVH against brute force: nearest hits and shadow tests of 100,000+ random rays
 * on random scenes (overlapping and nested spheres, rays starting inside spheres and on their
 * surfaces), the tree's invariants (depth bound, leaf sizes, every sphere in one leaf, boxes that
 * hold their contents) on ordinary and pathological inputs, the same tree for every thread count,
 * and build time for big scenes; the wide tree made from each: every sphere in one leaf, within
 * every decoded box above it, and every walk within its stack. */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "check.h"
#include "common/rng.h"
#include "render/bvh.h"
#include "render/bvh_wide.h"
#include "render/cpu/integrator.h"

static uint32_t rng_state = 12345u;
static float uniform(float lo, float hi) { return lo + (hi - lo) * rng_next(&rng_state); }

static vec3 random_direction(void) {
    for (;;) {
        vec3 v = v3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        float l = v3_length(v);
        if (l > 0.05f && l <= 1.0f) return v3_scale(v, 1.0f / l);
    }
}

/* A scene of n spheres in a 20-unit box: sizes from tiny to big, so they overlap and nest. */
static void random_scene(scene *s, int n) {
    *s = (scene){.width = 1,
                 .height = 1,
                 .pixel_size = 1,
                 .plane_width = 1,
                 .plane_height = 1,
                 .camera_direction = {0, 0, 1},
                 .camera_up = {0, 1, 0},
                 .spp = 1,
                 .bounces = 5};
    s->spheres = calloc((size_t)n, sizeof *s->spheres);
    s->sphere_count = n;
    /* every sphere names material 0, a grey lambertian */
    s->materials = calloc(1, sizeof *s->materials);
    *s->materials =
        (material){.kind = TZ_MATERIAL_LAMBERTIAN, .color = {0.8f, 0.8f, 0.8f}, .ior = 1};
    s->material_count = 1;
    for (int k = 0; k < n; k++) {
        float r = rng_next(&rng_state) < 0.1f ? uniform(1.0f, 4.0f) : uniform(0.01f, 0.6f);
        s->spheres[k] = (sphere){.center = v3(uniform(-10, 10), uniform(-10, 10), uniform(-10, 10)),
                                 .radius = r};
    }
}

/* The packed index of the sphere equal to input sphere k (the BVH reorders them). */
static int packed_index(const packed_scene *p, const sphere *sp) {
    for (uint32_t k = 0; k < p->frame.sphere_count; k++) {
        const tz_vec4 *c = &p->spheres[k].center_radius;
        if (c->x == sp->center.x && c->y == sp->center.y && c->z == sp->center.z &&
            c->w == sp->radius)
            return (int)k;
    }
    return -1;
}

static bool same_sphere(const packed_scene *a, int ia, const packed_scene *b, int ib) {
    if (ia < 0 || ib < 0) return ia == ib;
    return !memcmp(&a->spheres[ia].center_radius, &b->spheres[ib].center_radius, sizeof(tz_vec4));
}

static void compare_rays(int sphere_count, int rays) {
    scene s;
    random_scene(&s, sphere_count);
    render_opts with = {.spp = 1}, without = {.spp = 1, .no_bvh = true};
    packed_scene tree, brute;
    if (!scene_pack(&s, &with, &tree) || !scene_pack(&s, &without, &brute)) {
        CHECK(0, "pack failed");
        return;
    }
    CHECK(tree.frame.node_count > 0 && brute.frame.node_count == 0, "BVH present only when asked");
    int nearest_bad = 0, shadow_bad = 0, hits = 0;
    for (int r = 0; r < rays; r++) {
        vec3 o, d = random_direction();
        int self_brute = -1, self_tree = -1;
        if (r % 4 ==
            0) { /* start on a sphere's surface, leaving it (as every secondary ray does) */
            int k = (int)(rng_next(&rng_state) * (float)sphere_count) % sphere_count;
            const sphere *sp = &s.spheres[k];
            o = v3_add(sp->center, v3_scale(random_direction(), sp->radius));
            self_brute = packed_index(&brute, sp);
            self_tree = packed_index(&tree, sp);
        } else { /* anywhere, often inside one or more spheres */
            o = v3(uniform(-12, 12), uniform(-12, 12), uniform(-12, 12));
        }
        float ta, tb;
        int a = integrator_nearest(&brute, o, d, self_brute, &ta);
        int b = integrator_nearest(&tree, o, d, self_tree, &tb);
        hits += a >= 0;
        if (!same_sphere(&brute, a, &tree, b) || ta != tb) {
            if (nearest_bad++ < 5)
                fprintf(stderr, "ray %d: brute %d t=%.9g, bvh %d t=%.9g\n", r, a, ta, b, tb);
        }
        float dist = uniform(0.0f, 15.0f);
        if (integrator_occluded(&brute, o, d, dist, self_brute) !=
            integrator_occluded(&tree, o, d, dist, self_tree))
            shadow_bad++;
    }
    CHECK(nearest_bad == 0, "%d spheres: %d of %d nearest hits differ", sphere_count, nearest_bad,
          rays);
    CHECK(shadow_bad == 0, "%d spheres: %d of %d shadow tests differ", sphere_count, shadow_bad,
          rays);
    CHECK(hits > rays / 10, "%d spheres: only %d of %d rays hit anything", sphere_count, hits,
          rays);
    scene_pack_free(&tree);
    scene_pack_free(&brute);
    scene_free(&s);
}

static uint32_t bits(float f) {
    uint32_t u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* 1 when box lo..hi lies within box olo..ohi. */
static int box_within(const tz_vec4 *lo, const tz_vec4 *hi, const tz_vec4 *olo,
                      const tz_vec4 *ohi) {
    return lo->x >= olo->x && lo->y >= olo->y && lo->z >= olo->z && hi->x <= ohi->x &&
           hi->y <= ohi->y && hi->z <= ohi->z;
}

/* Walks the child of box lo..hi that ref names: leaf sizes, coverage, containment; returns the
 * depth of its deepest leaf below it (0 for a leaf). */
static uint32_t check_child(const bvh *t, const struct gpu_sphere *spheres, uint32_t ref,
                            const tz_vec4 *lo, const tz_vec4 *hi, uint32_t *seen, uint32_t count,
                            int *bad) {
    uint32_t leaf = ref >> TZ_BVH_COUNT_SHIFT, index = ref & TZ_BVH_INDEX_MASK;
    if (leaf) {
        if (leaf > TZ_BVH_LEAF_MAX || index + leaf > count) {
            (*bad)++;
            return 0;
        }
        for (uint32_t k = index; k < index + leaf; k++) {
            seen[k]++;
            const tz_vec4 *c = &spheres[t->order[k]].center_radius;
            tz_vec4 slo = {c->x - c->w, c->y - c->w, c->z - c->w, 0.0f};
            tz_vec4 shi = {c->x + c->w, c->y + c->w, c->z + c->w, 0.0f};
            if (!box_within(&slo, &shi, lo, hi)) (*bad)++;
        }
        return 0;
    }
    if (index >= t->node_count) {
        (*bad)++;
        return 0;
    }
    const struct gpu_bvh_node *n = &t->nodes[index];
    const tz_vec4 *los[2] = {&n->left_lo, &n->right_lo}, *his[2] = {&n->left_hi, &n->right_hi};
    uint32_t depth = 0;
    for (int c = 0; c < 2; c++) {
        if (!box_within(los[c], his[c], lo, hi)) (*bad)++;
        uint32_t d = 1 + check_child(t, spheres, bits(los[c]->w), los[c], his[c], seen, count, bad);
        depth = d > depth ? d : depth;
    }
    return depth;
}

/* check_child from the root; a tree that is one leaf is a root with an empty right child. */
static uint32_t check_root(const bvh *t, const struct gpu_sphere *spheres, uint32_t *seen,
                           uint32_t count, int *bad) {
    const struct gpu_bvh_node *root = &t->nodes[0];
    if (root->right_lo.x == INFINITY) {
        int empty = root->right_hi.x == INFINITY && bits(root->right_lo.w) == 0;
        *bad += !empty;
        return check_child(t, spheres, bits(root->left_lo.w), &root->left_lo, &root->left_hi, seen,
                           count, bad);
    }
    const tz_vec4 everywhere_lo = {-INFINITY, -INFINITY, -INFINITY, 0};
    const tz_vec4 everywhere_hi = {INFINITY, INFINITY, INFINITY, 0};
    return check_child(t, spheres, 0, &everywhere_lo, &everywhere_hi, seen, count, bad);
}

/* Coordinate a of the box corner that quantized byte q of node n decodes to, as the shaders'
 * walk decodes it (shared_layout.h, struct gpu_wide_node). */
static float wide_decoded(const struct gpu_wide_node *n, int a, uint32_t q) {
    const uint32_t *origin = &n->origin_exponents.x;
    uint32_t exponent = n->origin_exponents.w >> (8 * a) & 255u, scale_bits = exponent << 23;
    float o, scale;
    memcpy(&o, &origin[a], sizeof o);
    memcpy(&scale, &scale_bits, sizeof scale);
    return o + (float)q * scale;
}

/* What check_wide_child passes down: the tree, and the decoded boxes from the root's children to
 * the current one. */
typedef struct wide_check {
    const bvh *t;
    const struct gpu_sphere *spheres;
    const struct gpu_wide_node *nodes;
    uint32_t node_count, count, *seen;
    float lo[TZ_BVH_MAX_DEPTH][3], hi[TZ_BVH_MAX_DEPTH][3];
    int bad;
} wide_check;

/* Checks wide node k at level `level`, reached with `pending` children on a walk's stack, and
 * every node below it. */
static void check_wide_node(wide_check *w, uint32_t k, int level, uint32_t pending) {
    if (k >= w->node_count || level >= TZ_BVH_MAX_DEPTH) {
        w->bad++;
        return;
    }
    const struct gpu_wide_node *n = &w->nodes[k];
    const uint32_t *refs = &n->refs.x;
    const uint32_t *lo[3] = {&n->lo.x, &n->lo.y, &n->lo.z}, *hi[3] = {&n->lo.w, &n->hi.x, &n->hi.y};
    uint32_t children = 0;
    for (int c = 0; c < TZ_WIDE_CHILDREN; c++) children += refs[c] != 0u;
    if (children == 0 || pending + children - 1 > TZ_WIDE_STACK) w->bad++;
    for (int c = 0; c < TZ_WIDE_CHILDREN; c++) {
        uint32_t ref = refs[c];
        if (ref == 0u) continue;
        for (int a = 0; a < 3; a++) {
            w->lo[level][a] = wide_decoded(n, a, *lo[a] >> (8 * c) & 255u);
            w->hi[level][a] = wide_decoded(n, a, *hi[a] >> (8 * c) & 255u);
        }
        uint32_t leaf = ref >> TZ_BVH_COUNT_SHIFT, index = ref & TZ_BVH_INDEX_MASK;
        if (!leaf) {
            check_wide_node(w, index, level + 1, pending + children - 1);
            continue;
        }
        for (uint32_t s = index; s < index + leaf && s < w->count; s++) {
            w->seen[s]++;
            const tz_vec4 *b = &w->spheres[w->t->order[s]].center_radius;
            float slo[3] = {b->x - b->w, b->y - b->w, b->z - b->w};
            float shi[3] = {b->x + b->w, b->y + b->w, b->z + b->w};
            for (int l = 0; l <= level; l++)
                for (int a = 0; a < 3; a++)
                    w->bad += !(w->lo[l][a] <= slo[a] && shi[a] <= w->hi[l][a]);
        }
    }
}

/* The wide tree of t: as many spheres seen as the binary tree holds, each once and within every
 * decoded box on its way, no walk past its stack, fewer nodes than the binary tree. */
static void check_wide(const char *name, const bvh *t, const struct gpu_sphere *spheres,
                       uint32_t count) {
    wide_check w = {.t = t, .spheres = spheres, .count = count};
    CHECK(bvh_widen(t->nodes, t->node_count, (struct gpu_wide_node **)&w.nodes, &w.node_count),
          "%s: widening failed", name);
    w.seen = calloc(count, sizeof *w.seen);
    check_wide_node(&w, 0, 0, 0);
    int coverage = 0;
    for (uint32_t k = 0; k < count; k++) coverage += w.seen[k] != 1;
    CHECK(w.bad == 0, "%s: %d wide nodes break an invariant", name, w.bad);
    CHECK(coverage == 0, "%s: %d spheres not in exactly one wide leaf", name, coverage);
    CHECK(w.node_count <= t->node_count, "%s: %u wide nodes from %u", name, w.node_count,
          t->node_count);
    printf("%s: %u wide nodes\n", name, w.node_count);
    free(w.seen);
    free((void *)w.nodes);
}

static void check_tree(const char *name, const struct gpu_sphere *spheres, uint32_t count,
                       uint32_t max_depth) {
    bvh t;
    clock_t start = clock();
    CHECK(bvh_build(spheres, count, max_depth, &t), "%s: build failed", name);
    double seconds = (double)(clock() - start) / CLOCKS_PER_SEC;
    uint32_t *seen = calloc(count, sizeof *seen);
    int bad = 0;
    uint32_t depth = check_root(&t, spheres, seen, count, &bad);
    int coverage = 0;
    for (uint32_t k = 0; k < count; k++) coverage += seen[k] != 1;
    CHECK(bad == 0, "%s: %d nodes break an invariant", name, bad);
    CHECK(coverage == 0, "%s: %d spheres not in exactly one leaf", name, coverage);
    CHECK(depth == t.depth, "%s: depth %u, the build says %u", name, depth, t.depth);
    /* Inner nodes only: a tree of L leaves has L - 1 (one node for a single leaf). */
    CHECK(t.node_count <= (count > 1 ? count - 1 : 1), "%s: %u nodes for %u spheres", name,
          t.node_count, count);
    CHECK(t.depth < max_depth, "%s: depth %u reaches the bound %u", name, t.depth, max_depth);
    printf("%s: %u spheres, %u nodes, depth %u, %.3f s\n", name, count, t.node_count, t.depth,
           seconds);
    check_wide(name, &t, spheres, count);
    /* The parallel build splits big nodes' binning among threads and builds subtrees as tasks;
     * every thread count must give the very tree (nodes, sphere order, depth) of one thread. */
    bvh one;
    CHECK(bvh_build_threads(spheres, count, max_depth, 1, &one), "%s: 1-thread build failed", name);
    const int counts[] = {2, 3, 4, 7, 16};
    for (size_t k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        bvh p;
        CHECK(bvh_build_threads(spheres, count, max_depth, counts[k], &p), "%s: build failed",
              name);
        CHECK(p.node_count == one.node_count && p.depth == one.depth &&
                  !memcmp(p.nodes, one.nodes, (size_t)p.node_count * sizeof *p.nodes) &&
                  !memcmp(p.order, one.order, (size_t)count * sizeof *p.order),
              "%s: the tree on %d threads differs from one thread's", name, counts[k]);
        bvh_free(&p);
    }
    CHECK(one.node_count == t.node_count &&
              !memcmp(one.nodes, t.nodes, (size_t)t.node_count * sizeof *t.nodes),
          "%s: the tree on all processors differs from one thread's", name);
    bvh_free(&one);
    free(seen);
    bvh_free(&t);
}

int main(void) {
    compare_rays(1, 20000);
    compare_rays(7, 20000);
    compare_rays(100, 30000);
    compare_rays(3000, 40000);
    /* Invariants on random input and on inputs that defeat SAH: a geometric progression (every
     * split wants to peel off one sphere), identical centres, and a line of touching spheres. */
    uint32_t n = 200000;
    struct gpu_sphere *sp = calloc(n, sizeof *sp);
    for (uint32_t k = 0; k < n; k++)
        sp[k].center_radius = (tz_vec4){uniform(-100, 100), uniform(-100, 100), uniform(-100, 100),
                                        uniform(0.01f, 1)};
    check_tree("random", sp, n, TZ_BVH_MAX_DEPTH);
    for (uint32_t k = 0; k < 5000; k++)
        sp[k].center_radius =
            (tz_vec4){powf(1.01f, (float)k), 0.0f, 0.0f, 0.001f * powf(1.01f, (float)k)};
    check_tree("geometric", sp, 5000, TZ_BVH_MAX_DEPTH);
    /* Each SAH split peels the largest sphere off (only it falls in the top bin): without the
     * depth guard this is a chain of ~200 levels; with it the build turns to median splits. */
    for (uint32_t k = 0; k < 200; k++) {
        float x = powf(1.2f, (float)k);
        sp[k].center_radius = (tz_vec4){x, 0.0f, 0.0f, 0.05f * x};
    }
    check_tree("exponential", sp, 200, TZ_BVH_MAX_DEPTH);
    for (uint32_t k = 0; k < 1000; k++) sp[k].center_radius = (tz_vec4){1, 2, 3, 0.5f};
    check_tree("coincident", sp, 1000, TZ_BVH_MAX_DEPTH);
    for (uint32_t k = 0; k < 100000; k++) sp[k].center_radius = (tz_vec4){2.0f * (float)k, 0, 0, 1};
    check_tree("line", sp, 100000, TZ_BVH_MAX_DEPTH);
    check_tree("single", sp, 1, TZ_BVH_MAX_DEPTH);
    /* Ties everywhere: centres on a coarse lattice (many share one, and zeros of both signs), so
     * bins are uneven and equal centroids meet the median selection. */
    for (uint32_t k = 0; k < 150000; k++) {
        float x = floorf(uniform(-4, 4)), y = k % 3 ? 0.0f : -0.0f, z = floorf(uniform(-50, 50));
        sp[k].center_radius = (tz_vec4){x, y, z, uniform(0.1f, 2)};
    }
    check_tree("lattice", sp, 150000, TZ_BVH_MAX_DEPTH);
    check_tree("lattice, depth bound 17", sp, 150000, 17);
    /* The depth guard: binned SAH wants ~20 levels for 200,000 random spheres; under a bound of
     * 16 the build must turn to median splits in time (2^15 leaves of 8 hold them all). */
    for (uint32_t k = 0; k < n; k++)
        sp[k].center_radius = (tz_vec4){uniform(-100, 100), uniform(-100, 100), uniform(-100, 100),
                                        uniform(0.01f, 1)};
    check_tree("random, depth bound 16", sp, n, 16);
    free(sp);
    return check_summary("test_bvh");
}
