/* scene_parse.c: the scene parser's driver (DESIGN section 2), over a text (a string, or a file
 * read by scene_file.c): lines through the lexer (scene_lex.c) and the directives
 * (scene_directives.c), then the checks of the whole scene.
 *
 * One pass over the text, one line at a time: each line is split into tokens (pointers into the
 * text, no copies), its directive is parsed into a local struct scene, and the first error stops
 * everything with file:line:col. The caller's scene is written only on success.
 *
 * Big texts are cut into chunks at line ends. The first chunk is parsed in order on the calling
 * thread while the others are parsed at the same time, a chunk at a time by whichever thread is
 * free, on the guess that they hold only primitives (spheres, triangles, quads), comments and
 * blank lines. A chunk that does parse so is appended as if read in order (its spheres after the
 * spheres so far, its triangles after the triangles); any other (another directive, an error, too
 * many primitives) is parsed again in order, so the scene, messages, warnings and which error
 * comes first are those of one pass.
 */
#include <float.h>
#include <limits.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "scene/directives.h"
#include "scene/mesh_cache.h"
#include "scene/parser.h"
#include "scene/scene.h"
#include "shared_layout.h"
#include "util/big_memory.h"
#include "util/threads.h"

/* Chunks are no shorter than this: a chunk costs a parser and a copy of its primitives. */
#define MIN_CHUNK_BYTES (256 * 1024)
/* Threads a parse uses at most. */
#define MAX_PARSE_THREADS 16
/* Chunks per thread: several, so that a thread that gets a core late (the host is shared) holds
 * up the others by one small chunk at most. */
#define CHUNKS_PER_THREAD 4
#define MAX_CHUNKS (CHUNKS_PER_THREAD * MAX_PARSE_THREADS)

bool parser_line(parser *p, const char *line, size_t length) {
    /* A CR before the '\n' belongs to the line ending, not to the line's length. */
    size_t content = length > 0 && line[length - 1] == '\r' ? length - 1 : length;
    if (content > SCENE_MAX_LINE) {
        /* A NUL byte before the limit says more (binary input, /dev/zero): tokenizing those
         * bytes reports it. */
        if (memchr(line, '\0', SCENE_MAX_LINE) && !parser_tokenize(p, line, SCENE_MAX_LINE))
            return false;
        return parser_fail(p, SCENE_MAX_LINE + 1, "line is longer than %d bytes", SCENE_MAX_LINE);
    }
    if (!parser_tokenize(p, line, length)) return false;
    if (p->token_count == 0) return true;
    return parser_directive(p);
}

/* Parses the lines of [text, end), counting them in p->line. */
static bool parse_lines(parser *p, const char *text, const char *end) {
    while (text < end) {
        const char *newline = memchr(text, '\n', (size_t)(end - text));
        const char *line_end = newline ? newline : end;
        if (!parser_line(p, text, (size_t)(line_end - text))) return false;
        if (!newline) break;
        text = newline + 1;
        p->line++;
    }
    return true;
}

/* A chunk of the text parsed ahead on its own thread, its lines counted from 1. */
typedef struct chunk {
    const char *begin, *end;
    parser *p; /* NULL: no memory for it, parse it in order */
    bool ok;   /* every line was a primitive, a comment or blank, and parsed */
} chunk;

typedef struct chunk_list {
    chunk *chunks;
    int count;
    atomic_int next; /* the next chunk to parse ahead */
} chunk_list;

/* Parses chunks ahead, taken from the shared list, until none is left. */
static void *chunks_run(void *arg) {
    chunk_list *l = arg;
    for (;;) {
        int k = atomic_fetch_add(&l->next, 1);
        if (k >= l->count) return NULL;
        chunk *c = &l->chunks[k];
        if (c->p) c->ok = parse_lines(c->p, c->begin, c->end);
    }
}

/* Appends count items of size `item` to *array (holding *used of *capacity); false when out of
 * memory. */
static bool append_items(void **array, int *used, size_t *capacity, const void *items, int count,
                         size_t item) {
    size_t total = (size_t)*used + (size_t)count;
    if (total > *capacity) {
        /* Doubling: each growth may move the array, whose huge pages a move splits. */
        size_t capacity_new = total > 2 * *capacity ? total : 2 * *capacity;
        void *grown = big_realloc(*array, capacity_new * item);
        if (!grown) return false;
        *array = grown;
        *capacity = capacity_new;
    }
    if (count > 0) memcpy((char *)*array + (size_t)*used * item, items, (size_t)count * item);
    *used += count;
    return true;
}

/* Appends the spheres and triangles of chunk scene cs to p's with their materials and normals,
 * as if p had parsed them: its first material is p's last when they are the same
 * (material_add); false (nothing appended) when out of memory. */
static bool append_shapes(parser *p, const scene *cs) {
    int materials = p->s.material_count, normals = p->s.normals_count;
    int triangles = p->s.triangle_count, spheres = p->s.sphere_count;
    bool shared = materials > 0 && cs->material_count > 0 &&
                  material_same(&p->s.materials[materials - 1], &cs->materials[0]);
    int skip = shared ? 1 : 0;
    void *m = p->s.materials, *n = p->s.normals, *t = p->s.triangles;
    bool ok = append_items(&m, &p->s.material_count, &p->material_capacity, cs->materials + skip,
                           cs->material_count - skip, sizeof *cs->materials);
    p->s.materials = m;
    void *sp = p->s.spheres;
    ok = ok && append_items(&sp, &p->s.sphere_count, &p->sphere_capacity, cs->spheres,
                            cs->sphere_count, sizeof *cs->spheres);
    p->s.spheres = sp;
    ok = ok && append_items(&n, &p->s.normals_count, &p->normals_capacity, cs->normals,
                            cs->normals_count, sizeof *cs->normals);
    p->s.normals = n;
    ok = ok && append_items(&t, &p->s.triangle_count, &p->triangle_capacity, cs->triangles,
                            cs->triangle_count, sizeof *cs->triangles);
    p->s.triangles = t;
    if (!ok) {
        p->s.material_count = materials, p->s.normals_count = normals;
        p->s.triangle_count = triangles, p->s.sphere_count = spheres;
        return false;
    }
    for (int k = spheres; k < p->s.sphere_count; k++)
        p->s.spheres[k].material += (uint32_t)materials - (uint32_t)skip;
    for (int k = triangles; k < p->s.triangle_count; k++) {
        triangle *f = &p->s.triangles[k];
        f->material = f->material + (uint32_t)materials - (uint32_t)skip;
        if (f->normals != TRIANGLE_FLAT) f->normals += (uint32_t)normals;
    }
    return true;
}

/* Appends chunk c's spheres, triangles and warning to p as if p had parsed its lines; false when
 * c must be parsed in order instead. */
static bool chunk_adopt(parser *p, const chunk *c) {
    if (!c->p) return false;
    const scene *cs = &c->p->s;
    long long primitives =
        (long long)p->s.sphere_count + p->s.triangle_count + cs->sphere_count + cs->triangle_count;
    if (!c->ok || cs->sphere_count > SCENE_MAX_SPHERES - p->s.sphere_count ||
        primitives > PARSER_MAX_PRIMITIVES)
        return false;
    if (!append_shapes(p, cs)) return false;
    /* Its only possible warning is its first tiny sphere, which counts if p had none yet. */
    if (cs->warning_count > 0 && !p->tiny_warned) {
        p->tiny_warned = true;
        if (p->s.warning_count < SCENE_MAX_WARNINGS) {
            scene_error *w = &p->s.warnings[p->s.warning_count++];
            *w = cs->warnings[0];
            w->line += p->line - 1;
        }
    }
    if (c->p->emission_line && !p->emission_line) {
        p->emission_line = c->p->emission_line + p->line - 1;
        p->emission_col = c->p->emission_col;
    }
    if (c->p->bright_line && !p->bright_line) {
        p->bright_line = c->p->bright_line + p->line - 1;
        p->bright_col = c->p->bright_col;
        memcpy(p->bright_what, c->p->bright_what, sizeof p->bright_what);
    }
    p->line += c->p->line - 1;
    return true;
}

/* Parses p's text on up to threads threads (see the top of the file). */
static bool parse_chunks(parser *p, int threads) {
    const char *text = p->text, *end = p->text + p->length;
    if (threads > MAX_PARSE_THREADS) threads = MAX_PARSE_THREADS;
    int count = threads * CHUNKS_PER_THREAD;
    if (p->length / MIN_CHUNK_BYTES < (size_t)count) count = (int)(p->length / MIN_CHUNK_BYTES);
    if (threads < 2 || count < 2) return parse_lines(p, text, end);
    chunk chunks[MAX_CHUNKS];
    const char *at = text;
    for (int k = 0; k < count; k++) { /* each chunk ends just past a '\n' (the last at end) */
        const char *cut = k == count - 1 ? end : text + p->length / (size_t)count * (size_t)(k + 1);
        if (cut < at) cut = at;
        const char *newline = cut < end ? memchr(cut, '\n', (size_t)(end - cut)) : NULL;
        chunks[k] = (chunk){.begin = at, .end = newline ? newline + 1 : end};
        at = chunks[k].end;
    }
    for (int k = 1; k < count; k++) {
        chunk *c = &chunks[k];
        c->p = calloc(1, sizeof *c->p);
        if (!c->p) continue;
        *c->p = (parser){.text = p->text,
                         .length = p->length,
                         .filename = p->filename,
                         .line = 1,
                         .primitives_only = true};
    }
    chunk_list list = {.chunks = chunks, .count = count};
    atomic_init(&list.next, 1);
    pthread_t workers[MAX_PARSE_THREADS];
    int started = 0;
    while (started < threads - 1 && started < count - 1 &&
           pthread_create(&workers[started], NULL, chunks_run, &list) == 0)
        started++;
    /* The first chunk in order, then whatever chunks the other threads have not taken (none after
     * an error: they would not count). */
    bool ok = parse_lines(p, chunks[0].begin, chunks[0].end);
    if (ok)
        chunks_run(&list);
    else
        atomic_store(&list.next, count);
    for (int t = 0; t < started; t++) pthread_join(workers[t], NULL);
    for (int k = 1; k < count; k++) {
        chunk *c = &chunks[k];
        if (ok && !chunk_adopt(p, c)) ok = parse_lines(p, c->begin, c->end);
        if (c->p) {
            scene_free(&c->p->s);
            free(c->p);
        }
    }
    return ok;
}

/* A fov so small that the image plane lies past SCENE_MAX_PLANE_DISTANCE for the plane's width
 * is an error at the fov, naming the smallest that works: it rendered only the background. */
static bool fov_reaches(double fov, double half_width) {
    return half_width / tan(0.5 * (double)(float)fov * (3.14159265358979323846 / 180.0)) <=
           SCENE_MAX_PLANE_DISTANCE;
}

static bool check_fov(parser *p) {
    double half_width = 0.5 * p->s.plane_width;
    if (!p->fov_line || fov_reaches(p->s.camera_fov, half_width)) return true;
    /* The smallest fov of three significant digits that works, as the parser reads it. */
    double least =
        2.0 * atan(half_width / SCENE_MAX_PLANE_DISTANCE) * (180.0 / 3.14159265358979323846);
    double step = pow(10.0, floor(log10(least)) - 2.0);
    least = ceil(least / step) * step;
    while (!fov_reaches(least, half_width)) least += step;
    double fov = p->s.camera_fov;
    p->line = p->fov_line;
    return parser_fail(p, p->fov_col,
                       "fov %g puts the image plane of a plane %g wide past %g away, where single "
                       "precision overflows: give a fov of at least %.3g",
                       fov, p->s.plane_width, SCENE_MAX_PLANE_DISTANCE, least);
}

static bool parse_text(parser *p, int threads) {
    if (!parse_chunks(p, threads) || !mesh_placed_finish(p)) return false;
    /* Whole-scene errors are reported at the end of the file: the line after the last '\n'. */
    if (!p->camera_line) return parser_fail(p, 1, "missing 'camera' directive");
    if (!p->plane_line) return parser_fail(p, 1, "missing 'plane' directive");
    if (!check_fov(p)) return false;
    /* The mode the render will use decides, not the scene's own: --mode path enables emission. */
    if (p->emission_line && p->mode_given == RENDER_MODE_REPORT) {
        p->line = p->emission_line;
        return parser_fail(p, p->emission_col,
                           "emission needs path mode, and the render was asked for in report mode "
                           "(--mode report)");
    }
    if (p->emission_line && p->mode_given < 0 && p->s.mode == RENDER_MODE_REPORT) {
        p->line = p->emission_line;
        return parser_fail(p, p->emission_col,
                           "emission needs path mode: add 'render mode path' (or render with "
                           "--mode path)");
    }
    /* A setting the render's mode has no use for is said once, not ignored silently. */
    render_mode mode = p->mode_given >= 0 ? (render_mode)p->mode_given : p->s.mode;
    if (p->roulette_col && mode == RENDER_MODE_REPORT)
        parser_warn(p, p->render_line, p->roulette_col,
                    "roulette does nothing in report mode: it is path mode's Russian roulette");
    if (p->indirect_col && mode == RENDER_MODE_PATH)
        parser_warn(p, p->render_line, p->indirect_col,
                    "indirect does nothing in path mode: paths bounce until `bounces`");
    if (p->light_samples_col && mode == RENDER_MODE_REPORT)
        parser_warn(p, p->render_line, p->light_samples_col,
                    "light_samples does nothing in report mode: it is path mode's emitter samples "
                    "a vertex");
    /* Paths multiply their throughput by the albedo at every bounce: above 1 they gain energy
     * (fireflies, a furnace that never settles). Report mode's one bounce is the course report's
     * own model, whose scenes (the default among them) use such materials as they are. */
    if (p->bright_line && mode == RENDER_MODE_PATH)
        parser_warn(p, p->bright_line, p->bright_col,
                    "%s (keep max(color) + ks at most 1: path mode's light grows at every bounce)",
                    p->bright_what);
    parser_warn_near_clip(p);
    parser_report_meshes(p);
    return true;
}

scene parser_scene_defaults(void) {
    return (scene){
        .camera_direction = v3(0, 0, 1),
        .camera_up = v3(0, 1, 0),
        .spp = 64,
        .indirect = true,
        .bounces = 5,
        .seed = 1,
        .mode = RENDER_MODE_REPORT,
        .roulette = true,
        .light_samples = 1,
    };
}

/* parser_run of threads threads with the models of cache (NULL: none yet), which it releases. */
static bool run_with(const char *text, size_t length, const char *filename, int threads, int mode,
                     struct mesh_cache *cache, scene *out, scene_error *err) {
    if (err) err->out_of_memory = false;
    parser *p = calloc(1, sizeof *p);
    if (!p) {
        mesh_cache_free(cache);
        if (err) *err = (scene_error){.message = "out of memory", .out_of_memory = true};
        return false;
    }
    p->meshes = cache;
    p->text = text;
    p->length = length;
    p->filename = filename ? filename : "<string>";
    p->err = err;
    p->line = 1;
    p->mode_given = mode;
    p->s = parser_scene_defaults();
    bool ok;
    if (length > MAX_TEXT_BYTES) {
        p->line = 0;
        ok = parser_fail(p, 0, "scene is too large (%zu bytes; the limit is %zu)", length,
                         MAX_TEXT_BYTES);
    } else {
        ok = parse_text(p, thread_count(threads, MAX_PARSE_THREADS));
    }
    if (ok) {
        *out = p->s;
    } else {
        scene_free(&p->s);
    }
    mesh_cache_free(p->meshes);
    mesh_placed_free(p);
    free(p->views);
    free(p);
    return ok;
}

bool parser_run(const char *text, size_t length, const char *filename, int threads, int mode,
                scene *out, scene_error *err) {
    return run_with(text, length, filename, threads, mode, NULL, out, err);
}

bool parser_run_cached(const char *text, size_t length, const char *filename, int mode,
                       struct mesh_cache *cache, scene *out, scene_error *err) {
    return run_with(text, length, filename, 0, mode, cache, out, err);
}

bool scene_parse_string_threads(const char *text, size_t length, const char *filename, int threads,
                                scene *out, scene_error *err) {
    return parser_run(text, length, filename, threads, -1, out, err);
}

bool scene_parse_string(const char *text, size_t length, const char *filename, scene *out,
                        scene_error *err) {
    return parser_run(text, length, filename, 0, -1, out, err);
}

bool scene_parse_string_in_mode(const char *text, size_t length, const char *filename, int mode,
                                scene *out, scene_error *err) {
    return parser_run(text, length, filename, 0, mode, out, err);
}
