/* render_cpu.c: the C reference back end: pthreads over tiles of a part's region, pass after pass
 * of whole chunks of samples; each chunk of a pixel summed in sample order (compensated,
 * common/film_sum.h) and pushed on the pixel's stack of chunk-tree blocks (chunk_tree.h), as
 * shaders/trace.comp does, so the sums are bit-identical for every thread count and split. */
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "common/adaptive.h"
#include "common/film_sum.h"
#include "render/chunk_tree.h"
#include "render/chunk_values.h"
#include "render/cpu/integrator.h"
#include "render/part.h"
#include "render/pass_loop.h"
#include "render/render.h"
#include "util/big_memory.h"
#include "util/clock.h"
#include "util/log.h"
#include "util/threads.h"

/* The side of the squares of pixels the threads take in turn (the Vulkan back end plans its own
 * tiles: vk_pass_plan.h). */
#define CPU_TILE_SIZE 16

/* Cache lines are 64 bytes on the processors the packet builds target. */
#define CACHE_LINE 64

typedef struct cpu_job {
    const packed_scene *packed;
    packet_integrator packet; /* the fastest this processor runs */
    /* The one-sample build of the mode: integrator_report_sample or integrator_path_sample. */
    vec3 (*one)(const packed_scene *p, uint32_t i, uint32_t j, uint32_t sample_index);
    part *part;
    int width, height; /* the region */
    /* The pass: chunks first_chunk to first_chunk + chunks - 1, chunk k placed at top[k] with
     * merges[k] merges after it; the stack holds old_count blocks before and new_count after. */
    uint32_t first_chunk, chunks;
    const int *top, *merges;
    int old_count, new_count;
    /* Where the pass writes: the part itself, or (with a stop flag, so that a pass can be
     * abandoned with the part as before it) planes of its own, swapped in once it is done. */
    float *out_block[CHUNK_STACK_MAX];
    uint32_t *out_count;
    float *out_adaptive; /* the noise threshold's state (part.adaptive); NULL when off */
    float *spare[CHUNK_STACK_MAX];
    uint32_t *spare_count;
    float *spare_adaptive;
    float threshold;             /* render_opts.noise_threshold */
    volatile sig_atomic_t *stop; /* NULL: never */
    int tiles_x, tile_count;
    /* Written by every thread after every tile: on lines of their own, so that the fields above,
     * which every thread reads all the time, are not taken from it by each write. */
    _Alignas(CACHE_LINE) atomic_int next_tile;
    atomic_int tiles_done;
    atomic_ullong nonfinite;
    atomic_ullong rays;
} cpu_job;

/* A packet of a noise threshold's render draws its lanes one by one once at most one in this
 * many is still sampled. */
#define ALONE_SHARE 4u

/* The most chunks a path build's run takes at once: the longer a run, the less of it goes by
 * with lanes idle at its end. */
#define RUN_CHUNKS 4

/* Renders the pass's chunks of `lanes` pixels of region row j from column i: loads their stacks,
 * pushes each chunk's compensated sum, stores the stacks back. The sums build up in locals and
 * reach the part once: a line of the part can hold pixels of two tiles that two threads render
 * at the same time, and a store per sample there would move it between their caches. Returns the
 * non-finite samples. */
static unsigned long long render_lanes(cpu_job *job, int i, int j, uint32_t lanes) {
    const packet_integrator *pk = &job->packet;
    part *p = job->part;
    size_t at = (size_t)j * (size_t)job->width + (size_t)i;
    float value[PACKET_LANES_MAX][CHUNK_STACK_MAX][3];
    for (uint32_t k = 0; k < lanes; k++)
        for (int b = 0; b < job->old_count; b++)
            for (int c = 0; c < 3; c++) value[k][b][c] = p->block[b][3 * (at + k) + c];
    uint32_t x = (uint32_t)(p->meta.x0 + i), y = (uint32_t)(p->meta.y0 + j);
    unsigned long long dropped = 0;
    uint32_t counted[PACKET_LANES_MAX] = {0};
    /* The noise threshold's state of each lane: its odd chunks' sum, the chunk it stopped at. */
    vec3 odd[PACKET_LANES_MAX];
    uint32_t stopped[PACKET_LANES_MAX] = {0};
    for (uint32_t k = 0; p->adaptive && k < lanes; k++) {
        const float *a = &p->adaptive[4 * (at + k)];
        odd[k] = v3(a[0], a[1], a[2]);
        stopped[k] = (uint32_t)a[3];
    }
    uint32_t run_chunks = p->adaptive ? 1u : RUN_CHUNKS; /* each chunk is decided on its own */
    /* A path build renders up to RUN_CHUNKS chunks' samples as one run (a lane whose path ends
     * takes the next sample); they are summed in sample order, chunk by chunk, all the same. */
    vec3 run[RUN_CHUNKS * TZ_CHUNK_SAMPLES * PACKET_LANES_MAX];
    uint32_t run_first = 0;
    for (uint32_t n = 0; n < job->chunks; n++) {
        uint32_t first = (job->first_chunk + n) * TZ_CHUNK_SAMPLES;
        uint32_t end =
            p->meta.spp - first < TZ_CHUNK_SAMPLES ? p->meta.spp : first + TZ_CHUNK_SAMPLES;
        vec3 sum[PACKET_LANES_MAX], comp[PACKET_LANES_MAX];
        for (uint32_t k = 0; k < lanes; k++) sum[k] = comp[k] = v3(0.0f, 0.0f, 0.0f);
        uint32_t chunk = job->first_chunk + n, sampled = 0;
        for (uint32_t k = 0; k < lanes; k++) {
            if (p->adaptive && !stopped[k] &&
                !adaptive_goes_on(chunk_stack_total(value[k], (uint32_t)job->top[n]), odd[k], chunk,
                                  job->threshold))
                stopped[k] = chunk;
            sampled += !stopped[k];
        }
        /* A noise threshold's few lanes left are drawn alone by the one-sample build (bit for bit
         * the packet's): a packet would draw every lane. */
        bool alone = sampled * ALONE_SHARE <= lanes;
        if (!pk->samples) run_first = first; /* one sample of all lanes at a time */
        if (pk->samples && n % run_chunks == 0 && sampled && !alone) {
            uint32_t last = n + run_chunks < job->chunks ? n + run_chunks : job->chunks;
            uint32_t run_end = (job->first_chunk + last) * TZ_CHUNK_SAMPLES;
            run_end = run_end < p->meta.spp ? run_end : p->meta.spp;
            run_first = first;
            pk->samples(job->packed, x, y, lanes, first, run_end - first, run);
        }
        for (uint32_t s = first; sampled && s < end; s++) {
            vec3 lone[PACKET_LANES_MAX];
            vec3 *l = alone ? lone : run + (size_t)(s - run_first) * lanes;
            for (uint32_t k = 0; alone && k < lanes; k++)
                if (!stopped[k]) l[k] = job->one(job->packed, x + k, y, s);
            if (!pk->samples && !alone) pk->sample(job->packed, x, y, lanes, s, l);
            for (uint32_t k = 0; k < lanes; k++) {
                if (stopped[k]) continue; /* its samples are not drawn: zero */
                if (!sample_finite(l[k])) {
                    dropped++;
                    continue;
                }
                film_sum_add(&sum[k], &comp[k], l[k]);
                counted[k]++;
            }
        }
        for (uint32_t k = 0; k < lanes; k++) {
            vec3 v = film_sum_value(sum[k], comp[k]);
            chunk_push(value[k], (uint32_t)job->top[n], (uint32_t)job->merges[n], v);
            if (p->adaptive && !stopped[k] && chunk % 2u == 1u) odd[k] = v3_add(odd[k], v);
        }
    }
    for (uint32_t k = 0; p->adaptive && k < lanes; k++) {
        float *a = &job->out_adaptive[4 * (at + k)];
        a[0] = odd[k].x, a[1] = odd[k].y, a[2] = odd[k].z, a[3] = (float)stopped[k];
    }
    for (uint32_t k = 0; k < lanes; k++) {
        for (int b = 0; b < job->new_count; b++)
            for (int c = 0; c < 3; c++) job->out_block[b][3 * (at + k) + c] = value[k][b][c];
        job->out_count[at + k] = p->count[at + k] + counted[k];
    }
    return dropped;
}

static void render_tile(cpu_job *job, int tile) {
    int x0 = (tile % job->tiles_x) * CPU_TILE_SIZE, y0 = (tile / job->tiles_x) * CPU_TILE_SIZE;
    int x1 = x0 + CPU_TILE_SIZE < job->width ? x0 + CPU_TILE_SIZE : job->width;
    int y1 = y0 + CPU_TILE_SIZE < job->height ? y0 + CPU_TILE_SIZE : job->height;
    unsigned long long dropped = 0;
    int width = (int)job->packet.width;
    for (int j = y0; j < y1; j++)
        for (int i = x0; i < x1; i += width)
            dropped += render_lanes(job, i, j, (uint32_t)(x1 - i < width ? x1 - i : width));
    if (dropped) atomic_fetch_add(&job->nonfinite, dropped);
}

static void *worker(void *arg) {
    cpu_job *job = arg;
    uint64_t rays_before = integrator_rays_traced();
    for (;;) {
        if (job->stop && *job->stop) break; /* the pass is abandoned */
        int tile = atomic_fetch_add(&job->next_tile, 1);
        if (tile >= job->tile_count) break;
        render_tile(job, tile);
        atomic_fetch_add(&job->tiles_done, 1);
    }
    atomic_fetch_add(&job->rays, integrator_rays_traced() - rays_before);
    return NULL;
}

/* The progress line's scale: samples a pixel rendered before this pass, in it and in all. */
typedef struct cpu_progress {
    double start, done, pass, total, pixels, deadline;
} cpu_progress;

/* Prints the share of finished tiles on stderr every 0.2 s until every tile is done, which it
 * notices within 5 ms (a render does not wait for the next print). */
static void report_progress(cpu_job *job, const cpu_progress *pr) {
    struct timespec pause = {0, 5 * 1000 * 1000};
    double next_print = 0.0;
    while (atomic_load(&job->tiles_done) < job->tile_count && !(job->stop && *job->stop)) {
        double now = clock_seconds();
        if (now >= next_print) {
            double done =
                pr->done + pr->pass * atomic_load(&job->tiles_done) / (double)job->tile_count;
            render_progress_print(done / pr->total, now - pr->start, pr->pixels * pr->total,
                                  pr->deadline);
            next_print = now + 0.2;
        }
        nanosleep(&pause, NULL);
    }
}

/* Runs one pass over every tile on n threads; the threads that ran (0: this one alone). */
static int run_pass(cpu_job *job, int n, bool progress, const cpu_progress *pr) {
    atomic_store(&job->next_tile, 0);
    atomic_store(&job->tiles_done, 0);
    pthread_t threads[RENDER_MAX_THREADS];
    int started = 0;
    while (started < n && pthread_create(&threads[started], NULL, worker, job) == 0) started++;
    if (started == 0) worker(job); /* no thread could start: render on this one */
    if (progress) report_progress(job, pr);
    for (int k = 0; k < started; k++) pthread_join(threads[k], NULL);
    return started;
}

/* Lays out the pass of `chunks` chunks from the part's stack: where each goes, and room for the
 * blocks the stack then has; false (logged) on out of memory. */
static bool plan_pass(cpu_job *job, chunk_stack *shape, uint32_t chunks, int *top, int *merges) {
    part *p = job->part;
    size_t n = (size_t)job->width * (size_t)job->height;
    job->first_chunk = shape->end;
    job->chunks = chunks;
    job->old_count = shape->count;
    for (uint32_t k = 0; k < chunks; k++) {
        top[k] = shape->count;
        merges[k] = chunk_stack_push(shape, (chunk_block){0, job->first_chunk + k});
    }
    job->new_count = shape->count;
    for (int b = 0; b < shape->count; b++)
        if (!p->block[b] && !(p->block[b] = big_malloc(n * 3 * sizeof(float)))) {
            log_error("out of memory for a part of %zu pixels", n);
            return false;
        }
    for (int b = 0; b < shape->count; b++) job->out_block[b] = p->block[b];
    job->out_count = p->count;
    job->out_adaptive = p->adaptive;
    if (!job->stop) return true;
    if (p->adaptive && !job->spare_adaptive &&
        !(job->spare_adaptive = big_malloc(n * 4 * sizeof(float)))) {
        log_error("out of memory for a part of %zu pixels", n);
        return false;
    }
    if (p->adaptive) job->out_adaptive = job->spare_adaptive;
    for (int b = 0; b < shape->count; b++)
        if (!job->spare[b] && !(job->spare[b] = big_malloc(n * 3 * sizeof(float)))) {
            log_error("out of memory for a part of %zu pixels", n);
            return false;
        }
    if (!job->spare_count && !(job->spare_count = big_malloc(n * sizeof *job->spare_count))) {
        log_error("out of memory for a part of %zu pixels", n);
        return false;
    }
    for (int b = 0; b < shape->count; b++) job->out_block[b] = job->spare[b];
    job->out_count = job->spare_count;
    return true;
}

/* Makes a finished pass's planes the part's (the part's old ones the spares); nothing to do
 * when the pass wrote the part itself. */
static void swap_in(cpu_job *job) {
    part *p = job->part;
    if (!job->stop) return;
    for (int b = 0; b < job->new_count; b++) {
        float *old = p->block[b];
        p->block[b] = job->spare[b];
        job->spare[b] = old;
    }
    uint32_t *old = p->count;
    p->count = job->spare_count;
    job->spare_count = old;
    float *old_adaptive = p->adaptive;
    p->adaptive = job->spare_adaptive;
    job->spare_adaptive = old_adaptive;
}

/* What the CPU back end's passes share across pass_loop_run's calls. */
typedef struct cpu_passes {
    cpu_job *job;
    int *top, *merges; /* the pass's plan: where each chunk goes on the stack */
    int threads, ran;  /* threads to start, and the last pass's */
    bool progress;
    cpu_progress *pr;
    uint32_t begin; /* the chunk the render began at */
} cpu_passes;

/* pass_backend.run: plans and renders a pass, its planes swapped into the part when it is done,
 * or the part left as it was when it was abandoned. */
static pass_result cpu_run_pass(void *user, part *p, uint32_t first, uint32_t chunks) {
    cpu_passes *c = user;
    cpu_job *job = c->job;
    chunk_stack shape = p->stack; /* ends at chunk `first` */
    if (!plan_pass(job, &shape, chunks, c->top, c->merges)) return PASS_FAILED;
    job->top = c->top;
    job->merges = c->merges;
    c->pr->done = (double)(part_sample_of(p, first) - part_sample_of(p, c->begin));
    c->pr->pass = (double)(part_sample_of(p, first + chunks) - part_sample_of(p, first));
    c->ran = run_pass(job, c->threads, c->progress, c->pr);
    bool abandoned = atomic_load(&job->tiles_done) < job->tile_count;
    if (abandoned) {
        atomic_store(&job->nonfinite, 0);
    } else {
        swap_in(job);
        p->stack = shape;
        p->meta.sample_end = part_sample_of(p, shape.end);
        p->meta.nonfinite += atomic_exchange(&job->nonfinite, 0);
    }
    for (int b = p->stack.count; b < CHUNK_STACK_MAX; b++) {
        free(p->block[b]);
        p->block[b] = NULL;
    }
    return abandoned ? PASS_ABANDONED : PASS_DONE;
}

/* pass_backend.sync: nothing to do, every pass writes the part itself. */
static bool cpu_sync(void *user, part *p, uint32_t done, pass_result result) {
    (void)user, (void)p, (void)done, (void)result;
    return true;
}

/* Adds to part p the samples up to sample_end (render_backend.render_part); false on failure
 * (logged). */
static bool render_cpu_part(const scene *s, const render_opts *opts, part *p, uint32_t sample_end) {
    /* Samples of another back end differ by rounding: going on from them would mix the two. */
    if (p->meta.backend[0] && strcmp(p->meta.backend, "cpu")) {
        log_error(
            "the part to go on from was rendered by the %s back end, and this render by the cpu "
            "back end: the two differ by rounding, so their samples do not mix",
            p->meta.backend);
        return false;
    }
    snprintf(p->meta.backend, sizeof p->meta.backend, "cpu");
    packed_scene packed;
    double start = clock_seconds();
    if (!scene_pack(s, opts, &packed)) return false;
    scene_pack_report(&packed, opts, start);
    cpu_job job = {
        .packed = &packed,
        .part = p,
        .threshold = opts->noise_threshold,
        .one = opts->mode == RENDER_MODE_PATH ? integrator_path_sample : integrator_report_sample,
        .width = p->meta.x1 - p->meta.x0,
        .height = p->meta.y1 - p->meta.y0};
    const char *build = opts->cpu_build;
    job.packet = opts->mode == RENDER_MODE_PATH
                     ? integrator_path_choose(build, integrator_packet_walks(&packed))
                     : integrator_packet_choose(build, integrator_packet_walks(&packed));
    log_debug("cpu back end: packet integrator build %s, %u lanes", job.packet.name,
              job.packet.width);
    job.tiles_x = (job.width + CPU_TILE_SIZE - 1) / CPU_TILE_SIZE;
    job.tile_count = job.tiles_x * ((job.height + CPU_TILE_SIZE - 1) / CPU_TILE_SIZE);
    atomic_init(&job.next_tile, 0);
    atomic_init(&job.tiles_done, 0);
    atomic_init(&job.nonfinite, 0);
    atomic_init(&job.rays, 0);
    uint32_t end_chunk = part_chunk_of(p, sample_end);
    uint32_t begin = p->stack.end;
    int *top = malloc((end_chunk - begin + 1u) * sizeof *top);
    int *merges = malloc((end_chunk - begin + 1u) * sizeof *merges);
    bool ok = top && merges;
    if (!ok) log_error("out of memory for a plan of %u chunks", end_chunk - begin);
    int n = thread_count(opts->threads, RENDER_MAX_THREADS), ran = 0;
    cpu_progress pr = {.start = clock_seconds(),
                       .total = (double)(part_sample_of(p, end_chunk) - part_sample_of(p, begin)),
                       .pixels = (double)job.width * job.height,
                       .deadline = opts->deadline};
    job.stop = opts->control ? opts->control->stop : NULL;
    cpu_passes passes = {.job = &job,
                         .top = top,
                         .merges = merges,
                         .threads = n,
                         .progress = opts->progress,
                         .pr = &pr,
                         .begin = begin};
    pass_backend be = {.run = cpu_run_pass, .sync = cpu_sync, .user = &passes};
    ok = ok && pass_loop_run(opts, p, end_chunk, "cpu", &be);
    ran = passes.ran;
    if (opts->progress) render_progress_clear();
    double render_seconds = clock_seconds() - pr.start;
    log_debug("cpu: rendering in %.1f ms on %d threads", render_seconds * 1e3, ran ? ran : 1);
    if (opts->stats) {
        opts->stats->render_seconds = render_seconds;
        opts->stats->rays = atomic_load(&job.rays);
    }
    free(top);
    free(merges);
    for (int b = 0; b < CHUNK_STACK_MAX; b++) free(job.spare[b]);
    free(job.spare_count);
    free(job.spare_adaptive);
    scene_pack_free(&packed);
    return ok;
}

/* render_backend.render_part of the CPU back end, which never refuses. */
static render_status cpu_render(const scene *s, const render_opts *opts, part *p,
                                uint32_t sample_end, char *reason) {
    reason[0] = '\0';
    return render_cpu_part(s, opts, p, sample_end) ? RENDER_DONE : RENDER_FAILED;
}

/* render_backend.device_count: the processor. */
static int cpu_device_count(void) { return 1; }

/* render_backend.cpu_only: it is one. */
static bool cpu_is_cpu(void) { return true; }

/* render_backend.describe: the packet builds this processor runs. */
static bool cpu_describe(void) {
    packet_integrator every = integrator_packet_choose(NULL, false);
    packet_integrator walk = integrator_packet_choose(NULL, true);
    packet_integrator path = integrator_path_choose(NULL, false);
    printf(
        "packet integrator build %s (%u lanes) where every sphere is tested, %s (%u lanes) where "
        "the BVH is walked, %s (%u lanes) in path mode\n",
        every.name, every.width, walk.name, walk.width, path.name, path.width);
    return true;
}

const render_backend render_backend_cpu = {.name = "cpu",
                                           .device_count = cpu_device_count,
                                           .cpu_only = cpu_is_cpu,
                                           .describe = cpu_describe,
                                           .render_part = cpu_render};
