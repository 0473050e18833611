/* mesh_files.c: the file system assimp imports through (mesh_load.c's child process). */
#include <assimp/cfileio.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "scene/mesh_import.h"

/* The import's file system (aiFileIO): assimp's own, but recording each file it opens in the
 * mesh's inputs, so that the CLI can refuse to write over a model's MTL or buffers as over the
 * model, and opening regular files alone (a FIFO that an OBJ names as its MTL would block the
 * import until killed). The import only reads. */
static FILE *file_of(struct aiFile *f) { return (FILE *)(void *)f->UserData; }

static size_t file_read(struct aiFile *f, char *buffer, size_t size, size_t count) {
    return fread(buffer, size, count, file_of(f));
}

static size_t file_write(struct aiFile *f, const char *buffer, size_t size, size_t count) {
    (void)f, (void)buffer, (void)size, (void)count;
    return 0;
}

static size_t file_tell(struct aiFile *f) {
    off_t at = ftello(file_of(f));
    return at < 0 ? 0 : (size_t)at;
}

static size_t file_size(struct aiFile *f) {
    struct stat st;
    return fstat(fileno(file_of(f)), &st) == 0 ? (size_t)st.st_size : 0;
}

/* assimp passes an offset from the end as a negative number in a size_t. */
static enum aiReturn file_seek(struct aiFile *f, size_t offset, enum aiOrigin origin) {
    int whence = origin == aiOrigin_SET ? SEEK_SET : origin == aiOrigin_CUR ? SEEK_CUR : SEEK_END;
    return fseeko(file_of(f), (off_t)offset, whence) == 0 ? aiReturn_SUCCESS : aiReturn_FAILURE;
}

static void file_flush(struct aiFile *f) { (void)f; }

/* Keeps the identity st of the file opened as path in m's inputs (each file once). */
static void record_input(mesh *m, const struct stat *st, const char *path) {
    for (int k = 0; k < m->input_count; k++)
        if (scene_input_is(&m->inputs[k], (uint64_t)st->st_dev, st->st_ino)) return;
    if (m->input_count == MESH_MAX_INPUTS) return;
    scene_input *in = &m->inputs[m->input_count++];
    in->device = (uint64_t)st->st_dev;
    in->inode = (uint64_t)st->st_ino;
    snprintf(in->path, sizeof in->path, "%s", path);
}

struct aiFile *mesh_file_open(struct aiFileIO *io, const char *path, const char *mode) {
    if (strpbrk(mode, "wa+")) return NULL;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC); /* a FIFO's open would block */
    if (fd < 0) return NULL;
    struct stat st;
    FILE *fp = NULL;
    struct aiFile *f = malloc(sizeof *f);
    if (f && fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
        fcntl(fd, F_SETFL, fcntl(fd, F_GETFL) & ~O_NONBLOCK) == 0)
        fp = fdopen(fd, "rb");
    if (!fp) {
        free(f);
        close(fd);
        return NULL;
    }
    record_input((mesh *)(void *)io->UserData, &st, path);
    *f = (struct aiFile){file_read, file_write, file_tell,         file_size,
                         file_seek, file_flush, (char *)(void *)fp};
    return f;
}

void mesh_file_close(struct aiFileIO *io, struct aiFile *f) {
    (void)io;
    fclose(file_of(f));
    free(f);
}
