/* render_common.c: what both back ends share: options from the scene, the progress
 * line, and the metadata (scene digest included) of the parts they render. */
#include <inttypes.h>
#include <stdio.h>

#include "render/part.h"
#include "render/render.h"
#include "util/clock.h"

void render_opts_from_scene(const scene *s, render_opts *opts) {
    *opts = (render_opts){0};
    opts->spp = s->spp;
    opts->seed = s->seed;
    opts->indirect = s->indirect;
    opts->bounces = s->bounces;
    opts->mode = s->mode;
    opts->roulette = s->roulette;
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

/* The scene's digest: every field of the scene and every setting that changes a sample, in a
 * fixed order, field by field (no padding bytes). */
static uint64_t render_digest(const scene *s, const render_opts *o) {
    uint64_t h = 0xcbf29ce484222325u;
    h = digest_vec3(h, s->camera_position);
    h = digest_vec3(h, s->camera_direction);
    h = digest_vec3(h, s->camera_up);
    h = digest_float(h, s->camera_fov);
    h = digest_float(h, s->camera_near);
    h = digest_float(h, s->plane_width);
    h = digest_float(h, s->plane_height);
    h = digest_float(h, s->pixel_size);
    h = digest_int(h, s->width);
    h = digest_int(h, s->height);
    h = digest_vec3(h, s->background);
    h = digest_int(h, s->sphere_count);
    for (int k = 0; k < s->sphere_count; k++) {
        const sphere *p = &s->spheres[k];
        h = digest_vec3(h, p->center);
        h = digest_float(h, p->radius);
        h = digest_int(h, p->material);
        h = digest_vec3(h, p->color);
        h = digest_float(h, p->ks);
        h = digest_float(h, p->alpha);
        h = digest_float(h, p->ior);
        h = digest_vec3(h, p->emission);
    }
    h = digest_int(h, s->light_count);
    for (int k = 0; k < s->light_count; k++) {
        h = digest_vec3(h, s->lights[k].position);
        h = digest_float(h, s->lights[k].power);
        h = digest_vec3(h, s->lights[k].color);
    }
    /* Only scenes with triangles hash them, so that sphere-only scenes keep their digest (and
     * their part files stay mergeable with ones rendered before triangles existed). */
    if (s->triangle_count > 0) {
        h = digest_int(h, s->triangle_count);
        for (int k = 0; k < s->triangle_count; k++) {
            const triangle *t = &s->triangles[k];
            for (int c = 0; c < 3; c++) h = digest_vec3(h, t->v[c]);
            for (int c = 0; c < 3; c++) h = digest_vec3(h, t->n[c]);
            h = digest_int(h, t->smooth);
            h = digest_int(h, t->material);
            h = digest_vec3(h, t->color);
            h = digest_float(h, t->ks);
            h = digest_float(h, t->alpha);
            h = digest_float(h, t->ior);
            h = digest_vec3(h, t->emission);
        }
    }
    int64_t settings[] = {o->spp,      o->seed,      o->mode,     o->bounces,
                          o->indirect, o->no_jitter, o->roulette, o->strategy};
    for (size_t k = 0; k < sizeof settings / sizeof settings[0]; k++)
        h = digest_int(h, settings[k]);
    /* random keeps the digests of before the sampler existed (their parts still merge) */
    if (scene_sampler_of(o->sampler, o->mode) == RENDER_SAMPLER_SOBOL) h = digest_int(h, 1);
    return h;
}

void render_part_meta(const scene *s, const render_opts *opts, part_meta *m) {
    *m = (part_meta){.seed = opts->seed,
                     .spp = (uint32_t)opts->spp,
                     .chunk = TZ_CHUNK_SAMPLES,
                     .width = s->width,
                     .height = s->height,
                     .x1 = s->width,
                     .y1 = s->height};
    snprintf(m->digest, sizeof m->digest, "%016" PRIx64, render_digest(s, opts));
    snprintf(m->mode, sizeof m->mode, "%s", opts->mode == RENDER_MODE_PATH ? "path" : "report");
    snprintf(m->version, sizeof m->version, "%s", TRAZADOR_VERSION);
}
