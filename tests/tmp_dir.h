/* tmp_dir.h: the temporary folder of a test program and the paths inside it. */
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

#endif
