/* render_common.c: what both back ends share: options from the scene, the progress
 * line, and the metadata (scene digest included) of the parts they render. */
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "render/part.h"
#include "render/render.h"
#include "util/clock.h"
#include "util/threads.h"

void render_opts_from_scene(const scene *s, render_opts *opts) {
    *opts = (render_opts){0};
    opts->spp = s->spp;
    opts->seed = s->seed;
    opts->indirect = s->indirect;
    opts->bounces = s->bounces;
    opts->mode = s->mode;
    opts->roulette = s->roulette;
    opts->light_samples = s->light_samples;
    opts->noise_threshold = s->noise_threshold;
    opts->sampler = s->sampler;
}

void render_progress_print(double share, double seconds, double samples, double deadline) {
    char rate[48] = "", left[64] = "";
    double until = deadline > 0.0 ? deadline - clock_seconds() : -1.0;
    if (seconds > 0.0 && share > 0.0) {
        double rest = seconds * (1.0 - share) / share;
        snprintf(rate, sizeof rate, ", %.2f Msamples/s", share * samples / seconds * 1e-6);
        if (until >= 0.0 && until < rest)
            snprintf(left, sizeof left, ", %.1f s left (time limit)", until);
        else
            snprintf(left, sizeof left, ", %.1f s left", rest);
    }
    fprintf(stderr, "\r\033[Ktrazador: rendering %5.1f%%, %.1f s%s%s", 100.0 * share, seconds, rate,
            left);
}

void render_progress_clear(void) { fprintf(stderr, "\r\033[K"); }

/* FNV-1a over bytes, continued from h. */
static uint64_t digest_bytes(uint64_t h, const void *data, size_t len) {
    const unsigned char *b = data;
    for (size_t k = 0; k < len; k++) h = (h ^ b[k]) * 0x100000001b3u;
    return h;
}
static uint64_t digest_float(uint64_t h, float v) { return digest_bytes(h, &v, sizeof v); }
static uint64_t digest_vec3(uint64_t h, vec3 v) {
    return digest_float(digest_float(digest_float(h, v.x), v.y), v.z);
}
static uint64_t digest_int(uint64_t h, int64_t v) { return digest_bytes(h, &v, sizeof v); }
/* FNV-1a's step over a 32-bit word at once. */
static uint64_t digest_word(uint64_t h, uint32_t w) { return (h ^ w) * 0x100000001b3u; }

/* The floats of material m that the digest holds, in its fixed order (its kind apart). */
#define MATERIAL_FLOATS 9
static void material_floats(const material *m, float out[MATERIAL_FLOATS]) {
    /* A microfacet kind has no ks and alpha: its metallic and roughness take their words, so
     * that the other kinds keep their digests. */
    bool microfacet = material_is_microfacet(m);
    float f[] = {m->color.x,
                 m->color.y,
                 m->color.z,
                 microfacet ? m->metallic : m->ks,
                 microfacet ? m->roughness : m->alpha,
                 m->ior,
                 m->emission.x,
                 m->emission.y,
                 m->emission.z};
    _Static_assert(sizeof f / sizeof f[0] == MATERIAL_FLOATS, "a material's floats");
    memcpy(out, f, sizeof f);
}

/* Triangles a block of the triangles' digest holds. */
#define DIGEST_BLOCK 16384
/* The words a triangle is hashed as. */
#define TRIANGLE_WORDS 29

/* The words of triangle t of s, in a fixed order (a flat face's normals zero). */
static void triangle_words(const scene *s, const triangle *t, uint32_t out[TRIANGLE_WORDS]) {
    static const face_normals flat = {0};
    const face_normals *nf = t->normals != TRIANGLE_FLAT ? &s->normals[t->normals] : &flat;
    const material *m = triangle_material(s, t);
    const vec3 *n = nf->n;
    float f[TRIANGLE_WORDS - 2] = {t->v[0].x, t->v[0].y, t->v[0].z, t->v[1].x, t->v[1].y, t->v[1].z,
                                   t->v[2].x, t->v[2].y, t->v[2].z, n[0].x,    n[0].y,    n[0].z,
                                   n[1].x,    n[1].y,    n[1].z,    n[2].x,    n[2].y,    n[2].z};
    _Static_assert(18 + MATERIAL_FLOATS + 2 == TRIANGLE_WORDS, "a triangle's words");
    material_floats(m, f + 18);
    memcpy(out, f, sizeof f);
    out[TRIANGLE_WORDS - 2] = (uint32_t)(t->normals != TRIANGLE_FLAT);
    out[TRIANGLE_WORDS - 1] = (uint32_t)m->kind;
}

/* Blocks [begin, end) of faces (a scene's triangles or its models' faces), block b hashed into
 * digests[b - begin]. */
typedef struct digest_share {
    const scene *s;
    const triangle *faces;
    size_t count;
    uint64_t *digests;
    size_t begin, end;
} digest_share;

/* A block's words go to four FNV-1a streams in turn (one stream waits on each multiply), which
 * are then folded into one. */
static void *digest_share_run(void *arg) {
    const digest_share *d = arg;
    size_t count = d->count;
    for (size_t block = d->begin; block < d->end; block++) {
        uint64_t lane[4] = {0xcbf29ce484222325u, 0x84222325cbf29ce4u, 0xcbf29ce4u, 0x84222325u};
        size_t last = (block + 1) * DIGEST_BLOCK < count ? (block + 1) * DIGEST_BLOCK : count;
        for (size_t k = block * DIGEST_BLOCK; k < last; k++) {
            uint32_t w[TRIANGLE_WORDS];
            triangle_words(d->s, &d->faces[k], w);
            for (int c = 0; c < TRIANGLE_WORDS; c++) lane[c & 3] = digest_word(lane[c & 3], w[c]);
        }
        uint64_t h = 0xcbf29ce484222325u;
        for (int c = 0; c < 4; c++) h = digest_int(h, (int64_t)lane[c]);
        d->digests[block - d->begin] = h;
    }
    return NULL;
}

/* h continued by count faces of s: blocks hashed on every core, their digests folded in order,
 * the same whatever the thread count (one stream waited on its multiplies). */
static uint64_t digest_triangles(uint64_t h, const scene *s, const triangle *faces, size_t count) {
    size_t blocks = (count + DIGEST_BLOCK - 1) / DIGEST_BLOCK;
    uint64_t *digests = malloc(blocks * sizeof *digests);
    if (!digests) { /* no memory: block by block on this thread */
        for (size_t b = 0; b < blocks; b++) {
            uint64_t one;
            digest_share_run(&(digest_share){s, faces, count, &one, b, b + 1});
            h = digest_int(h, (int64_t)one);
        }
        return h;
    }
    int shares = thread_count(0, THREADS_MAX);
    if ((size_t)shares > blocks) shares = (int)blocks;
    digest_share d[THREADS_MAX];
    for (int t = 0; t < shares; t++) {
        size_t begin = blocks * (size_t)t / (size_t)shares;
        d[t] = (digest_share){
            s, faces, count, digests + begin, begin, blocks * (size_t)(t + 1) / (size_t)shares};
    }
    threads_run(digest_share_run, d, sizeof d[0], shares);
    for (size_t b = 0; b < blocks; b++) h = digest_int(h, (int64_t)digests[b]);
    free(digests);
    return h;
}

/* Whether a face of s with shading normals is a mirror or glass. */
static bool has_smooth_specular_faces(const scene *s) {
    for (int k = 0; k < s->triangle_count; k++) {
        const triangle *t = &s->triangles[k];
        material_kind kind = triangle_material(s, t)->kind;
        if (t->normals != TRIANGLE_FLAT &&
            (kind == TZ_MATERIAL_MIRROR || kind == TZ_MATERIAL_REFRACTIVE))
            return true;
    }
    return false;
}

/* h continued by what textures change: each material's maps, which material each sphere and
 * face takes, the faces' UVs, the slots and the images' texels. */
static uint64_t digest_textures(uint64_t h, const scene *s) {
    for (int k = 0; k < s->material_count; k++)
        for (int c = 0; c < MATERIAL_MAP_COUNT; c++) h = digest_int(h, s->materials[k].maps[c]);
    for (int k = 0; k < s->sphere_count; k++) h = digest_int(h, s->spheres[k].material);
    for (int k = 0; k < s->triangle_count + s->model_face_count; k++) { /* models' after */
        const triangle *t =
            k < s->triangle_count ? &s->triangles[k] : &s->model_faces[k - s->triangle_count];
        h = digest_int(h, t->material);
        if (t->normals == TRIANGLE_FLAT) continue;
        for (int c = 0; c < 3; c++) {
            h = digest_float(h, s->normals[t->normals].uv[c][0]);
            h = digest_float(h, s->normals[t->normals].uv[c][1]);
        }
    }
    for (int k = 0; k < s->slot_count; k++) {
        const texture_slot *sl = &s->slots[k];
        h = digest_int(h, sl->image);
        h = digest_int(h, sl->flags);
        h = digest_float(h, sl->param);
        for (int c = 0; c < 6; c++) h = digest_float(h, sl->transform[c]);
    }
    for (int k = 0; k < s->image_count; k++) {
        const texture_image *t = &s->images[k].texels;
        h = digest_int(h, t->width);
        h = digest_int(h, t->height);
        h = digest_int(h, t->format);
        for (size_t w = 0; w < t->word_count; w++) h = digest_word(h, t->words[w]);
    }
    return h;
}

/* Whether a material of s has an emission or an alpha map. */
static bool has_emission_or_alpha_maps(const scene *s) {
    for (int k = 0; k < s->material_count; k++)
        if (s->materials[k].maps[MAP_EMISSION] || s->materials[k].maps[MAP_ALPHA]) return true;
    return false;
}

/* The scene's digest: every field of the scene and every setting that changes a sample, in a
 * fixed order, field by field (no padding bytes). */
static uint64_t render_digest(const scene *s, const render_opts *o) {
    uint64_t h = 0xcbf29ce484222325u;
    h = digest_vec3(h, s->camera_position);
    h = digest_vec3(h, s->camera_direction);
    h = digest_vec3(h, s->camera_up);
    h = digest_float(h, s->camera_fov);
    h = digest_float(h, s->camera_near);
    /* Only lens and orthographic cameras hash their fields: pinhole scenes keep their digest. */
    if (s->camera_aperture > 0.0f || s->camera_orthographic) {
        h = digest_float(h, s->camera_aperture);
        h = digest_float(h, s->camera_focus);
        h = digest_int(h, s->camera_orthographic);
    }
    h = digest_float(h, s->plane_width);
    h = digest_float(h, s->plane_height);
    h = digest_float(h, s->pixel_size);
    h = digest_int(h, s->width);
    h = digest_int(h, s->height);
    h = digest_vec3(h, s->background);
    h = digest_int(h, s->sphere_count);
    for (int k = 0; k < s->sphere_count; k++) {
        const sphere *p = &s->spheres[k];
        const material *m = sphere_material(s, p);
        float f[MATERIAL_FLOATS];
        material_floats(m, f);
        h = digest_vec3(h, p->center);
        h = digest_float(h, p->radius);
        h = digest_int(h, m->kind);
        for (int c = 0; c < MATERIAL_FLOATS; c++) h = digest_float(h, f[c]);
    }
    h = digest_int(h, s->light_count);
    for (int k = 0; k < s->light_count; k++) {
        h = digest_vec3(h, s->lights[k].position);
        h = digest_float(h, s->lights[k].power);
        h = digest_vec3(h, s->lights[k].color);
        /* only spots and suns hash their shape: scenes of point lights keep their digest */
        if (s->lights[k].kind != LIGHT_POINT) {
            h = digest_int(h, s->lights[k].kind);
            h = digest_vec3(h, s->lights[k].direction);
            h = digest_float(h, s->lights[k].cos_inner);
            h = digest_float(h, s->lights[k].cos_outer);
            h = digest_float(h, s->lights[k].angle);
        }
    }
    /* Only scenes with triangles hash them, so that sphere-only scenes keep their digest (and
     * their part files stay mergeable with ones rendered before triangles existed). */
    if (s->triangle_count > 0) {
        h = digest_int(h, s->triangle_count);
        h = digest_triangles(h, s, s->triangles, (size_t)s->triangle_count);
    }
    /* Only scenes with instances hash their models' faces and the placements. */
    if (s->instance_count > 0) {
        h = digest_int(digest_int(h, 6), s->model_face_count);
        h = digest_triangles(h, s, s->model_faces, (size_t)s->model_face_count);
        for (int k = 0; k < s->model_count; k++)
            h = digest_int(digest_int(h, s->models[k].first), s->models[k].count);
        for (int k = 0; k < s->instance_count; k++)
            h = digest_bytes(digest_int(h, s->instances[k].model), s->instances[k].to_world,
                             sizeof s->instances[k].to_world);
    }
    /* Only scenes with an environment map hash it (its texels, as its radiance), so that the
     * others keep their digest. */
    const environment_map *env = &s->environment;
    if (env->rgb) {
        h = digest_int(h, env->width);
        h = digest_int(h, env->height);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) h = digest_float(h, env->to_map[i][j]);
        size_t n = (size_t)env->width * (size_t)env->height * 3;
        for (size_t k = 0; k < n; k++) h = digest_float(h, env->rgb[k]);
    }
    int64_t settings[] = {o->spp,      o->seed,      o->mode,     o->bounces,
                          o->indirect, o->no_jitter, o->roulette, o->strategy};
    for (size_t k = 0; k < sizeof settings / sizeof settings[0]; k++)
        h = digest_int(h, settings[k]);
    /* random keeps the digests of before the sampler existed (their parts still merge) */
    if (scene_sampler_of(o->sampler, o->mode) == RENDER_SAMPLER_SOBOL) h = digest_int(h, 1);
    /* one light sample keeps the digests of before light_samples existed */
    if (render_light_samples(o) > 1) h = digest_int(h, render_light_samples(o));
    /* the noise threshold decides which samples are drawn; off keeps the digests of before */
    if (o->noise_threshold > 0.0f) h = digest_float(digest_int(h, 4), o->noise_threshold);
    /* Smooth mirror and glass faces once turned rays about their geometric normal: parts rendered
     * then estimate another image, so such scenes hash one more word and those parts do not
     * merge with newer ones; every other scene keeps its digest. */
    if (has_smooth_specular_faces(s)) h = digest_int(h, 2);
    /* Face hits were once placed at the watertight test's distance, not on the face's plane
     * (plane_hit): parts rendered then differ in the last bits, so scenes with faces hash one more
     * word; scenes of spheres alone keep their digest. */
    if (s->triangle_count > 0) h = digest_int(h, 3);
    /* Only textured scenes hash their textures: the others keep their digest. */
    if (s->slot_count > 0) h = digest_textures(h, s);
    /* Emission and alpha maps were once read but not shaded: parts rendered then estimate
     * another image, so scenes with them hash one more word. */
    if (has_emission_or_alpha_maps(s)) h = digest_int(h, 5);
    return h;
}

void render_part_meta(const scene *s, const render_opts *opts, part_meta *m) {
    *m = (part_meta){.seed = opts->seed,
                     .spp = (uint32_t)opts->spp,
                     .chunk = TZ_CHUNK_SAMPLES,
                     .width = s->width,
                     .height = s->height,
                     .x1 = s->width,
                     .y1 = s->height,
                     .adaptive = opts->noise_threshold > 0.0f};
    snprintf(m->digest, sizeof m->digest, "%016" PRIx64, render_digest(s, opts));
    snprintf(m->mode, sizeof m->mode, "%s", opts->mode == RENDER_MODE_PATH ? "path" : "report");
    snprintf(m->version, sizeof m->version, "%s", TRAZADOR_VERSION);
}
