/* tmp_dir.h: the temporary folder of a test program, the paths inside it, and whole files read
 * and written there. */
#ifndef TRAZADOR_TMP_DIR_H
#define TRAZADOR_TMP_DIR_H

#include <stdio.h>
#include <stdlib.h>

/* The folder, set up from "/tmp/<program>.XXXXXX" by mkdtemp. */
static char tmpdir[64];

/* Creates the folder for the named program; NULL on failure (as mkdtemp). */
static inline char *tmp_dir_make(const char *program) {
    snprintf(tmpdir, sizeof tmpdir, "/tmp/%s.XXXXXX", program);
    return mkdtemp(tmpdir);
}

/* tmpdir/name, from a small ring of buffers so that a few can be alive at once. */
static inline const char *tmp_path(const char *name) {
    static char bufs[8][512];
    static int next;
    char *p = bufs[next++ % 8];
    snprintf(p, sizeof bufs[0], "%s/%s", tmpdir, name);
    return p;
}

/* The whole file, or NULL; *len its size. */
static inline unsigned char *tmp_file_read(const char *path, size_t *len) {
    FILE *fp = fopen(path, "rb");
    if (!fp) return NULL;
    unsigned char *buf = NULL;
    size_t n = 0, cap = 0, got;
    do {
        if (n == cap) buf = realloc(buf, cap = cap * 2 + 4096);
        got = fread(buf + n, 1, cap - n, fp);
        n += got;
    } while (got > 0);
    fclose(fp);
    *len = n;
    return buf;
}

/* Writes len bytes to path; a test that cannot set up its file stops (exit 1). */
static inline void tmp_file_write(const char *path, const void *data, size_t len) {
    FILE *fp = fopen(path, "wb");
    if (!fp || fwrite(data, 1, len, fp) != len || fclose(fp) != 0) {
        printf("cannot write %s\n", path);
        exit(1);
    }
}

#endif
