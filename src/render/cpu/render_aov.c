/* render_aov.c: a part's feature images (render.h, render_aov): the first-hit features of the
 * samples of chunk 0 of each pixel (shaders/common/aov.h through the C text), summed in sample
 * order and averaged, rows shared among threads. They depend on the pixel alone, never on the
 * split, the threads or the back end that renders the colour, so parts merge them exactly. */
#include <math.h>
#include <stdatomic.h>
#include <stdlib.h>

#include "image/aov.h"
#include "render/cpu/integrator.h"
#include "render/part.h"
#include "render/render.h"
#include "util/clock.h"
#include "util/log.h"
#include "util/threads.h"

typedef struct aov_job {
    const packed_scene *packed;
    part *part;
    uint32_t samples;
    atomic_int next_row;
} aov_job;

/* Stores the features of region pixel at (image pixel x, y). */
static void aov_pixel(const aov_job *job, size_t at, uint32_t x, uint32_t y) {
    vec3 albedo = v3(0.0f, 0.0f, 0.0f), normal = albedo, position = albedo, emission = albedo;
    float depth = 0.0f;
    uint32_t hits = 0;
    for (uint32_t s = 0; s < job->samples; s++) {
        integrator_aov a = integrator_aov_sample(job->packed, x, y, s);
        albedo = v3_add(albedo, a.albedo);
        emission = v3_add(emission, a.emission);
        if (!a.hit) continue;
        hits++;
        normal = v3_add(normal, a.normal);
        position = v3_add(position, a.position);
        depth += a.depth;
    }
    /* Colours over every sample; where the ray went (misses have none) over the hits. */
    float all = 1.0f / (float)job->samples, hit = hits ? 1.0f / (float)hits : 0.0f;
    vec3 value[AOV_COUNT] = {v3_scale(albedo, all), v3_scale(normal, hit),
                             v3(hits ? depth * hit : INFINITY, 0.0f, 0.0f), v3_scale(position, hit),
                             v3_scale(emission, all)};
    aov_set *a = &job->part->aov;
    for (int k = 0; k < AOV_COUNT; k++) {
        float *out = a->plane[k];
        if (!out) continue;
        int w = aov_channels((aov_kind)k);
        out[(size_t)w * at] = value[k].x;
        if (w == 1) continue;
        out[(size_t)w * at + 1] = value[k].y;
        out[(size_t)w * at + 2] = value[k].z;
    }
}

static void *aov_rows(void *arg) {
    aov_job *job = *(aov_job **)arg;
    const part_meta *m = &job->part->meta;
    int width = m->x1 - m->x0, height = m->y1 - m->y0;
    for (int j; (j = atomic_fetch_add(&job->next_row, 1)) < height;)
        for (int i = 0; i < width; i++)
            aov_pixel(job, (size_t)j * (size_t)width + (size_t)i, (uint32_t)(m->x0 + i),
                      (uint32_t)(m->y0 + j));
    return NULL;
}

bool render_aov(const scene *s, const render_opts *opts, part *p) {
    const part_meta *m = &p->meta;
    size_t pixels = (size_t)(m->x1 - m->x0) * (size_t)(m->y1 - m->y0);
    double start = clock_seconds();
    packed_scene packed;
    if (!aov_alloc(&p->aov, opts->aov, pixels)) return false;
    if (!scene_pack(s, opts, &packed)) {
        aov_free(&p->aov);
        return false;
    }
    aov_job job = {.packed = &packed,
                   .part = p,
                   .samples = m->spp < RENDER_AOV_SAMPLES ? m->spp : RENDER_AOV_SAMPLES};
    atomic_init(&job.next_row, 0);
    aov_job *shares[THREADS_MAX];
    int n = thread_count(opts->threads, THREADS_MAX);
    for (int t = 0; t < n; t++) shares[t] = &job;
    threads_run(aov_rows, shares, sizeof shares[0], n);
    scene_pack_free(&packed);
    log_debug("aov: the feature images of %zu pixels in %.1f ms", pixels,
              (clock_seconds() - start) * 1e3);
    return true;
}
