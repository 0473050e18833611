/* scene_pack.c: fills the shared_layout.h structs from struct scene and checks their layout. */
#include "render/scene_pack.h"

#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "render/bvh.h"
#include "render/scene_pack_instances.h"
#include "util/big_memory.h"
#include "util/clock.h"
#include "util/log.h"

/* std430 in 16-byte groups (vec4s, four scalars): the C structs must have no padding of their own.
 */
_Static_assert(sizeof(tz_vec4) == 16, "vec4 is 16 bytes");
_Static_assert(sizeof(tz_uvec4) == 16, "uvec4 is 16 bytes");
_Static_assert(sizeof(struct gpu_sphere) == 32, "gpu_sphere is 32 bytes");
_Static_assert(offsetof(struct gpu_sphere, center_radius) == 0, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, material) == 16, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, emitter) == 20, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, pad0) == 24, "gpu_sphere layout");
_Static_assert(offsetof(struct gpu_sphere, pad1) == 28, "gpu_sphere layout");
_Static_assert(sizeof(struct gpu_triangle) == 48, "gpu_triangle is 48 bytes");
_Static_assert(offsetof(struct gpu_triangle, v1) == 16, "gpu_triangle layout");
_Static_assert(offsetof(struct gpu_triangle, v2) == 32, "gpu_triangle layout");
_Static_assert(sizeof(struct gpu_material) == 64, "gpu_material is 64 bytes");
_Static_assert(offsetof(struct gpu_material, color_ks) == 0, "gpu_material layout");
_Static_assert(offsetof(struct gpu_material, alpha) == 16, "gpu_material layout");
_Static_assert(offsetof(struct gpu_material, ior) == 20, "gpu_material layout");
_Static_assert(offsetof(struct gpu_material, kind) == 24, "gpu_material layout");
_Static_assert(offsetof(struct gpu_material, reserved0) == 28, "gpu_material layout");
_Static_assert(offsetof(struct gpu_material, emission) == 32, "gpu_material layout");
_Static_assert(offsetof(struct gpu_material, maps) == 48, "gpu_material layout");
_Static_assert(MAP_COLOR == TZ_MAP_COLOR && MAP_EMISSION == TZ_MAP_EMISSION &&
                   MAP_NORMAL == TZ_MAP_NORMAL && MAP_ALPHA == TZ_MAP_ALPHA &&
                   MAP_METALLIC_ROUGHNESS == TZ_MAP_METALLIC_ROUGHNESS &&
                   MAP_ROUGHNESS == TZ_MAP_ROUGHNESS && MAP_METALLIC == TZ_MAP_METALLIC &&
                   MATERIAL_MAP_COUNT <= 8,
               "a material's maps, two to a word of gpu_material.maps");
_Static_assert(sizeof(struct gpu_normals) == 48, "gpu_normals is 48 bytes");
_Static_assert(sizeof(struct gpu_light) == 48, "gpu_light is 48 bytes");
_Static_assert(offsetof(struct gpu_light, shape) == 32, "gpu_light layout");
_Static_assert(offsetof(struct gpu_light, position_power) == 0, "gpu_light layout");
_Static_assert(offsetof(struct gpu_light, color) == 16, "gpu_light layout");
_Static_assert(sizeof(struct gpu_frame) == 240, "gpu_frame is 240 bytes");
_Static_assert(offsetof(struct gpu_frame, instance_count) == 224, "gpu_frame layout");
_Static_assert(sizeof(struct gpu_instance) == 112, "gpu_instance is 112 bytes");
_Static_assert(offsetof(struct gpu_instance, to_world) == 48, "gpu_instance layout");
_Static_assert(offsetof(struct gpu_instance, model) == 96, "gpu_instance layout");
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
_Static_assert(offsetof(struct gpu_frame, triangle_count) == 120, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, env_x) == 128, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, env_z) == 160, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, env_width) == 176, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, env_slot) == 184, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, lens) == 192, "gpu_frame layout");
_Static_assert(offsetof(struct gpu_frame, sun) == 208, "gpu_frame layout");
_Static_assert(sizeof(struct gpu_pass) == 64 + 4 * TZ_PASS_CHUNKS, "gpu_pass is 96 bytes");
_Static_assert(sizeof(struct gpu_pass) <= 128, "gpu_pass fits the push constants of any device");
_Static_assert(offsetof(struct gpu_pass, stack_slot) == 64, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, x0) == 0, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, y0) == 4, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, first_sample) == 8, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, sample_count) == 12, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, group_stride) == 16, "gpu_pass layout");
_Static_assert(offsetof(struct gpu_pass, stack_depth) == 44, "gpu_pass layout");

_Static_assert(sizeof(struct gpu_unrolled) == TZ_UNROLL_MAX_SPHERES * 3 * sizeof(tz_vec4) +
                                                  TZ_UNROLL_MAX_LIGHTS * 2 * sizeof(tz_vec4),
               "gpu_unrolled is its spheres and lights (position_power and color)");
_Static_assert(offsetof(struct gpu_unrolled, lights) == TZ_UNROLL_MAX_SPHERES * 3 * sizeof(tz_vec4),
               "gpu_unrolled layout");
_Static_assert(sizeof(struct gpu_emitter) == 32, "gpu_emitter is 32 bytes");
_Static_assert(offsetof(struct gpu_emitter, primitive_cdf) == 16, "gpu_emitter layout");
_Static_assert(sizeof(struct gpu_bvh_node) == 64, "gpu_bvh_node is 64 bytes");
_Static_assert(offsetof(struct gpu_bvh_node, left_hi) == 16, "gpu_bvh_node layout");
_Static_assert(offsetof(struct gpu_bvh_node, right_lo) == 32, "gpu_bvh_node layout");
_Static_assert(offsetof(struct gpu_bvh_node, right_hi) == 48, "gpu_bvh_node layout");
_Static_assert(sizeof(struct gpu_wide_node) == 64, "gpu_wide_node is 64 bytes");
_Static_assert(offsetof(struct gpu_wide_node, refs) == 16, "gpu_wide_node layout");
_Static_assert(offsetof(struct gpu_wide_node, lo) == 32, "gpu_wide_node layout");
_Static_assert(offsetof(struct gpu_wide_node, hi) == 48, "gpu_wide_node layout");
_Static_assert(TZ_BVH_LEAF_MAX < 1u << (32u - TZ_BVH_COUNT_SHIFT) &&
                   SCENE_MAX_PRIMITIVES - 1u <= TZ_BVH_INDEX_MASK,
               "a leaf's count and first sphere fit a child reference");

/* Sorts the spheres and the scene's own triangles into BVH order and keeps the tree unless no_bvh
 * (the order stays: exact ties go to the lower index, so the same order gives the same image with
 * and without the tree); *triangle_source[t] becomes the scene index of stored triangle t. With
 * instances the tree is kept whatever no_bvh says, its leaves hold them too, and they are packed
 * in its order with their models (pack_instances). False (logged) on out-of-memory. */
static bool pack_bvh(packed_scene *out, const scene *s, uint32_t triangles, bool no_bvh,
                     uint32_t **triangle_source) {
    double start = clock_seconds();
    uint32_t spheres = (uint32_t)s->sphere_count, instances = (uint32_t)s->instance_count;
    bvh tree;
    bvh_box *boxes = NULL;
    if (instances && !pack_instance_boxes(out, s, &boxes)) return false;
    bvh_input in = {out->spheres,
                    spheres,
                    out->triangles,
                    triangles,
                    boxes,
                    instances,
                    spheres + out->frame.triangle_count};
    bool built = bvh_build_primitives(&in, TZ_BVH_MAX_DEPTH, 0, &tree);
    free(boxes);
    if (!built) return false;
    uint32_t *instance_order = big_malloc((instances ? instances : 1) * sizeof *instance_order);
    struct gpu_sphere *sorted = big_calloc(spheres ? spheres : 1, sizeof *sorted);
    struct gpu_triangle *sorted_t = big_calloc(triangles ? triangles : 1, sizeof *sorted_t);
    *triangle_source = big_malloc((triangles ? triangles : 1) * sizeof **triangle_source);
    if (!sorted || !sorted_t || !*triangle_source || !instance_order) {
        log_error("out of memory sorting %u primitives into BVH order", spheres + triangles);
        free(sorted), free(sorted_t), free(*triangle_source), free(instance_order);
        *triangle_source = NULL;
        bvh_free(&tree);
        return false;
    }
    uint32_t ns = 0, nt = 0, ni = 0;
    for (uint32_t k = 0; k < spheres + triangles + instances; k++) {
        uint32_t from = tree.order[k];
        if (from < spheres) {
            sorted[ns++] = out->spheres[from];
        } else if (from >= spheres + triangles) {
            instance_order[ni++] = from - spheres - triangles;
        } else {
            (*triangle_source)[nt] = from - spheres;
            sorted_t[nt++] = out->triangles[from - spheres];
        }
    }
    free(out->spheres);
    out->spheres = sorted;
    memcpy(out->triangles, sorted_t, (size_t)triangles * sizeof *sorted_t); /* models' stay */
    free(sorted_t);
    free(tree.order);
    if (no_bvh && !instances) {
        free(tree.nodes);
    } else {
        out->nodes = tree.nodes;
        out->bvh_depth = tree.depth;
        out->frame.node_count = tree.node_count;
    }
    bool packed = !instances || pack_instances(out, s, instance_order);
    free(instance_order);
    out->bvh_seconds = clock_seconds() - start;
    return packed;
}

/* The material m as the shaders read it: the one packing of a material, a sphere's or a
 * face's. */
static struct gpu_material gpu_material_of(const material *m) {
    /* The microfacet kinds pack metallic as ks and the GGX width roughness^2 as alpha. */
    bool microfacet = material_is_microfacet(m);
    float width = m->roughness * m->roughness;
    return (struct gpu_material){
        .color_ks = vec4_from(m->color, microfacet ? m->metallic : m->ks),
        .alpha = microfacet ? (width > TZ_GGX_MIN_ALPHA ? width : TZ_GGX_MIN_ALPHA) : m->alpha,
        .ior = m->ior,
        .kind = (float)m->kind,
        .emission = vec4_from(m->emission, 0.0f),
        .maps = {m->maps[MAP_COLOR] | m->maps[MAP_EMISSION] << 16,
                 m->maps[MAP_NORMAL] | m->maps[MAP_ALPHA] << 16,
                 m->maps[MAP_METALLIC_ROUGHNESS] | m->maps[MAP_ROUGHNESS] << 16,
                 m->maps[MAP_METALLIC]},
    };
}

/* The scene's materials, in its order (spheres and faces refer to them by the same index). */
static bool pack_materials(packed_scene *out, const scene *s) {
    uint32_t count = (uint32_t)s->material_count;
    out->materials = big_calloc(count ? count : 1, sizeof *out->materials);
    if (!out->materials) return false;
    for (uint32_t k = 0; k < count; k++) out->materials[k] = gpu_material_of(&s->materials[k]);
    out->material_count = count;
    return true;
}

/* The triangles in scene order (v0.w the index of their material, as the scene's) and the
 * normals of the smooth ones; v2.w holds nothing yet (emitters_pack). False on out-of-memory. */
static bool pack_triangles(packed_scene *out, const scene *s) {
    uint32_t flat = (uint32_t)s->triangle_count, smooth = 0;
    uint32_t count = flat + (uint32_t)s->model_face_count; /* the models' faces after the scene's */
    for (uint32_t k = 0; k < count; k++)
        smooth += (k < flat ? s->triangles[k] : s->model_faces[k - flat]).normals != TRIANGLE_FLAT;
    out->triangles = big_calloc(count ? count : 1, sizeof *out->triangles);
    out->normals = big_calloc(smooth ? smooth : 1, sizeof *out->normals);
    if (!out->triangles || !out->normals) return false;
    uint32_t n = 0;
    for (uint32_t k = 0; k < count; k++) {
        const triangle *t = k < flat ? &s->triangles[k] : &s->model_faces[k - flat];
        uint32_t normals = t->normals != TRIANGLE_FLAT ? n : TZ_FLAT;
        if (t->normals != TRIANGLE_FLAT) {
            const vec3 *sn = s->normals[t->normals].n;
            out->normals[n++] = (struct gpu_normals){vec4_from(sn[0], 0.0f), vec4_from(sn[1], 0.0f),
                                                     vec4_from(sn[2], 0.0f)};
        }
        float material_bits, normals_bits;
        memcpy(&material_bits, &t->material, sizeof material_bits);
        memcpy(&normals_bits, &normals, sizeof normals_bits);
        out->triangles[k] =
            (struct gpu_triangle){vec4_from(t->v[0], material_bits),
                                  vec4_from(t->v[1], normals_bits), vec4_from(t->v[2], 0.0f)};
    }
    out->normals_count = smooth;
    return true;
}

/* The corners' structure-of-arrays copy, padded as pack_soa's. */
static bool pack_triangle_soa(packed_scene *out, uint32_t count) {
    size_t n = ((size_t)count + SOA_LANES - 1) / SOA_LANES * SOA_LANES + SOA_LANES;
    out->triangle_soa.v[0] = big_calloc(9 * n, sizeof(float));
    if (!out->triangle_soa.v[0]) return false;
    for (int a = 1; a < 9; a++) out->triangle_soa.v[a] = out->triangle_soa.v[0] + a * n;
    for (uint32_t k = 0; k < count; k++) {
        const tz_vec4 *v[3] = {&out->triangles[k].v0, &out->triangles[k].v1, &out->triangles[k].v2};
        for (int c = 0; c < 3; c++) {
            out->triangle_soa.v[3 * c][k] = v[c]->x;
            out->triangle_soa.v[3 * c + 1][k] = v[c]->y;
            out->triangle_soa.v[3 * c + 2][k] = v[c]->z;
        }
    }
    return true;
}

/* The structure-of-arrays copy, padded by SOA_LANES zeros past every array's end. */
static bool pack_soa(packed_scene *out, uint32_t count) {
    size_t n = ((size_t)count + SOA_LANES - 1) / SOA_LANES * SOA_LANES + SOA_LANES;
    out->sphere_soa.cx = big_calloc(4 * n, sizeof(float));
    if (!out->sphere_soa.cx) return false;
    out->sphere_soa.cy = out->sphere_soa.cx + n;
    out->sphere_soa.cz = out->sphere_soa.cx + 2 * n;
    out->sphere_soa.r = out->sphere_soa.cx + 3 * n;
    for (uint32_t k = 0; k < count; k++) {
        const tz_vec4 *c = &out->spheres[k].center_radius;
        out->sphere_soa.cx[k] = c->x;
        out->sphere_soa.cy[k] = c->y;
        out->sphere_soa.cz[k] = c->z;
        out->sphere_soa.r[k] = c->w;
    }
    return true;
}

bool scene_pack(const scene *s, const render_opts *opts, packed_scene *out) {
    *out = (packed_scene){0};
    uint32_t count = (uint32_t)s->sphere_count;
    /* One zero element when empty keeps every buffer non-empty for Vulkan. */
    out->spheres = big_calloc(count ? count : 1, sizeof *out->spheres);
    out->lights = calloc(s->light_count ? (size_t)s->light_count : 1, sizeof *out->lights);
    if (!out->spheres || !out->lights || !pack_materials(out, s) || !pack_triangles(out, s) ||
        !texture_pack(s, out)) {
        log_error("out of memory packing %u spheres and %d triangles", count, s->triangle_count);
        scene_pack_free(out);
        return false;
    }
    for (uint32_t k = 0; k < count; k++) {
        const sphere *sp = &s->spheres[k];
        out->spheres[k] = (struct gpu_sphere){
            .center_radius = vec4_from(sp->center, sp->radius),
            .material = (float)sp->material,
            .emitter = (float)k, /* emitters_pack */
        };
    }
    /* Camera frame of DESIGN section 3: F forward, R = up x F to the right, U = F x R. */
    vec3 f = v3_normalize(s->camera_direction);
    vec3 r = v3_normalize(v3_cross(s->camera_up, f));
    vec3 u = v3_cross(f, r);
    bool path = opts->mode == RENDER_MODE_PATH;
    uint32_t flags =
        (opts->no_jitter ? 0u : TZ_FLAG_JITTER) |
        (opts->indirect && !path ? TZ_FLAG_INDIRECT : 0u) | (path ? TZ_FLAG_PATH : 0u) |
        (path && opts->roulette ? TZ_FLAG_ROULETTE : 0u) |
        (opts->strategy == PATH_LIGHTS_ONLY ? TZ_FLAG_LIGHTS_ONLY : 0u) |
        (opts->strategy == PATH_BSDF_ONLY ? TZ_FLAG_BSDF_ONLY : 0u) |
        (scene_sampler_of(opts->sampler, opts->mode) == RENDER_SAMPLER_SOBOL ? TZ_FLAG_SOBOL : 0u) |
        (s->triangle_count + s->model_face_count > 0 ? TZ_FLAG_TRIANGLES : 0u) |
        (s->slot_count > 0 ? TZ_FLAG_TEXTURES : 0u) |
        (s->environment.rgb ? TZ_FLAG_ENVIRONMENT : 0u) |
        (scene_has_microfacet(s) ? TZ_FLAG_MICROFACET : 0u) |
        (s->triangle_count + s->model_face_count > 0 && scene_has_cutouts(s) ? TZ_FLAG_CUTOUTS
                                                                             : 0u) |
        (s->camera_aperture > 0.0f ? TZ_FLAG_LENS : 0u) |
        (s->camera_orthographic ? TZ_FLAG_ORTHOGRAPHIC : 0u);
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
        .triangle_count = (uint32_t)(s->triangle_count + s->model_face_count),
        .light_count = (uint32_t)s->light_count,
        .seed = opts->seed,
        .bounces = (uint32_t)opts->bounces,
        .flags = flags,
        .near_distance = s->camera_near,
        .light_samples = (uint32_t)render_light_samples(opts),
        .lens = {s->camera_aperture, s->camera_focus, 0.0f, 0.0f},
    };
    const environment_map *env = &s->environment;
    if (env->rgb) {
        out->frame.env_x = (tz_vec4){env->to_map[0][0], env->to_map[0][1], env->to_map[0][2], 0};
        out->frame.env_y = (tz_vec4){env->to_map[1][0], env->to_map[1][1], env->to_map[1][2], 0};
        out->frame.env_z = (tz_vec4){env->to_map[2][0], env->to_map[2][1], env->to_map[2][2], 0};
        out->frame.env_width = (uint32_t)env->width;
        out->frame.env_height = (uint32_t)env->height;
    }
    uint32_t *triangle_source = NULL;
    double env_mean = 0.0, radius = emitter_scene_radius(s);
    sun_disc sun = lights_pack(s, path, radius, out);
    bool sorted = environment_pack(env, out, &env_mean) &&
                  pack_bvh(out, s, (uint32_t)s->triangle_count, opts->no_bvh, &triangle_source) &&
                  emitters_pack(out, s, path, triangle_source,
                                env_mean > 0.0 ? env_mean * radius * radius : 0.0, &sun);
    free(triangle_source);
    if (sorted && (!pack_soa(out, count) || !pack_triangle_soa(out, out->frame.triangle_count)))
        log_error("out of memory packing %u spheres", count);
    if (!sorted || !out->sphere_soa.cx || !out->triangle_soa.v[0]) {
        scene_pack_free(out);
        return false;
    }
    return true;
}

void scene_pack_unrolled(const packed_scene *p, uint32_t spheres, struct gpu_unrolled *out) {
    for (uint32_t k = 0; k < spheres; k++) {
        const struct gpu_sphere *g = &p->spheres[k];
        const struct gpu_material *m = &p->materials[(uint32_t)g->material];
        out->spheres[3 * k] = g->center_radius;
        out->spheres[3 * k + 1] = m->color_ks;
        out->spheres[3 * k + 2] = (tz_vec4){m->alpha, m->ior, m->kind, g->emitter};
    }
}

void scene_pack_report(const packed_scene *p, const render_opts *opts, double pack_start) {
    if (!opts->stats) return;
    render_stats *st = opts->stats;
    st->pack_seconds = clock_seconds() - pack_start;
    st->bvh_seconds = p->bvh_seconds;
    st->bvh_nodes = p->frame.node_count;
    st->bvh_depth = p->bvh_depth;
    st->scene_bytes = (uint64_t)p->frame.sphere_count * sizeof *p->spheres +
                      (uint64_t)p->frame.triangle_count * sizeof *p->triangles +
                      (uint64_t)p->material_count * sizeof *p->materials +
                      (uint64_t)p->normals_count * sizeof *p->normals +
                      (uint64_t)p->texture_word_count * sizeof *p->texture_words +
                      (uint64_t)p->frame.light_count * sizeof *p->lights +
                      (uint64_t)p->frame.node_count * sizeof *p->nodes +
                      (uint64_t)p->frame.instance_count * sizeof(struct gpu_instance);
    log_debug(
        "scene: %u sphere%s, %u triangle%s (%u smooth, %u material%s), %u BVH node%s (depth %u) "
        "built in %.3f s, %.1f MB for the shaders, packed in %.3f s in all",
        p->frame.sphere_count, p->frame.sphere_count == 1 ? "" : "s", p->frame.triangle_count,
        p->frame.triangle_count == 1 ? "" : "s", p->normals_count, p->material_count,
        p->material_count == 1 ? "" : "s", st->bvh_nodes, st->bvh_nodes == 1 ? "" : "s",
        st->bvh_depth, st->bvh_seconds, (double)st->scene_bytes * 1e-6, st->pack_seconds);
}

void scene_pack_free(packed_scene *p) {
    free(p->spheres);
    free(p->lights);
    free(p->sphere_soa.cx);
    free(p->triangles);
    free(p->materials);
    free(p->normals);
    free(p->texture_words);
    free(p->triangle_soa.v[0]);
    free(p->nodes);
    free(p->emitters);
    free(p->instances);
    free(p->environment);
    *p = (packed_scene){0};
}
