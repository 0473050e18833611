/* mesh_load.c: model files through assimp's C API (Debian libassimp-dev), in a child process:
 * import with the post-processing trazador needs through a file system that records what it
 * reads, faces gathered with their normals, the file's materials mapped (mesh_material.c). */
#define _GNU_SOURCE /* memfd_create */
#include "scene/mesh_load.h"

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/mman.h> /* memfd_create */
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "scene/assimp_lib.h"
#include "scene/mesh_gltf.h"
#include "scene/mesh_import.h"
#include "scene/mesh_material.h"
#include "util/big_memory.h"
#include "util/clock.h"
#include "util/fd_io.h"
#include "util/log.h"
#include "util/threads.h"

/* Normals are generated across edges whose faces meet at less than this (degrees): a cube stays
 * flat, a tessellated sphere turns smooth. */
#define SMOOTHING_ANGLE 60.0f
/* The import's limit in processor time: this, plus the file's size over the rate below, unless
 * TRAZADOR_MESH_SECONDS gives one (at most LOAD_SECONDS_MAX). Processor time, because CI's
 * loaded cores once stretched a 10 ms import past a wall-clock limit of 2 s. */
#define LOAD_SECONDS 2.0
#define LOAD_BYTES_PER_SECOND 1e6
#define LOAD_SECONDS_MAX 86400.0
/* A child blocked on something other than a core (a model naming a FIFO) ends past this many
 * times its limit on the wall clock, plus LOAD_WALL_SLACK seconds. */
#define LOAD_WALL_FACTOR 10.0
#define LOAD_WALL_SLACK 20.0
/* The child's heap is reserved (heap_reserve) at this many bytes per byte of the file, and at
 * least HEAP_MIN. */
#define HEAP_PER_FILE_BYTE 32
#define HEAP_MIN ((size_t)64 << 20)

/* assimp, opened by mesh_load before it forks the child that imports (which inherits it). */
static const assimp_lib *ai;

static bool fail(char *error, size_t size, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static bool fail(char *error, size_t size, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(error, size, fmt, ap);
    va_end(ap);
    return false;
}

/* Room for count (> 0) faces in private memory, on huge pages mapped at once: the faces cross
 * between the processes by copies into and out of shared memory (pwrite, pread), not through a
 * mapping of it, whose 4 KB pages a virtual machine charges microseconds each at their first
 * touch (docs/PERF.md, "Faces by copy"). NULL when out of memory. */
static mesh_face *faces_room(size_t count) {
    mesh_face *faces = count <= SIZE_MAX / sizeof *faces ? malloc(count * sizeof *faces) : NULL;
    big_memory_advise(faces, faces ? count * sizeof *faces : 0); /* huge pages, mapped at once */
    return faces;
}

/* Copies count faces between memory and shared memory fd (fd_copy_at). */
static bool copy_faces(int fd, mesh_face *faces, size_t count, bool to) {
    return fd_copy_at(fd, faces, count * sizeof *faces, to);
}

/* assimp 5.2.5 reads no KHR_materials_emissive_strength (no key of its glTF reader holds it), so
 * a glTF emitter that has one renders its emissive factor alone: Blender exports a strong lamp
 * as factor 1 and strength 12, and it came out 12 times too dark without a word. Where a
 * material of path emits and the file names the extension, the loss is said with the first
 * emitter's name. */
static void note_lost_strength(const char *path, mesh *out) {
    int first = -1, count = 0;
    for (int k = 0; k < out->material_count; k++) {
        vec3 e = out->materials[k].emission;
        if (e.x > 0.0f || e.y > 0.0f || e.z > 0.0f) count++, first = first < 0 ? k : first;
    }
    if (first < 0 || !mesh_gltf_names(path, "KHR_materials_emissive_strength")) return;
    char what[256];
    snprintf(what, sizeof what,
             "emission strength (KHR_materials_emissive_strength, which assimp 5.2.5 does not "
             "read: material '%s'%s emits its emissive factor alone)",
             out->materials[first].name, count > 1 ? " and the other emitters" : "");
    mesh_note_unsupported(out->unsupported, sizeof out->unsupported, what);
}

/* The import itself, in the child process (mesh_load): the faces go into shared memory fd. */
static bool import(const char *path, bool smooth, int fd, mesh *out, char *error,
                   size_t error_size) {
    memset(out, 0, sizeof *out);
    /* The cameras and lights are read before the post-processing, which renames them */
    unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices | aiProcess_SortByPType;
    struct aiFileIO files = {mesh_file_open, mesh_file_close, (char *)(void *)out};
    const struct aiScene *sc = ai->import_file_ex(path, aiProcess_ValidateDataStructure, &files);
    if (!sc) return fail(error, error_size, "cannot load: %s", ai->get_error_string());
    const char *dot = strrchr(path, '.');
    bool gltf = dot && (!strcasecmp(dot, ".gltf") || !strcasecmp(dot, ".glb"));
    if (!mesh_read_views(sc, gltf, out)) {
        ai->release_import(sc);
        mesh_free(out);
        return fail(error, error_size, "out of memory");
    }
    /* A mesh that several nodes place is kept once, with its placements (mesh_nodes.c) */
    bool shared = mesh_nodes_shared(sc);
    if (shared) flags &= ~(unsigned)aiProcess_PreTransformVertices;
    sc = ai->apply_post_processing(sc, flags);
    if (!sc) {
        mesh_free(out);
        return fail(error, error_size, "cannot load: %s", ai->get_error_string());
    }
    size_t faces = 0;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        const struct aiMesh *me = sc->mMeshes[i];
        if (me->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) faces += me->mNumFaces;
    }
    bool ok = true;
    if (faces == 0) {
        ok = fail(error, error_size, "holds no triangles (%u mesh%s of points or lines only)",
                  sc->mNumMeshes, sc->mNumMeshes == 1 ? "" : "es");
    }
    if (ok && !shared && ftruncate(fd, (off_t)(faces * sizeof *out->faces)) != 0) {
        ok = fail(error, error_size, "cannot hold its %zu faces (%.0f MB) in shared memory: %s%s",
                  faces, (double)(faces * sizeof *out->faces) / 1e6, strerror(errno),
                  errno == EFBIG ? " (the file-size limit, ulimit -f, caps it)" : "");
    }
    if (ok) {
        out->faces = shared ? NULL : faces_room(faces);
        out->materials = calloc(sc->mNumMaterials ? sc->mNumMaterials : 1, sizeof *out->materials);
        if ((!shared && !out->faces) || !out->materials)
            ok = fail(error, error_size, "out of memory");
    }
    for (unsigned i = 0; ok && i < sc->mNumMaterials; i++)
        ok = mesh_map_material(ai, sc->mMaterials[i], i, &out->materials[i], out->unsupported,
                               sizeof out->unsupported, error, error_size);
    out->material_count = (int)sc->mNumMaterials;
    if (ok) note_lost_strength(path, out);
    if (ok) ok = mesh_gather_embedded(sc, out, error, error_size);
    if (ok)
        ok = shared ? mesh_nodes_gather(sc, out, error, error_size)
                    : mesh_gather_faces(sc, out, error, error_size);
    ai->release_import(sc); /* before the normals' tables: the peak is then one of the two */
    size_t all = out->face_count + out->part_face_count;
    if (ok && all == 0)
        ok = fail(error, error_size, "holds no triangles (its faces are points or lines)");
    if (ok && smooth && !mesh_smooth_normals(out, SMOOTHING_ANGLE))
        ok = fail(error, error_size, "out of memory generating its normals");
    for (int k = 0; ok && smooth && k < out->part_count; k++) {
        mesh part = mesh_part_view(out, k);
        if (!mesh_smooth_normals(&part, SMOOTHING_ANGLE))
            ok = fail(error, error_size, "out of memory generating its normals");
    }
    if (ok && shared && ftruncate(fd, (off_t)(all * sizeof *out->faces)) != 0)
        ok = fail(error, error_size, "cannot hold its %zu faces in shared memory: %s", all,
                  strerror(errno));
    if (ok && !copy_faces(fd, out->faces, all, true)) {
        ok = fail(error, error_size, "cannot put its %zu faces (%.0f MB) in shared memory: %s%s",
                  all, (double)(all * sizeof *out->faces) / 1e6, strerror(errno),
                  errno == EFBIG ? " (the file-size limit, ulimit -f, caps it)" : "");
    }
    if (!ok) mesh_free(out);
    return ok;
}

/* What the child sends: the outcome, then the materials follow (the faces are in shared memory). */
typedef struct reply {
    bool ok;
    size_t face_count;
    int material_count;
    double import_seconds; /* assimp's import and the faces gathered */
    char unsupported[384];
    scene_input inputs[MESH_MAX_INPUTS];
    int input_count;
    int camera_count, light_count;  /* follow the materials */
    int embedded_count;             /* the embedded images' ends and bytes follow the lights */
    size_t part_face_count;         /* in shared memory after the placed faces */
    int part_count, instance_count; /* follow the embedded images */
    char error[512];
} reply;

/* assimp allocates a small block per face and vertex list, and every first touch of a 4 KB page
 * of the heap is a fault (microseconds on a virtual machine): the child's heap is reserved on
 * huge pages at about what the import of file_bytes will use (a 1e6-face PLY imported in 0.14 s
 * against 0.28 s, docs/PERF.md "Huge pages"). */
static void heap_reserve(size_t file_bytes) {
    size_t want =
        file_bytes < SIZE_MAX / HEAP_PER_FILE_BYTE ? file_bytes * HEAP_PER_FILE_BYTE : SIZE_MAX;
    big_memory_reserve_heap(want < HEAP_MIN ? HEAP_MIN : want);
}

/* The child: imports into shared memory shm and sends the outcome down fd. A crash in assimp
 * ends this process whatever handlers the parent installed (a sanitizer's or a fuzzer's would
 * report it as the parent's); a file-size limit fails the shared memory's growth, not the
 * process. */
static void child_run(int fd, int shm, const char *path, bool smooth, size_t file_bytes) {
    const int crashes[] = {SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT};
    for (size_t k = 0; k < sizeof crashes / sizeof crashes[0]; k++) signal(crashes[k], SIG_DFL);
    signal(SIGXFSZ, SIG_IGN);
    mesh m;
    reply r = {0};
    double start = clock_seconds();
    heap_reserve(file_bytes);
    r.ok = import(path, smooth, shm, &m, r.error, sizeof r.error);
    r.import_seconds = clock_seconds() - start;
    r.face_count = m.face_count;
    r.material_count = m.material_count;
    memcpy(r.unsupported, m.unsupported, sizeof r.unsupported);
    memcpy(r.inputs, m.inputs, sizeof r.inputs);
    r.input_count = m.input_count;
    r.camera_count = m.camera_count;
    r.light_count = m.light_count;
    r.embedded_count = m.embedded_count;
    r.part_face_count = m.part_face_count;
    r.part_count = m.part_count;
    r.instance_count = m.instance_count;
    if (fd_write_all(fd, &r, sizeof r) && r.ok &&
        fd_write_all(fd, m.materials, (size_t)m.material_count * sizeof *m.materials) &&
        fd_write_all(fd, m.cameras, (size_t)m.camera_count * sizeof *m.cameras) &&
        fd_write_all(fd, m.lights, (size_t)m.light_count * sizeof *m.lights) &&
        fd_write_all(fd, m.embedded_at, sizeof m.embedded_at) &&
        fd_write_all(fd, m.embedded, m.embedded_at[m.embedded_count]) &&
        fd_write_all(fd, m.parts, (size_t)m.part_count * sizeof *m.parts))
        fd_write_all(fd, m.instances, (size_t)m.instance_count * sizeof *m.instances);
    _exit(0);
}

/* Reads the embedded images' ends and bytes the child sends after the lights into out; false
 * when they do not arrive within the limit, are inconsistent or find no memory. */
static bool receive_embedded(int fd, const reply *r, mesh *out, const fd_time_limit *limit,
                             bool *late) {
    if (r->embedded_count < 0 || r->embedded_count > MESH_MAX_EMBEDDED ||
        !fd_read_all_by(fd, out->embedded_at, sizeof out->embedded_at, limit, late))
        return false;
    size_t bytes = out->embedded_at[r->embedded_count];
    for (int k = 0; k < r->embedded_count; k++)
        if (out->embedded_at[k] > out->embedded_at[k + 1]) return false;
    if (out->embedded_at[0] != 0 || bytes > MESH_MAX_EMBEDDED_BYTES) return false;
    out->embedded = malloc(bytes + 1);
    out->embedded_count = r->embedded_count;
    return out->embedded && fd_read_all_by(fd, out->embedded, bytes, limit, late);
}

/* Reads the parts and instances the child sends after the embedded images into out (room for
 * them made); false when they do not arrive within the limit or are inconsistent. */
static bool receive_nodes(int fd, const reply *r, mesh *out, const fd_time_limit *limit,
                          bool *late) {
    out->part_face_count = r->part_face_count;
    if (!fd_read_all_by(fd, out->parts, (size_t)r->part_count * sizeof *out->parts, limit, late) ||
        !fd_read_all_by(fd, out->instances, (size_t)r->instance_count * sizeof *out->instances,
                        limit, late))
        return false;
    out->part_count = r->part_count;
    out->instance_count = r->instance_count;
    for (int k = 0; k < out->part_count; k++) {
        const mesh_part *part = &out->parts[k];
        if (part->count == 0 || part->first > out->part_face_count ||
            part->count > out->part_face_count - part->first)
            return false;
    }
    for (int k = 0; k < out->instance_count; k++) {
        out->instances[k].node[sizeof out->instances[k].node - 1] = '\0';
        if (out->instances[k].part < 0 || out->instances[k].part >= out->part_count) return false;
    }
    return true;
}

/* The import's time limit in seconds for a file of `bytes`: TRAZADOR_MESH_SECONDS where set,
 * else the rule of LOAD_SECONDS; 0 (error said) when the variable is not a number of seconds. */
static double load_limit(off_t bytes, char *error, size_t error_size) {
    const char *given = getenv("TRAZADOR_MESH_SECONDS");
    if (!given || !given[0]) return LOAD_SECONDS + (double)bytes / LOAD_BYTES_PER_SECOND;
    char *end;
    double seconds = strtod(given, &end);
    if (*end || !(seconds > 0.0 && seconds <= LOAD_SECONDS_MAX)) {
        fail(error, error_size,
             "TRAZADOR_MESH_SECONDS='%s' is not a time limit in seconds (more than 0, at most "
             "%g)",
             given, LOAD_SECONDS_MAX);
        return 0.0;
    }
    return seconds;
}

bool mesh_load(const char *path, bool smooth, mesh *out, char *error, size_t error_size) {
    memset(out, 0, sizeof *out);
    /* Only regular files: a FIFO or a device would block assimp's reader for ever. */
    struct stat st;
    if (stat(path, &st) != 0) return fail(error, error_size, "cannot open: %s", strerror(errno));
    if (!S_ISREG(st.st_mode)) return fail(error, error_size, "not a regular file");
    double seconds = load_limit(st.st_size, error, error_size);
    if (seconds == 0.0) return false;
    ai = assimp_lib_open(error, error_size);
    if (!ai) return false;
    const char *dot = strrchr(path, '.');
    if (!dot || strchr(dot, '/') || !ai->is_extension_supported(dot)) {
        return fail(error, error_size,
                    "unsupported format: this assimp reads no '%s' files (`trazador formats` "
                    "lists those it reads)",
                    dot && !strchr(dot, '/') ? dot : "extensionless");
    }
    /* assimp loops for ever or crashes on some malformed files (a PLY whose vertex count is a
     * word hangs 5.2.5): it runs in a child process, killed past its time. */
    /* The faces come back in shared memory (copy_faces): through a pipe the 76 MB of a million
     * faces took longer than assimp's import. */
    int shm = memfd_create("trazador-mesh", MFD_CLOEXEC);
    if (shm < 0) return fail(error, error_size, "cannot make shared memory: %s", strerror(errno));
    int fds[2];
    if (pipe(fds) != 0) {
        close(shm);
        return fail(error, error_size, "cannot make a pipe: %s", strerror(errno));
    }
    double start = clock_seconds();
    pid_t pid = fork();
    if (pid < 0) {
        close(shm);
        close(fds[0]);
        close(fds[1]);
        return fail(error, error_size, "cannot fork: %s", strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        child_run(fds[1], shm, path, smooth, (size_t)st.st_size);
    }
    close(fds[1]);
    fd_time_limit limit = {
        .cpu_seconds = seconds,
        .wall_deadline = clock_seconds() + LOAD_WALL_FACTOR * seconds + LOAD_WALL_SLACK};
    if (clock_getcpuclockid(pid, &limit.cpu_clock) != 0) { /* then the wall clock alone */
        limit.cpu_clock = CLOCK_MONOTONIC;
        limit.cpu_seconds += clock_seconds();
    }
    reply r = {0};
    bool late = false, reported = false, ok = false;
    bool got = fd_read_all_by(fds[0], &r, sizeof r, &limit, &late);
    if (got && r.ok) {
        out->face_count = r.face_count;
        out->material_count = r.material_count;
        memcpy(out->unsupported, r.unsupported, sizeof r.unsupported);
        out->unsupported[sizeof out->unsupported - 1] = '\0';
        out->input_count = r.input_count < 0                 ? 0
                           : r.input_count > MESH_MAX_INPUTS ? MESH_MAX_INPUTS
                                                             : r.input_count;
        memcpy(out->inputs, r.inputs, sizeof r.inputs);
        for (int k = 0; k < out->input_count; k++)
            out->inputs[k].path[sizeof out->inputs[k].path - 1] = '\0';
        struct stat shared;
        size_t all = r.face_count + r.part_face_count;
        bool fits = all >= r.face_count && all <= SIZE_MAX / sizeof *out->faces &&
                    fstat(shm, &shared) == 0 &&
                    (uint64_t)shared.st_size >= all * sizeof *out->faces;
        bool nodes = r.part_count >= 0 && r.part_count <= MESH_MAX_INSTANCES &&
                     r.instance_count >= 0 && r.instance_count <= MESH_MAX_INSTANCES;
        out->faces = fits && nodes && all > 0 ? faces_room(all) : NULL;
        out->parts = nodes ? calloc((size_t)r.part_count + 1, sizeof *out->parts) : NULL;
        out->instances =
            nodes ? calloc((size_t)r.instance_count + 1, sizeof *out->instances) : NULL;
        out->materials = calloc((size_t)r.material_count + 1, sizeof *out->materials);
        bool views = r.camera_count >= 0 && r.camera_count <= MESH_MAX_CAMERAS &&
                     r.light_count >= 0 && r.light_count <= MESH_MAX_LIGHTS;
        out->cameras = views ? calloc((size_t)r.camera_count + 1, sizeof *out->cameras) : NULL;
        out->lights = views ? calloc((size_t)r.light_count + 1, sizeof *out->lights) : NULL;
        if (!out->faces || !out->materials || !out->cameras || !out->lights || !out->parts ||
            !out->instances) {
            fail(error, error_size, "out of memory for %zu faces", all);
            reported = true;
        } else if (!copy_faces(shm, out->faces, all, false)) {
            fail(error, error_size, "cannot read its %zu faces back from shared memory: %s",
                 r.face_count, strerror(errno));
            reported = true;
        } else {
            ok = fd_read_all_by(fds[0], out->materials,
                                (size_t)r.material_count * sizeof *out->materials, &limit, &late) &&
                 fd_read_all_by(fds[0], out->cameras, (size_t)r.camera_count * sizeof *out->cameras,
                                &limit, &late) &&
                 fd_read_all_by(fds[0], out->lights, (size_t)r.light_count * sizeof *out->lights,
                                &limit, &late);
            out->camera_count = r.camera_count;
            out->light_count = r.light_count;
            ok = ok && receive_embedded(fds[0], &r, out, &limit, &late) &&
                 receive_nodes(fds[0], &r, out, &limit, &late);
            for (int k = 0; k < out->camera_count; k++)
                out->cameras[k].name[sizeof out->cameras[k].name - 1] = '\0';
            for (int k = 0; k < out->light_count; k++) {
                out->lights[k].name[sizeof out->lights[k].name - 1] = '\0';
                out->lights[k].kind[sizeof out->lights[k].kind - 1] = '\0';
            }
        }
    } else if (got) {
        r.error[sizeof r.error - 1] = '\0';
        fail(error, error_size, "%s", r.error);
        reported = true;
    }
    close(fds[0]);
    close(shm);
    if (ok)
        log_debug(
            "mesh %s: %zu faces imported by assimp in %.1f ms (its own process), received "
            "in %.1f ms",
            path, out->face_count, r.import_seconds * 1e3,
            (clock_seconds() - start - r.import_seconds) * 1e3);
    if (late) kill(pid, SIGKILL);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR) continue;
    if (!ok && !reported) {
        if (late)
            fail(error, error_size,
                 "cannot load: assimp did not finish within its time limit of %.1f s of processor "
                 "time (a malformed file, or a slow one: TRAZADOR_MESH_SECONDS=N gives it N s)",
                 seconds);
        else if (WIFSIGNALED(status))
            fail(error, error_size, "cannot load: assimp crashed reading it (signal %d)",
                 WTERMSIG(status));
        else
            fail(error, error_size, "cannot load: assimp's process ended before its reply");
    }
    if (!ok) mesh_free(out);
    return ok;
}

void mesh_free(mesh *m) {
    free(m->faces);
    free(m->parts);
    free(m->instances);
    free(m->materials);
    free(m->cameras);
    free(m->lights);
    free(m->embedded);
    memset(m, 0, sizeof *m);
}
