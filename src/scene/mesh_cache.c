/* mesh_cache.c: a parse's loaded models by file identity, since each import costs a process and
 * assimp's whole read. Each `mesh` line transforms its own copy of the faces, so a model kept
 * for later lines is a copy made before that; models up to CACHE_MAX_FACES faces are kept, the
 * oldest dropped past CACHE_SLOTS, and of the bigger ones the last alone, for the next line
 * that loads it to take (one slot of its own): the copy of a million faces costs tens of
 * milliseconds against the second import's second, which the first instance of a model
 * (scene_instance.c) would otherwise pay, and holds one model's faces once more until then. */
#include "scene/mesh_cache.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "util/log.h"

#define CACHE_SLOTS 8
#define CACHE_MAX_FACES ((size_t)1 << 18)

typedef struct cached_mesh {
    struct stat file;
    bool smooth, kept; /* kept: the copy was made (not out of memory) */
    bool once;         /* adopted: the next load takes the model itself */
    mesh model;
} cached_mesh;

struct mesh_cache {
    cached_mesh slot[CACHE_SLOTS + 1]; /* the last: the one model past CACHE_MAX_FACES kept */
    int count, oldest;
};

static bool same_file(const struct stat *a, const struct stat *b) {
    return a->st_dev == b->st_dev && a->st_ino == b->st_ino && a->st_size == b->st_size &&
           a->st_mtim.tv_sec == b->st_mtim.tv_sec && a->st_mtim.tv_nsec == b->st_mtim.tv_nsec;
}

/* A copy of model `from` into *to (its own arrays); false out of memory (*to empty). */
static bool mesh_copy(const mesh *from, mesh *to) {
    *to = *from;
    size_t faces = from->face_count + from->part_face_count;
    to->faces = malloc(faces * sizeof *from->faces);
    to->parts = malloc(((size_t)from->part_count + 1) * sizeof *from->parts);
    to->instances = malloc(((size_t)from->instance_count + 1) * sizeof *from->instances);
    to->materials = malloc(((size_t)from->material_count + 1) * sizeof *from->materials);
    to->cameras = malloc(((size_t)from->camera_count + 1) * sizeof *from->cameras);
    to->lights = malloc(((size_t)from->light_count + 1) * sizeof *from->lights);
    size_t embedded = from->embedded_at[from->embedded_count];
    to->embedded = malloc(embedded + 1);
    if (!to->faces || !to->materials || !to->cameras || !to->lights || !to->embedded ||
        !to->parts || !to->instances) {
        mesh_free(to);
        return false;
    }
    memcpy(to->cameras, from->cameras, (size_t)from->camera_count * sizeof *from->cameras);
    memcpy(to->lights, from->lights, (size_t)from->light_count * sizeof *from->lights);
    memcpy(to->faces, from->faces, faces * sizeof *from->faces);
    memcpy(to->parts, from->parts, (size_t)from->part_count * sizeof *from->parts);
    memcpy(to->instances, from->instances, (size_t)from->instance_count * sizeof *from->instances);
    memcpy(to->materials, from->materials, (size_t)from->material_count * sizeof *from->materials);
    if (embedded) memcpy(to->embedded, from->embedded, embedded);
    return true;
}

bool mesh_cache_load(mesh_cache **cache, const char *path, bool smooth, mesh *out, char *error,
                     size_t error_size) {
    struct stat file;
    bool known = stat(path, &file) == 0 && S_ISREG(file.st_mode);
    for (int k = 0; known && *cache && k <= CACHE_SLOTS; k++) {
        cached_mesh *c = &(*cache)->slot[k];
        if (k < CACHE_SLOTS && k >= (*cache)->count) continue;
        if (!c->kept || c->smooth != smooth || !same_file(&c->file, &file)) continue;
        if (c->once) { /* a model's scene's mesh line, or a big model's next: takes it */
            *out = c->model;
            memset(&c->model, 0, sizeof c->model);
            c->kept = false;
            log_debug("mesh %s: %zu faces, the import kept for it", path, out->face_count);
            return true;
        }
        if (!mesh_copy(&c->model, out)) break; /* out of memory: load it as if new */
        log_debug("mesh %s: %zu faces, the import of an earlier line", path, out->face_count);
        return true;
    }
    if (!mesh_load(path, smooth, out, error, error_size)) return false;
    if (!known) return true;
    if (!*cache) *cache = calloc(1, sizeof **cache);
    if (!*cache) return true; /* out of memory: the next line loads again */
    mesh_cache *c = *cache;
    if (out->face_count + out->part_face_count > CACHE_MAX_FACES) {
        cached_mesh *big = &c->slot[CACHE_SLOTS];
        mesh_free(&big->model);
        *big = (cached_mesh){.file = file, .smooth = smooth, .once = true};
        big->kept = mesh_copy(out, &big->model);
        return true;
    }
    int k = c->count < CACHE_SLOTS ? c->count++ : c->oldest;
    if (k == c->oldest && c->count == CACHE_SLOTS) mesh_free(&c->slot[k].model);
    c->oldest = c->count < CACHE_SLOTS ? 0 : (k + 1) % CACHE_SLOTS;
    c->slot[k].file = file;
    c->slot[k].smooth = smooth;
    c->slot[k].kept = mesh_copy(out, &c->slot[k].model);
    return true;
}

bool mesh_cache_adopt(mesh_cache **cache, const char *path, bool smooth, mesh *model) {
    struct stat file;
    if (stat(path, &file) != 0 || !S_ISREG(file.st_mode)) return false;
    if (!*cache) *cache = calloc(1, sizeof **cache);
    if (!*cache || (*cache)->count == CACHE_SLOTS) return false;
    cached_mesh *c = &(*cache)->slot[(*cache)->count++];
    *c = (cached_mesh){.file = file, .smooth = smooth, .kept = true, .once = true, .model = *model};
    memset(model, 0, sizeof *model);
    return true;
}

void mesh_cache_free(mesh_cache *cache) {
    for (int k = 0; cache && k < cache->count; k++) mesh_free(&cache->slot[k].model);
    if (cache) mesh_free(&cache->slot[CACHE_SLOTS].model);
    free(cache);
}
