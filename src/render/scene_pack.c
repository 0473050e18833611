/* scene_pack.c: fills the shared_layout.h structs from struct scene and checks their layout. */
#include "render/scene_pack.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "render/bvh.h"
#include "util/clock.h"
#include "util/log.h"

/* params.z stores the material as the shaders' TZ_MATERIAL_* number. */
_Static_assert(MATERIAL_LAMBERTIAN == TZ_MATERIAL_LAMBERTIAN &&
                   MATERIAL_PHONG == TZ_MATERIAL_PHONG && MATERIAL_MIRROR == TZ_MATERIAL_MIRROR &&
                   MATERIAL_REFRACTIVE == TZ_MATERIAL_REFRACTIVE,
               "material numbers");
/* std430 in 16-byte groups (vec4s, four scalars): the C structs must have no padding of their own.
 */
_Static_assert(sizeof(tz_vec4) == 16, "vec4 is 16 bytes");
_Static_assert(sizeof(tz_uvec4) == 16, "uvec4 is 16 bytes");
_Static_assert(sizeof(struct gpu_sphere) == 48, "gpu_sphere is 48 bytes");
_Static_assert(offsetof(struct gpu_sphere, center_radius) == 0, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, color_ks) == 16, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, params) == 32, "gpu_sphere layout");
_Static_assert(sizeof(struct gpu_light) == 32, "gpu_light is 32 bytes");
_Static_assert(offsetof(struct gpu_light, position_power) == 0, "gpu_light layout");
_Static_assert(offsetof(struct gpu_light, color) == 16, "gpu_light layout");
_Static_assert(sizeof(struct gpu_frame) == 128, "gpu_frame is 128 bytes");
_Static_assert(offsetof(struct gpu_frame, origin) == 0, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, right) == 16, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, up) == 32, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, forward) == 48, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, background) == 64, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, width) == 80, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, height) == 84, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, sphere_count) == 88, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, light_count) == 92, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, seed) == 96, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, bounces) == 100, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, flags) == 104, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, node_count) == 108, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, near_distance) == 112, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, emitter_count) == 116, "gpu_frame layout");
_Static_assert(sizeof(struct gpu_pass) == 64 + 4 * TZ_PASS_CHUNKS, "gpu_pass is 96 bytes");
_Static_assert(sizeof(struct gpu_pass) <= 128, "gpu_pass fits the push constants of any device");
_Static_assert(offsetof(struct gpu_pass, stack_slot) == 64, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, x0) == 0, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, y0) == 4, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, first_sample) == 8, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, sample_count) == 12, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, group_stride) == 16, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, stack_depth) == 44, "gpu_pass layout");

_Static_assert(sizeof(struct gpu_unrolled) == TZ_UNROLL_MAX_SPHERES * sizeof(struct gpu_sphere) +
                                                  TZ_UNROLL_MAX_LIGHTS * sizeof(struct gpu_light),
               "gpu_unrolled is its spheres and lights");
_Static_assert(offsetof(struct gpu_unrolled, lights) ==
                   TZ_UNROLL_MAX_SPHERES * sizeof(struct gpu_sphere),
               "gpu_unrolled layout");
_Static_assert(sizeof(struct gpu_emitter) == 32, "gpu_emitter is 32 bytes");
_Static_assert(offsetof(struct gpu_emitter, sphere_cdf) == 16, "gpu_emitter layout");
_Static_assert(sizeof(struct gpu_bvh_node) == 64, "gpu_bvh_node is 64 bytes");
_Static_assert(offsetof(struct gpu_bvh_node, left_hi) == 16, "gpu_bvh_node layout");
_Static_assert(offsetof(struct gpu_bvh_node, right_lo) == 32, "gpu_bvh_node layout");
_Static_assert(offsetof(struct gpu_bvh_node, right_hi) == 48, "gpu_bvh_node layout");
_Static_assert(TZ_BVH_LEAF_MAX < 1u << (32u - TZ_BVH_COUNT_SHIFT) &&
                   SCENE_MAX_SPHERES - 1u <= TZ_BVH_INDEX_MASK,
               "a leaf's count and first sphere fit a child reference");

static tz_vec4 vec4_from(vec3 v, float w) { return (tz_vec4){v.x, v.y, v.z, w}; }

/* Sorts the spheres into BVH order and keeps the tree unless no_bvh (the order stays: exact ties
 * go to the lower index, so the same order gives the same image with and without the tree);
 * false (logged) on out-of-memory. */
static bool pack_bvh(packed_scene *out, uint32_t count, bool no_bvh) {
    double start = clock_seconds();
    bvh tree;
    if (!bvh_build(out->spheres, count, TZ_BVH_MAX_DEPTH, &tree)) return false;
    struct gpu_sphere *sorted = malloc((count ? count : 1) * sizeof *sorted);
    if (!sorted) {
        log_error("out of memory sorting %u spheres into BVH order", count);
        bvh_free(&tree);
        return false;
    }
    for (uint32_t k = 0; k < count; k++) sorted[k] = out->spheres[tree.order[k]];
    free(out->spheres);
    out->spheres = sorted;
    free(tree.order);
    if (no_bvh) {
        free(tree.nodes);
    } else {
        out->nodes = tree.nodes;
        out->bvh_depth = tree.depth;
        out->frame.node_count = tree.node_count;
    }
    out->bvh_seconds = clock_seconds() - start;
    return true;
}

/* The mean of an emission's channels, as double. */
static double emission_mean(vec3 e) { return ((double)e.x + e.y + e.z) / 3.0; }

/* The emitters of path mode from the spheres in their final (BVH) order, whose params.w holds
 * their index in the scene until here: each emitter is picked in proportion to its power
 * r^2 mean(Le), the shares summed in double; params.w becomes the emitter's slot + 1, or 0.
 * False (logged) on out-of-memory. */
static bool pack_emitters(packed_scene *out, const scene *sc, bool path_mode) {
    uint32_t count = (uint32_t)sc->sphere_count, n = 0;
    double total = 0.0;
    for (uint32_t k = 0; path_mode && k < count; k++) {
        const sphere *sp = &sc->spheres[k];
        double power = (double)sp->radius * sp->radius * emission_mean(sp->emission);
        if (power > 0.0) total += power, n++;
    }
    out->emitters = calloc(n ? n : 1, sizeof *out->emitters);
    if (!out->emitters) {
        log_error("out of memory packing %u emitters", n);
        return false;
    }
    double running = 0.0;
    uint32_t slot = 0;
    for (uint32_t k = 0; k < count; k++) {
        struct gpu_sphere *g = &out->spheres[k];
        const sphere *sp = &sc->spheres[(uint32_t)g->params.w];
        double power = (double)sp->radius * sp->radius * emission_mean(sp->emission);
        g->params.w = 0.0f;
        if (!path_mode || !(power > 0.0)) continue;
        running += power;
        float index_bits;
        memcpy(&index_bits, &k, sizeof index_bits);
        out->emitters[slot] = (struct gpu_emitter){
            .emission_pick = vec4_from(sp->emission, (float)(power / total)),
            .sphere_cdf = {index_bits, slot + 1 == n ? 1.0f : (float)(running / total), 0, 0},
        };
        g->params.w = (float)++slot;
    }
    out->frame.emitter_count = n;
    return true;
}

/* The structure-of-arrays copy, padded by SOA_LANES zeros past every array's end. */
static bool pack_soa(packed_scene *out, uint32_t count) {
    size_t n = ((size_t)count + SOA_LANES - 1) / SOA_LANES * SOA_LANES + SOA_LANES;
    out->soa.cx = calloc(4 * n, sizeof(float));
    if (!out->soa.cx) return false;
    out->soa.cy = out->soa.cx + n;
    out->soa.cz = out->soa.cx + 2 * n;
    out->soa.r = out->soa.cx + 3 * n;
    for (uint32_t k = 0; k < count; k++) {
        const tz_vec4 *c = &out->spheres[k].center_radius;
        out->soa.cx[k] = c->x;
        out->soa.cy[k] = c->y;
        out->soa.cz[k] = c->z;
        out->soa.r[k] = c->w;
    }
    return true;
}

bool scene_pack(const scene *s, const render_opts *opts, packed_scene *out) {
    *out = (packed_scene){0};
    uint32_t count = (uint32_t)s->sphere_count;
    /* One zero element when empty keeps every buffer non-empty for Vulkan. */
    out->spheres = calloc(count ? count : 1, sizeof *out->spheres);
    out->lights = calloc(s->light_count ? (size_t)s->light_count : 1, sizeof *out->lights);
    if (!out->spheres || !out->lights) {
        log_error("out of memory packing %u spheres", count);
        scene_pack_free(out);
        return false;
    }
    for (uint32_t k = 0; k < count; k++) {
        const sphere *sp = &s->spheres[k];
        out->spheres[k] = (struct gpu_sphere){
            .center_radius = vec4_from(sp->center, sp->radius),
            .color_ks = vec4_from(sp->color, sp->ks),
            .params = {sp->alpha, sp->ior, (float)sp->material, (float)k}, /* pack_emitters */
        };
    }
    for (int k = 0; k < s->light_count; k++) {
        const light *l = &s->lights[k];
        out->lights[k] = (struct gpu_light){
            .position_power = vec4_from(l->position, l->power),
            .color = vec4_from(l->color, 0.0f),
        };
    }
    /* Camera frame of DESIGN section 3: F forward, R = up x F to the right, U = F x R. */
    vec3 f = v3_normalize(s->camera_direction);
    vec3 r = v3_normalize(v3_cross(s->camera_up, f));
    vec3 u = v3_cross(f, r);
    bool path = opts->mode == RENDER_MODE_PATH;
    uint32_t flags = (opts->no_jitter ? 0u : TZ_FLAG_JITTER) |
                     (opts->indirect && !path ? TZ_FLAG_INDIRECT : 0u) |
                     (path ? TZ_FLAG_PATH : 0u) | (path && opts->roulette ? TZ_FLAG_ROULETTE : 0u) |
                     (opts->strategy == PATH_LIGHTS_ONLY ? TZ_FLAG_LIGHTS_ONLY : 0u) |
                     (opts->strategy == PATH_BSDF_ONLY ? TZ_FLAG_BSDF_ONLY : 0u);
    /* The plane's distance: 2 x width (the seed's), or what the field of view asks. */
    float distance = s->camera_fov > 0.0f
                         ? (float)(0.5 * s->plane_width /
                                   tan(0.5 * s->camera_fov * (3.14159265358979323846 / 180.0)))
                         : 2.0f * s->plane_width;
    out->frame = (struct gpu_frame){
        .origin = vec4_from(s->camera_position, s->pixel_size),
        .right = vec4_from(r, -0.5f * s->plane_width),
        .up = vec4_from(u, 0.5f * s->plane_height),
        .forward = vec4_from(f, distance),
        .background = vec4_from(s->background, 0.0f),
        .width = (uint32_t)s->width,
        .height = (uint32_t)s->height,
        .sphere_count = (uint32_t)s->sphere_count,
        .light_count = (uint32_t)s->light_count,
        .seed = opts->seed,
        .bounces = (uint32_t)opts->bounces,
        .flags = flags,
        .near_distance = s->camera_near,
    };
    bool sorted = pack_bvh(out, count, opts->no_bvh) && pack_emitters(out, s, path); /* logged */
    if (sorted && !pack_soa(out, count)) log_error("out of memory packing %u spheres", count);
    if (!sorted || !out->soa.cx) {
        scene_pack_free(out);
        return false;
    }
    return true;
}

void scene_pack_report(const packed_scene *p, const render_opts *opts, double pack_start) {
    if (!opts->stats) return;
    render_stats *st = opts->stats;
    st->pack_seconds = clock_seconds() - pack_start;
    st->bvh_seconds = p->bvh_seconds;
    st->bvh_nodes = p->frame.node_count;
    st->bvh_depth = p->bvh_depth;
    st->scene_bytes = (uint64_t)p->frame.sphere_count * sizeof *p->spheres +
                      (uint64_t)p->frame.light_count * sizeof *p->lights +
                      (uint64_t)p->frame.node_count * sizeof *p->nodes;
    log_debug(
        "scene: %u sphere%s, %u BVH node%s (depth %u) built in %.3f s, %.1f MB for the "
        "shaders, packed in %.3f s in all",
        p->frame.sphere_count, p->frame.sphere_count == 1 ? "" : "s", st->bvh_nodes,
        st->bvh_nodes == 1 ? "" : "s", st->bvh_depth, st->bvh_seconds,
        (double)st->scene_bytes * 1e-6, st->pack_seconds);
}

void scene_pack_free(packed_scene *p) {
    free(p->spheres);
    free(p->lights);
    free(p->soa.cx);
    free(p->nodes);
    free(p->emitters);
    *p = (packed_scene){0};
}
