/* render_cpu.c: the C reference back end: pthreads over tiles of the image, each pixel's samples
 * summed in sample order (compensated, film_sum.h), so the film is bit-identical for every thread
 * count. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "render/cpu/integrator.h"
#include "render/film_sum.h"
#include "render/render.h"
#include "util/clock.h"
#include "util/log.h"

#define TILE_SIZE 16

/* Cache lines are 64 bytes on the processors the packet builds target. */
#define CACHE_LINE 64

typedef struct cpu_job {
    const packed_scene *packed;
    packet_integrator packet; /* the fastest this processor runs */
    film *film;
    int samples;
    int tiles_x, tile_count;
    /* Written by every thread after every tile: on lines of their own, so that the fields above,
     * which every thread reads all the time, are not taken from it by each write. */
    _Alignas(CACHE_LINE) atomic_int next_tile;
    atomic_int tiles_done;
    atomic_ullong nonfinite;
    atomic_ullong rays;
} cpu_job;

static void render_tile(cpu_job *job, int tile) {
    int x0 = (tile % job->tiles_x) * TILE_SIZE, y0 = (tile / job->tiles_x) * TILE_SIZE;
    int x1 = x0 + TILE_SIZE < job->film->width ? x0 + TILE_SIZE : job->film->width;
    int y1 = y0 + TILE_SIZE < job->film->height ? y0 + TILE_SIZE : job->film->height;
    unsigned long long dropped = 0;
    const packet_integrator *pk = &job->packet;
    int width = (int)pk->width;
    for (int j = y0; j < y1; j++) {
        for (int i = x0; i < x1; i += width) {
            uint32_t lanes = (uint32_t)(x1 - i < width ? x1 - i : width);
            float *row = &job->film->accum[((size_t)j * (size_t)job->film->width + (size_t)i) * 4];
            float comp[PACKET_LANES_MAX][3] = {{0.0f}}; /* every sample of these pixels is here */
            /* The sums build up here from the zeros film_init left and reach the film once: a
             * film line can hold pixels of two tiles that two threads render at the same time,
             * and a store per sample there would move the line between their caches at every
             * sample. */
            float sum[PACKET_LANES_MAX][4] = {{0.0f}};
            for (int s = 0; s < job->samples; s++) {
                vec3 l[PACKET_LANES_MAX];
                pk->sample(job->packed, (uint32_t)i, (uint32_t)j, lanes, (uint32_t)s, l);
                for (uint32_t k = 0; k < lanes; k++) {
                    if (!isfinite(l[k].x) || !isfinite(l[k].y) || !isfinite(l[k].z)) {
                        dropped++;
                        continue;
                    }
                    float *px = sum[k];
                    film_sum_add(&px[0], &comp[k][0], l[k].x);
                    film_sum_add(&px[1], &comp[k][1], l[k].y);
                    film_sum_add(&px[2], &comp[k][2], l[k].z);
                    px[3] += 1.0f;
                }
            }
            for (uint32_t k = 0; k < lanes; k++) {
                for (int c = 0; c < 3; c++) sum[k][c] = film_sum_value(sum[k][c], comp[k][c]);
            }
            memcpy(row, sum, (size_t)lanes * sizeof sum[0]);
        }
    }
    if (dropped) atomic_fetch_add(&job->nonfinite, dropped);
}

static void *worker(void *arg) {
    cpu_job *job = arg;
    uint64_t rays_before = integrator_rays_traced();
    for (;;) {
        int tile = atomic_fetch_add(&job->next_tile, 1);
        if (tile >= job->tile_count) {
            atomic_fetch_add(&job->rays, integrator_rays_traced() - rays_before);
            return NULL;
        }
        render_tile(job, tile);
        atomic_fetch_add(&job->tiles_done, 1);
    }
}

static int thread_count(int requested) {
    if (requested > 0) return requested < RENDER_MAX_THREADS ? requested : RENDER_MAX_THREADS;
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > RENDER_MAX_THREADS ? RENDER_MAX_THREADS : (int)n;
}

/* Prints the share of finished tiles on stderr every 0.2 s until every tile is done, which it
 * notices within 5 ms (a render does not wait for the next print). */
static void report_progress(cpu_job *job) {
    struct timespec pause = {0, 5 * 1000 * 1000};
    double start = clock_seconds(), next_print = 0.0;
    double samples = (double)job->film->width * job->film->height * job->samples;
    while (atomic_load(&job->tiles_done) < job->tile_count) {
        double now = clock_seconds();
        if (now >= next_print) {
            double share = (double)atomic_load(&job->tiles_done) / job->tile_count;
            render_progress_print(share, now - start, samples);
            next_print = now + 0.2;
        }
        nanosleep(&pause, NULL);
    }
    render_progress_clear();
}

bool render_cpu(const scene *s, const render_opts *opts, film *f) {
    packed_scene packed;
    double start = clock_seconds();
    if (!scene_pack(s, opts, &packed)) return false;
    scene_pack_report(&packed, opts, start);
    if (!film_init(f, s->width, s->height)) {
        log_error("out of memory for a %d x %d film", s->width, s->height);
        scene_pack_free(&packed);
        return false;
    }
    cpu_job job = {.packed = &packed, .film = f, .samples = opts->samples};
    job.packet = opts->mode == RENDER_MODE_PATH
                     ? integrator_packet_path()
                     : integrator_packet_choose(opts->cpu_build, integrator_packet_walks(&packed));
    log_debug("cpu back end: packet integrator build %s, %u lanes", job.packet.name,
              job.packet.width);
    job.tiles_x = (s->width + TILE_SIZE - 1) / TILE_SIZE;
    job.tile_count = job.tiles_x * ((s->height + TILE_SIZE - 1) / TILE_SIZE);
    atomic_init(&job.next_tile, 0);
    atomic_init(&job.tiles_done, 0);
    atomic_init(&job.nonfinite, 0);
    atomic_init(&job.rays, 0);
    int n = thread_count(opts->threads);
    double render_start = clock_seconds();
    pthread_t threads[RENDER_MAX_THREADS];
    int started = 0;
    while (started < n && pthread_create(&threads[started], NULL, worker, &job) == 0) started++;
    if (started == 0) worker(&job); /* no thread could start: render on this one */
    if (opts->progress) report_progress(&job);
    for (int k = 0; k < started; k++) pthread_join(threads[k], NULL);
    f->nonfinite = atomic_load(&job.nonfinite);
    double render_seconds = clock_seconds() - render_start;
    log_debug("cpu: rendering in %.1f ms on %d threads", render_seconds * 1e3,
              started ? started : 1);
    if (opts->stats) {
        opts->stats->render_seconds = render_seconds;
        opts->stats->rays = atomic_load(&job.rays);
    }
    scene_pack_free(&packed);
    return true;
}
