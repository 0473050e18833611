/* model_formats.c: the model formats assimp reads, from assimp (assimp_lib.c), and the model files
 * render is given where a scene is expected: a user's first try (`render bunny.glb`) met the
 * parser's "unexpected byte" or "unknown directive". */
#include "scene/model_formats.h"

#include <assimp/importerdesc.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "scene/assimp_lib.h"
#include "util/log.h"

/* The bytes read of a file to tell a model from a scene. */
#define HEAD_BYTES 4096

bool model_formats_print(FILE *out) {
    char error[256];
    const assimp_lib *ai = assimp_lib_open(error, sizeof error);
    if (!ai) {
        log_error("%s", error);
        return false;
    }
    fprintf(out, "Model formats this assimp reads (a scene's `mesh file PATH`), by extension:\n");
    size_t count = ai->get_import_format_count();
    for (size_t k = 0; k < count; k++) {
        const struct aiImporterDesc *d = ai->get_import_format_description(k);
        if (!d || !d->mFileExtensions) continue;
        char extensions[256] = "";
        size_t used = 0;
        for (const char *e = d->mFileExtensions; *e;) {
            size_t n = strcspn(e, " ");
            if (n > 0 && used < sizeof extensions)
                used += (size_t)snprintf(extensions + used, sizeof extensions - used, "%s.%.*s",
                                         used ? " " : "", (int)n, e);
            e += n + (e[n] == ' ');
        }
        bool blender = strstr(d->mFileExtensions, "blend") != NULL;
        fprintf(out, "  %-20s %s%s\n", extensions, d->mName ? d->mName : "",
                blender ? " (Blender 2.7x and older only)" : "");
    }
    return true;
}

/* The line (from 1) of the first line of head that is neither blank nor a comment; 0 when head
 * holds none. */
static int first_content_line(const char *head, size_t length) {
    int line = 1;
    for (size_t i = 0; i < length; line++) {
        while (i < length && (head[i] == ' ' || head[i] == '\t' || head[i] == '\r')) i++;
        if (i < length && head[i] != '\n' && head[i] != '#') return line;
        const char *newline = memchr(head + i, '\n', length - i);
        if (!newline) return 0;
        i = (size_t)(newline - head) + 1;
    }
    return 0;
}

/* Whether head (of length bytes) holds text at its start. */
static bool starts(const char *head, size_t length, const char *text) {
    size_t n = strlen(text);
    return length >= n && !memcmp(head, text, n);
}

/* Whether head holds text anywhere (not NUL-terminated: binary files hold NULs). */
static bool holds(const char *head, size_t length, const char *text) {
    size_t n = strlen(text);
    for (size_t i = 0; i + n <= length; i++)
        if (!memcmp(head + i, text, n)) return true;
    return false;
}

/* The model format head's first bytes say, NULL for none. */
static const char *kind_of_bytes(const char *head, size_t length) {
    if (starts(head, length, "glTF")) return "glTF binary";
    if (starts(head, length, "ply\n") || starts(head, length, "ply\r\n")) return "PLY";
    if (starts(head, length, "BLENDER")) return "Blender";
    if (starts(head, length, "Kaydara FBX Binary")) return "FBX";
    if (holds(head, length, "<COLLADA")) return "COLLADA";
    if (starts(head, length, "solid") && holds(head, length, "facet normal")) return "STL";
    return NULL;
}

bool model_file_kind(const char *path, int error_line, char *kind, size_t size) {
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    if (dot && slash && dot < slash) dot = NULL;
    if (error_line < 1 || (dot && !strcasecmp(dot, ".scene"))) return false;
    char head[HEAD_BYTES];
    int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) return false;
    ssize_t got = read(fd, head, sizeof head);
    close(fd);
    if (got <= 0 || first_content_line(head, (size_t)got) != error_line) return false;
    const char *bytes = kind_of_bytes(head, (size_t)got);
    if (bytes) {
        snprintf(kind, size, "%s", bytes);
        return true;
    }
    char error[256];
    const assimp_lib *ai = dot ? assimp_lib_open(error, sizeof error) : NULL;
    if (!ai || !ai->is_extension_supported(dot)) return false;
    size_t n = 0;
    for (const char *c = dot + 1; *c && n + 1 < size; c++)
        kind[n++] = *c >= 'a' && *c <= 'z' ? (char)(*c - 'a' + 'A') : *c;
    kind[n] = '\0';
    return true;
}
