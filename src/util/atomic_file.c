/* atomic_file.c: all-or-nothing file writes (temporary file, fsync, rename). */
#define _XOPEN_SOURCE 700 /* lstat, readlink, fchmod */
#include "util/atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "util/interrupts.h"
#include "util/log.h"

static int last_error(void) { return errno ? errno : EIO; }

/* The temporary file being written, removed by a terminating signal: an interrupted run leaves
 * nothing behind (the destination is untouched until the rename). */
static char *volatile pending_temp;

static void remove_pending_temp(int sig) {
    char *temp = pending_temp;
    if (temp) unlink(temp); /* async-signal-safe */
    interrupts_die(sig);
}

/* The mode the file should end with: the file's own when it exists, else what open(2) would give
 * a new file (0666 less the umask), since mkstemp makes 0600. */
static mode_t target_mode(const char *path) {
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode)) return st.st_mode & 07777;
    mode_t mask = umask(0); /* reading the umask sets it: put it back at once */
    umask(mask);
    return 0666 & ~mask;
}

/* Runs fill into the open file and closes it (with `sync`, fsync first); 0 or an errno value,
 * *step names what failed. */
static int fill_file(int fd, bool sync, atomic_file_fill fill, const void *context,
                     const char **step) {
    *step = "write";
    FILE *fp = fdopen(fd, "wb");
    if (!fp) {
        int err = errno;
        close(fd);
        return err;
    }
    errno = 0;
    int err = fill(fp, context);
    if (!err && fflush(fp) != 0) err = last_error();
    if (!err && sync && fsync(fileno(fp)) != 0) {
        *step = "sync";
        err = last_error();
    }
    if (fclose(fp) != 0 && !err) err = last_error();
    return err;
}

/* The descriptor of this process that /dev/stdout, /dev/stderr, /dev/fd/N or /proc/self/fd/N
 * stands for; -1 for any other name. */
static int own_descriptor(const char *path) {
    if (!strcmp(path, "/dev/stdout")) return 1;
    if (!strcmp(path, "/dev/stderr")) return 2;
    const char *digits = !strncmp(path, "/dev/fd/", 8)          ? path + 8
                         : !strncmp(path, "/proc/self/fd/", 14) ? path + 14
                                                                : NULL;
    size_t n = digits ? strlen(digits) : 0;
    if (n == 0 || n > 9 || strspn(digits, "0123456789") != n) return -1;
    return atoi(digits);
}

/* Writes into an existing file that is not a regular one (/dev/null, a FIFO) or into one of this
 * process's descriptors: there is nothing to keep, and renaming over it would replace a device
 * with a plain file. A descriptor is written where it stands, as the stream it is (reopening
 * `/dev/stdout` redirected with >> would empty the file it appends to). */
static bool write_in_place(const char *path, atomic_file_fill fill, const void *context) {
    int own = own_descriptor(path);
    int fd = own >= 0 ? dup(own) : open(path, O_WRONLY | O_TRUNC);
    if (fd < 0) {
        log_error("%s: cannot open: %s", path, strerror(errno));
        return false;
    }
    const char *step;
    int err = fill_file(fd, false, fill, context, &step);
    if (err) log_error("%s: cannot %s: %s", path, step, strerror(err));
    return !err;
}

/* The temporary file's name in the destination's folder: a fixed short name, not the
 * destination's plus a suffix, which would pass NAME_MAX for names near it. */
#define TEMP_NAME ".trazador-XXXXXX"

/* The length of path's folder part, its last slash included (0 for a name in "."). */
static size_t folder_length(const char *path) {
    const char *slash = strrchr(path, '/');
    return slash ? (size_t)(slash - path) + 1 : 0;
}

/* Makes the rename durable: the folder's entry is synced too, or a power cut could lose the new
 * file. A file system that cannot sync folders (EINVAL) has nothing to do. */
static void sync_folder(const char *path, const char *shown) {
    size_t n = folder_length(path);
    char *folder = n ? strndup(path, n) : strdup(".");
    int fd = folder ? open(folder, O_RDONLY | O_DIRECTORY) : -1;
    if (fd < 0 || (fsync(fd) != 0 && errno != EINVAL))
        log_warn("%s: written, but its folder could not be synced: %s", shown, strerror(errno));
    if (fd >= 0) close(fd);
    free(folder);
}

/* Writes path through a temporary file beside it, renamed over it once complete; messages name
 * `shown` (what the user gave, when path is a link's target). */
static bool write_replacing(const char *path, const char *shown, atomic_file_fill fill,
                            const void *context) {
    size_t folder = folder_length(path);
    char *tmp = malloc(folder + sizeof TEMP_NAME);
    if (!tmp) {
        log_error("%s: %s", shown, strerror(ENOMEM));
        return false;
    }
    memcpy(tmp, path, folder);
    memcpy(tmp + folder, TEMP_NAME, sizeof TEMP_NAME);
    mode_t mode = target_mode(path);
    interrupts_saved saved;
    interrupts_catch(remove_pending_temp, &saved);
    /* The signals wait while the file is created and recorded: none can come in between. */
    sigset_t unblocked;
    interrupts_block(&unblocked);
    int fd = mkstemp(tmp);
    int create_error = errno;
    if (fd >= 0) pending_temp = tmp;
    interrupts_unblock(&unblocked);
    if (fd < 0) {
        interrupts_restore(&saved);
        log_error("%s: cannot create a temporary file: %s", shown, strerror(create_error));
        free(tmp);
        return false;
    }
    const char *step = "set the file mode";
    int err = fchmod(fd, mode) != 0 ? errno : 0;
    if (err)
        close(fd);
    else
        err = fill_file(fd, true, fill, context, &step);
    if (!err && rename(tmp, path) != 0) {
        err = errno;
        step = "rename the temporary file over it";
    }
    if (err) unlink(tmp);
    pending_temp = NULL;
    interrupts_restore(&saved);
    if (err) log_error("%s: cannot %s: %s", shown, step, strerror(err));
    if (!err) sync_folder(path, shown);
    free(tmp);
    return !err;
}

/* True for the names of a process's open files (/dev/stdout, /dev/fd/3, /proc/self/fd/1): they
 * are written in place, whatever they lead to (a pipe, a terminal, a file the shell opened). */
static bool names_open_file(const char *path) {
    return !strncmp(path, "/dev/std", 8) || !strncmp(path, "/dev/fd/", 8) ||
           (!strncmp(path, "/proc/", 6) && strstr(path, "/fd/"));
}

/* Symbolic links followed in a chain before giving up (Linux's own limit). */
#define MAX_LINK_HOPS 40

/* The file the symbolic link `path` leads to, link by link (malloc'd); the last one need not
 * exist yet: like the shell's >, writing through a link to a missing file creates that file.
 * As the kernel does (fs.protected_symlinks), a link in a sticky world-writable folder (/tmp) is
 * followed only when its owner is the caller or the folder's owner. NULL with errno set on a
 * loop, such a link, a target naming a folder, or a failure. */
static char *link_target(const char *path) {
    char *current = strdup(path);
    for (int hops = 0; current; hops++) {
        struct stat st, folder_st;
        size_t length = strlen(current);
        if (lstat(current, &st) != 0 || !S_ISLNK(st.st_mode)) {
            if (length > 0 && current[length - 1] != '/') return current;
            errno = EISDIR; /* "newdir/": a folder, not a file to create */
            break;
        }
        if (hops == MAX_LINK_HOPS) {
            errno = ELOOP;
            break;
        }
        const char *slash = strrchr(current, '/');
        size_t folder = !slash ? 0 : (size_t)(slash - current) + 1; /* with its slash */
        char *folder_path = strndup(slash ? current : ".", slash ? folder : 1);
        bool seen = folder_path && stat(folder_path, &folder_st) == 0;
        free(folder_path);
        if (seen && (folder_st.st_mode & S_ISVTX) && (folder_st.st_mode & S_IWOTH) &&
            st.st_uid != geteuid() && st.st_uid != folder_st.st_uid) {
            errno = EACCES;
            break;
        }
        char target[PATH_MAX];
        ssize_t n = readlink(current, target, sizeof target - 1);
        if (n < 0) break;
        target[n] = '\0';
        if (target[0] == '/') folder = 0; /* a relative target is relative to the link's folder */
        char *next = malloc(folder + (size_t)n + 1);
        if (next) {
            memcpy(next, current, folder);
            memcpy(next + folder, target, (size_t)n + 1);
        }
        free(current);
        current = next; /* NULL: out of memory, errno ENOMEM */
    }
    int err = errno;
    free(current);
    errno = err;
    return NULL;
}

/* How a path is written: refused (logged), in place, or by replacing `*file` (malloc'd: the
 * path itself, or what a symbolic link leads to, so that the link stays). */
typedef enum write_way { WRITE_REFUSED, WRITE_IN_PLACE, WRITE_REPLACING } write_way;

static write_way how_to_write(const char *path, char **file) {
    *file = NULL;
    struct stat st; /* what the path leads to, through any links */
    bool exists = stat(path, &st) == 0;
    if (exists && S_ISDIR(st.st_mode)) {
        log_error("%s: is a directory", path);
        return WRITE_REFUSED;
    }
    if ((exists && !S_ISREG(st.st_mode)) || names_open_file(path)) return WRITE_IN_PLACE;
    size_t length = strlen(path);
    if (!exists && length > 0 && path[length - 1] == '/') {
        log_error("%s: names a folder (it ends in '/'), not a file to write", path);
        return WRITE_REFUSED;
    }
    if (lstat(path, &st) == 0 && S_ISLNK(st.st_mode)) {
        *file = link_target(path);
        if (!*file) log_error("%s: cannot follow the symbolic link: %s", path, strerror(errno));
    } else {
        *file = strdup(path);
        if (!*file) log_error("%s: %s", path, strerror(ENOMEM));
    }
    return *file ? WRITE_REPLACING : WRITE_REFUSED;
}

bool atomic_file_write(const char *path, atomic_file_fill fill, const void *context) {
    char *file;
    write_way way = how_to_write(path, &file);
    if (way == WRITE_REFUSED) return false;
    /* A file-size limit (ulimit -f) kills the writer with SIGXFSZ and leaves its temporary file:
     * ignored while writing (unless the program handles it), the write fails with EFBIG and
     * cleans up like any failed write. */
    struct sigaction ignore = {.sa_handler = SIG_IGN}, old;
    sigemptyset(&ignore.sa_mask);
    sigaction(SIGXFSZ, NULL, &old);
    bool ignoring = old.sa_handler == SIG_DFL;
    if (ignoring) sigaction(SIGXFSZ, &ignore, NULL);
    bool ok = way == WRITE_IN_PLACE ? write_in_place(path, fill, context)
                                    : write_replacing(file, path, fill, context);
    if (ignoring) sigaction(SIGXFSZ, &old, NULL);
    free(file);
    return ok;
}

/* True (logged) when the file's name is longer than its folder's file system allows. */
static bool name_too_long(const char *shown, const char *file, const char *folder) {
    const char *name = file + folder_length(file);
    long most = pathconf(folder, _PC_NAME_MAX);
    if (most < 0 || strlen(name) <= (size_t)most) return false;
    log_error("%s: the file name is %zu bytes long, past the %ld this file system allows", shown,
              strlen(name), most);
    return true;
}

/* True (logged) when an existing file is write-protected: the caller may not write it, or it has
 * no write bit at all (which root's permissions would pass over, as the shell's > does not
 * for others). */
static bool write_protected(const char *shown, const char *file) {
    struct stat st;
    if (stat(file, &st) != 0) return false;
    if (access(file, W_OK) == 0 && (st.st_mode & 0222)) return false;
    log_error("%s: the file is write-protected (mode %03o): --force replaces it", shown,
              (unsigned)(st.st_mode & 0777));
    return true;
}

bool atomic_file_check_force(const char *path, bool force) {
    char *file;
    write_way way = how_to_write(path, &file);
    if (way == WRITE_REFUSED) return false;
    if (way == WRITE_IN_PLACE) { /* the file must take writes */
        bool ok = access(path, W_OK) == 0;
        if (!ok) log_error("%s: cannot write: %s", path, strerror(errno));
        return ok;
    }
    /* Replaced: its folder must take a new file of that name. */
    size_t n = folder_length(file);
    char *folder = n > 1 ? strndup(file, n - 1) : strdup(n ? "/" : ".");
    bool ok = folder != NULL;
    if (!ok) log_error("%s: %s", path, strerror(ENOMEM));
    if (ok && access(folder, W_OK | X_OK) != 0) {
        log_error("%s: cannot write in %s: %s", path, folder, strerror(errno));
        ok = false;
    }
    ok = ok && !name_too_long(path, file, folder) && (force || !write_protected(path, file));
    free(folder);
    free(file);
    return ok;
}

bool atomic_file_check(const char *path) { return atomic_file_check_force(path, false); }

/* The device and inode of path's folder; false when it cannot be read. */
static bool folder_id(const char *path, struct stat *st) {
    size_t n = folder_length(path);
    char *folder = n > 1 ? strndup(path, n - 1) : strdup(n ? "/" : ".");
    bool ok = folder && stat(folder, st) == 0;
    free(folder);
    return ok;
}

bool atomic_file_same(const char *a, const char *b) {
    struct stat sa, sb;
    bool has_a = stat(a, &sa) == 0, has_b = stat(b, &sb) == 0;
    if (has_a || has_b) return has_a && has_b && sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    /* Neither exists: one file once written if the names match in one folder. */
    if (strcmp(a + folder_length(a), b + folder_length(b))) return false;
    return folder_id(a, &sa) && folder_id(b, &sb) && sa.st_dev == sb.st_dev &&
           sa.st_ino == sb.st_ino;
}
