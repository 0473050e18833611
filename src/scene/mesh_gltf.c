/* mesh_gltf.c: what a glTF file names that assimp 5.2.5 does not read, found in the file's JSON
 * (a .gltf file whole, a GLB's first chunk), so that the loader can say what is lost. */
#define _GNU_SOURCE /* memmem */
#include "scene/mesh_gltf.h"

#include <fcntl.h>
#include <stdint.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

/* The JSON is searched in blocks of this many bytes (a .gltf may embed megabytes of buffers). */
#define BLOCK 65536
/* The longest text searched for, less one: what a block keeps of the one before. */
#define KEEP 127

/* The JSON's extent in the file of st opened as fd with its first `got` bytes in head: a GLB's
 * first chunk when it is JSON, a whole file named .gltf; false for anything else. */
static bool json_extent(const char *path, const unsigned char *head, ssize_t got,
                        const struct stat *st, off_t *from, off_t *to) {
    if (got >= 20 && !memcmp(head, "glTF", 4) && !memcmp(head + 16, "JSON", 4)) {
        uint32_t length = (uint32_t)head[12] | (uint32_t)head[13] << 8 | (uint32_t)head[14] << 16 |
                          (uint32_t)head[15] << 24;
        *from = 20;
        *to = st->st_size - 20 < (off_t)length ? st->st_size : 20 + (off_t)length;
        return true;
    }
    size_t n = strlen(path);
    if (n < 5 || strcasecmp(path + n - 5, ".gltf")) return false;
    *from = 0;
    *to = st->st_size;
    return true;
}

bool mesh_gltf_names(const char *path, const char *text) {
    size_t text_length = strlen(text);
    if (text_length == 0 || text_length > KEEP + 1) return false;
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC); /* a FIFO's open would block */
    if (fd < 0) return false;
    struct stat st;
    unsigned char head[20];
    off_t from = 0, to = 0;
    bool found = false;
    if (fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
        json_extent(path, head, pread(fd, head, sizeof head, 0), &st, &from, &to)) {
        unsigned char block[KEEP + BLOCK];
        size_t kept = 0;
        for (off_t at = from; at < to && !found;) {
            size_t want = to - at < BLOCK ? (size_t)(to - at) : BLOCK;
            ssize_t got = pread(fd, block + kept, want, at);
            if (got <= 0) break;
            size_t have = kept + (size_t)got;
            found = memmem(block, have, text, text_length) != NULL;
            kept = have < KEEP ? have : KEEP;
            memmove(block, block + have - kept, kept);
            at += got;
        }
    }
    close(fd);
    return found;
}
