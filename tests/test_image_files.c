/* test_image_files.c: image files written atomically (errors, interruptions, a killed writer,
   special files, links, overwrites), malformed inputs, and PNGs of other depths and color types
   (written here with libpng) for src/image/image.c and image_png.c. */
#include <errno.h>
#include <png.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "image_check.h"
#include "tmp_dir.h"
#include "util/atomic_file.h"
#include "util/log.h"

static bool file_is(const char *path, const char *content) {
    size_t len;
    unsigned char *data = tmp_file_read(path, &len);
    bool same = data && len == strlen(content) && memcmp(data, content, len) == 0;
    free(data);
    return same;
}

static void test_write_errors(void) {
    const char *dir = tmp_path("werr");
    mkdir(dir, 0755);
    const char *keep = tmp_path("werr/keep.bmp"), *noext = tmp_path("werr/noext");
    const char *missing = tmp_path("werr/missing/out.ppm"), *blocked = tmp_path("werr/blocked.ppm");
    const char *inner = tmp_path("werr/blocked.ppm/inside");
    tmp_file_write(keep, "original", 8);
    tmp_file_write(noext, "original", 8);
    mkdir(blocked, 0755); /* rename over a folder fails after the temporary is complete */
    tmp_file_write(inner, "x", 1);

    image src;
    make_8bit_image(&src, TONEMAP_SRGB);
    EXPECT(!image_write(keep, &src, TONEMAP_SRGB));
    EXPECT(!image_write(noext, &src, TONEMAP_SRGB));
    EXPECT(!image_write(missing, &src, TONEMAP_SRGB));
    EXPECT(!image_write(blocked, &src, TONEMAP_SRGB));
    image empty = {0};
    EXPECT(!image_write(keep, &empty, TONEMAP_SRGB));
    EXPECT(file_is(keep, "original"));
    EXPECT(file_is(noext, "original"));
    EXPECT(file_is(inner, "x"));
    EXPECT(count_entries(dir) == 3); /* keep.bmp, noext, blocked.ppm: no temporaries */
    image_free(&src);
}

static void test_write_interrupted(void) {
    /* a write failing halfway (file size limit: EFBIG) must leave the old file intact */
    const char *dir = tmp_path("wint");
    mkdir(dir, 0755);
    char dest[600];
    snprintf(dest, sizeof dest, "%s/old.ppm", dir);
    const char *names[] = {"old.ppm", "old.png", "old.pfm"};
    for (int k = 0; k < 3; k++) {
        snprintf(dest, sizeof dest, "%s/%s", dir, names[k]);
        tmp_file_write(dest, "original", 8);
        fflush(NULL);
        pid_t pid = fork();
        if (pid == 0) { /* SIGXFSZ as a shell leaves it: the writer must not die of it */
            signal(SIGXFSZ, SIG_DFL);
            struct rlimit lim;
            getrlimit(RLIMIT_FSIZE, &lim);
            lim.rlim_cur = 1000;
            setrlimit(RLIMIT_FSIZE, &lim);
            image big;
            image_init(&big, 64, 64);
            uint32_t state = 12345; /* noise, so that the PNG cannot compress below the limit */
            for (int i = 0; i < 64 * 64 * 3; i++) {
                state = state * 1664525u + 1013904223u;
                big.rgb[i] = (float)(state >> 24) / 255.0f;
            }
            _exit(image_write(dest, &big, TONEMAP_SRGB) ? 0 : 3);
        }
        int status = 0;
        EXPECT(pid > 0 && waitpid(pid, &status, 0) == pid);
        EXPECT(WIFEXITED(status) && WEXITSTATUS(status) == 3);
        EXPECT(file_is(dest, "original"));
    }
    EXPECT(count_entries(dir) == 3);
}

/* Writes half a file, then the process is killed as by Ctrl-C or `kill` mid-write. */
static int fill_then_die(FILE *fp, const void *context) {
    fputs("partial", fp);
    fflush(fp);
    raise(*(const int *)context);
    return 0;
}

static void test_write_killed(void) {
    /* a signal in the middle of a write removes the temporary file and keeps the old one */
    const char *dir = tmp_path("wkill");
    mkdir(dir, 0755);
    const int signals[] = {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGPIPE, SIGALRM, SIGXCPU};
    char dest[600];
    snprintf(dest, sizeof dest, "%s/out.png", dir);
    tmp_file_write(dest, "original", 8);
    for (int k = 0; k < (int)(sizeof signals / sizeof signals[0]); k++) {
        fflush(NULL);
        pid_t pid = fork();
        if (pid == 0) { /* as a foreground run gets them: a background job ignores SIGINT */
            signal(signals[k], SIG_DFL);
            setrlimit(RLIMIT_CORE, &(struct rlimit){0, 0}); /* SIGQUIT and SIGXCPU dump core */
            _exit(atomic_file_write(dest, fill_then_die, &signals[k]) ? 0 : 3);
        }
        int status = 0;
        EXPECT(pid > 0 && waitpid(pid, &status, 0) == pid);
        EXPECT(WIFSIGNALED(status) && WTERMSIG(status) == signals[k]);
        EXPECT(file_is(dest, "original"));
        EXPECT(count_entries(dir) == 1);
    }
}

static int fill_hello(FILE *fp, const void *context) {
    (void)context;
    return fputs("hello\n", fp) < 0 ? EIO : 0;
}

static void test_write_special(void) {
    /* a FIFO stays a FIFO and gets the bytes; a symbolic link stays a link to the new content;
     * a link to a missing file creates it */
    const char *dir = tmp_path("wspecial");
    mkdir(dir, 0755);
    const char *fifo = tmp_path("wspecial/pipe.ppm"), *got = tmp_path("wspecial/got");
    const char *target = tmp_path("wspecial/target.scene"), *link = tmp_path("wspecial/link.scene");
    const char *dangling = tmp_path("wspecial/dangling.scene");
    EXPECT(mkfifo(fifo, 0644) == 0);
    fflush(NULL);
    pid_t reader = fork();
    if (reader == 0) { /* copies the FIFO to `got`; gives up after 10 s if nothing writes it */
        alarm(10);
        FILE *in = fopen(fifo, "rb"), *out = fopen(got, "wb");
        int c;
        while (in && out && (c = fgetc(in)) != EOF) fputc(c, out);
        _exit(in && out && fclose(out) == 0 ? 0 : 1);
    }
    EXPECT(atomic_file_write(fifo, fill_hello, NULL));
    int status = 0;
    EXPECT(reader > 0 && waitpid(reader, &status, 0) == reader && WIFEXITED(status) &&
           WEXITSTATUS(status) == 0);
    struct stat st;
    EXPECT(lstat(fifo, &st) == 0 && S_ISFIFO(st.st_mode));
    EXPECT(file_is(got, "hello\n"));
    tmp_file_write(target, "old", 3);
    EXPECT(symlink("target.scene", link) == 0);
    EXPECT(atomic_file_write(link, fill_hello, NULL));
    EXPECT(lstat(link, &st) == 0 && S_ISLNK(st.st_mode));
    EXPECT(file_is(target, "hello\n"));
    /* a link to a missing file creates that file, as the shell's > does, and stays a link; one
     * into a missing folder, or a loop, is an error that creates nothing */
    EXPECT(symlink("new.scene", dangling) == 0);
    EXPECT(atomic_file_write(dangling, fill_hello, NULL));
    EXPECT(lstat(dangling, &st) == 0 && S_ISLNK(st.st_mode));
    EXPECT(file_is(tmp_path("wspecial/new.scene"), "hello\n"));
    const char *lost = tmp_path("wspecial/lost.scene"), *loop = tmp_path("wspecial/loop.scene");
    EXPECT(symlink("missing/nothing.scene", lost) == 0);
    EXPECT(!atomic_file_write(lost, fill_hello, NULL));
    EXPECT(symlink("loop.scene", loop) == 0);
    EXPECT(!atomic_file_write(loop, fill_hello, NULL));
    EXPECT(count_entries(tmp_path("wspecial")) == 8);
}

static void test_write_links(void) {
    /* 40 links in a chain are followed (the kernel's own limit), 41 are a loop; a link to
     * "folder/" names no file to create and is refused before anything is written */
    const char *dir = tmp_path("wlinks");
    mkdir(dir, 0755);
    char name[600], next[600];
    for (int k = 1; k <= 41; k++) {
        snprintf(name, sizeof name, "%s/l%d", dir, k);
        snprintf(next, sizeof next, k == 1 ? "end.txt" : "l%d", k - 1);
        EXPECT(symlink(next, name) == 0);
    }
    snprintf(name, sizeof name, "%s/l40", dir);
    EXPECT(atomic_file_write(name, fill_hello, NULL));
    snprintf(name, sizeof name, "%s/end.txt", dir);
    EXPECT(file_is(name, "hello\n"));
    snprintf(name, sizeof name, "%s/l41", dir);
    EXPECT(!atomic_file_check(name) && !atomic_file_write(name, fill_hello, NULL));
    snprintf(name, sizeof name, "%s/to-folder", dir);
    EXPECT(symlink("newdir/", name) == 0);
    EXPECT(!atomic_file_check(name));
    /* As root, another user's link in a sticky world-writable folder (/tmp) is not followed,
     * as the kernel's fs.protected_symlinks would not: it could lead anywhere. */
    if (geteuid() == 0) {
        snprintf(name, sizeof name, "%s/sticky", dir);
        EXPECT(mkdir(name, 0755) == 0 && chmod(name, 01777) == 0);
        snprintf(name, sizeof name, "%s/sticky/theirs.txt", dir);
        EXPECT(symlink("../victim.txt", name) == 0 && lchown(name, 4242, 4242) == 0);
        EXPECT(!atomic_file_write(name, fill_hello, NULL));
        snprintf(name, sizeof name, "%s/victim.txt", dir);
        EXPECT(access(name, F_OK) != 0);
    }
}

static void test_overwrite(void) {
    const char *dir = tmp_path("wover");
    mkdir(dir, 0755);
    const char *names[] = {"a.ppm", "a.png", "a.pfm"};
    image src, back;
    make_8bit_image(&src, TONEMAP_SRGB);
    for (int k = 0; k < 3; k++) {
        char path[600];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        tmp_file_write(path, "original", 8);
        chmod(path, 0600);
        EXPECT(image_write(path, &src, TONEMAP_SRGB));
        EXPECT(image_read(path, &back, TONEMAP_SRGB) && same_image(&back, &src));
        image_free(&back);
        struct stat st; /* the file keeps its own mode */
        EXPECT(stat(path, &st) == 0 && (st.st_mode & 0777) == 0600);
    }
    EXPECT(count_entries(dir) == 3);
    /* A new file gets what open(2) gives: 0666 less the umask. */
    const mode_t masks[] = {022, 077, 002};
    for (int k = 0; k < 3; k++) {
        char path[600];
        snprintf(path, sizeof path, "%s/new%d.png", dir, k);
        mode_t old = umask(masks[k]);
        EXPECT(image_write(path, &src, TONEMAP_SRGB));
        umask(old);
        struct stat st;
        EXPECT(stat(path, &st) == 0 && (st.st_mode & 0777) == (0666 & ~masks[k]));
    }
    image_free(&src);
}

/* Writes data to name and expects image_read to fail cleanly with out zeroed. */
/* The bytes of the 8-bit test image written as the PNG `name` (NULL when unreadable). */
static unsigned char *written_png(const char *name, size_t *len) {
    image src;
    make_8bit_image(&src, TONEMAP_SRGB);
    EXPECT(image_write(tmp_path(name), &src, TONEMAP_SRGB));
    image_free(&src);
    return tmp_file_read(tmp_path(name), len);
}

static void expect_bad(const char *name, const void *data, size_t len) {
    const char *path = tmp_path(name);
    tmp_file_write(path, data, len);
    image img = {7, 7, NULL};
    bool ok = image_read(path, &img, TONEMAP_SRGB);
    if (ok || img.rgb || img.width || img.height) {
        printf("  %s: %s was accepted\n", check_case_name, name);
        EXPECT(!"malformed file rejected");
    }
    image_free(&img);
}

#define BAD(name, lit) expect_bad(name, lit, sizeof lit - 1)

static void test_malformed(void) {
    BAD("empty.ppm", "");
    BAD("magic.ppm", "P5\n6 5\n255\n");
    BAD("magic2.ppm", "P7\n6 5\n255\n\0\0\0");
    BAD("header_only.ppm", "P6\n6 5\n");
    BAD("truncated.ppm", "P6\n6 5\n255\n0123456789");
    BAD("negative.ppm", "P6\n-6 5\n255\n\0\0\0");
    BAD("zero.ppm", "P6\n0 5\n255\n");
    BAD("huge.ppm", "P6\n16385 16384\n255\n\0\0\0");
    BAD("huge2.ppm", "P6\n16384 100000\n255\n\0\0\0");
    BAD("overflow.ppm", "P6\n99999999999999999999 5\n255\n\0\0\0");
    BAD("overflow2.ppm", "P6\n4294967302 5\n255\n\0\0\0");
    BAD("longtoken.ppm", "P6\n111111111111111111111111111111111111111 5\n255\n");
    BAD("maxval.ppm", "P6\n1 1\n65535\n\0\0\0\0\0\0");
    BAD("maxval0.ppm", "P6\n1 1\n0\n\0\0\0");
    BAD("bigclaim.ppm", "P6\n16384 16384\n255\n\0\0\0"); /* fails before allocating 3 GiB */
    BAD("p3_short.ppm", "P3\n2 1\n255\n0 1 2 3 4\n");
    BAD("p3_range.ppm", "P3\n1 1\n255\n0 256 0\n");
    BAD("p3_junk.ppm", "P3\n1 1\n255\n0 x 0\n");
    BAD("empty.pfm", "");
    BAD("magic.pfm", "PX\n1 1\n-1.0\n\0\0\0\0\0\0\0\0\0\0\0\0");
    BAD("truncated.pfm", "PF\n6 5\n-1.0\n\0\0\0\0\0\0\0\0\0\0");
    BAD("scale0.pfm", "Pf\n1 1\n0\n\0\0\0\0");
    BAD("scalenan.pfm", "Pf\n1 1\nnan\n\0\0\0\0");
    BAD("scalejunk.pfm", "Pf\n1 1\n-1.0x\n\0\0\0\0");
    BAD("huge.pfm", "PF\n16384 16384\n-1.0\n\0\0\0\0");
    BAD("negative.pfm", "PF\n6 -5\n-1.0\n\0\0\0\0");
    BAD("garbage.png", "\x89PNG\r\n\x1a\nthis is not a PNG at all, just garbage bytes");
    BAD("text.png", "hello");
    BAD("empty.png", "");
    BAD("noext", "P6\n1 1\n255\n\0\0\0");
    BAD("wrongext.bmp", "P6\n1 1\n255\n\0\0\0");

    /* a real PNG cut in half, and one whose header claims 20000 x 20000 */
    size_t len;
    unsigned char *png = written_png("whole.png", &len);
    EXPECT(png && len > 40);
    if (png && len > 40) {
        expect_bad("half.png", png, len / 2);
        expect_bad("header.png", png, 30);
        /* IHDR width 16385, height 16: past IMAGE_MAX_DIM */
        const unsigned char big[8] = {0, 0, 0x40, 0x01, 0, 0, 0, 0x10};
        memcpy(png + 16, big, 8);
        expect_bad("bigihdr.png", png, len);
    }
    free(png);

    image img;
    EXPECT(!image_read(tmp_path("does_not_exist.ppm"), &img, TONEMAP_SRGB) && !img.rgb);
    mkdir(tmp_path("folder.ppm"), 0755);
    EXPECT(!image_read(tmp_path("folder.ppm"), &img, TONEMAP_SRGB) && !img.rgb);
}

/* Writes a w x h PNG of `bits` bits a sample and color type `type` from packed big-endian rows,
 * with a palette and tRNS when given. */
static void write_png_raw(const char *path, int w, int h, int bits, int type, const uint8_t *data,
                          const png_color *palette, int colors, const uint8_t *alpha) {
    FILE *fp = fopen(path, "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!fp || !png || !info || setjmp(png_jmpbuf(png))) {
        printf("cannot write %s\n", path);
        exit(1);
    }
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, bits, type, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
    if (palette) png_set_PLTE(png, info, palette, colors);
    if (alpha) png_set_tRNS(png, info, alpha, colors, NULL);
    png_write_info(png, info);
    size_t row_bytes = png_get_rowbytes(png, info);
    for (int y = 0; y < h; y++) png_write_row(png, data + (size_t)y * row_bytes);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(fp);
}

/* Reads path, expecting failure with `message` in the error. */
static void expect_refused(const char *path, const char *message) {
    image img = {0};
    log_hold_errors();
    bool ok = image_read(path, &img, TONEMAP_SRGB);
    const char *errors = log_release_errors();
    CHECK(!ok && !img.rgb, "%s was accepted", path);
    CHECK(strstr(errors, message) != NULL, "%s: the error \"%s\" lacks \"%s\"", path, errors,
          message);
    image_free(&img);
}

/* 16 bits a channel are read to 16 bits, not their top 8: 0x1234 and 0x12ff differ. */
static void test_png_16bit(void) {
    const uint16_t values[6] = {0x1234, 0x12ff, 0xffff, 0x0000, 0x8001, 0x0101};
    uint8_t data[12];
    for (int k = 0; k < 6; k++) data[2 * k] = values[k] >> 8, data[2 * k + 1] = values[k] & 0xff;
    const char *path = tmp_path("deep.png");
    write_png_raw(path, 2, 1, 16, PNG_COLOR_TYPE_RGB, data, NULL, 0, NULL);
    image img;
    EXPECT(image_read(path, &img, TONEMAP_LINEAR));
    for (int k = 0; k < 6 && img.rgb; k++)
        CHECK(img.rgb[k] == (float)(values[k] / 65535.0),
              "16-bit sample %d read as %.9g, want %.9g", k, img.rgb[k], values[k] / 65535.0);
    image_free(&img);
    EXPECT(image_read(path, &img, TONEMAP_SRGB));
    if (img.rgb) EXPECT(img.rgb[0] != img.rgb[1] && img.rgb[2] == 1.0f && img.rgb[3] == 0.0f);
    image_free(&img);
}

/* Alpha: opaque RGBA reads as its RGB; a transparent pixel is refused with a reason, not
 * compared as if opaque; so is a palette whose tRNS makes one entry transparent. */
static void test_png_alpha(void) {
    uint8_t rgba[8] = {10, 20, 30, 255, 40, 50, 60, 255};
    write_png_raw(tmp_path("opaque.png"), 2, 1, 8, PNG_COLOR_TYPE_RGBA, rgba, NULL, 0, NULL);
    image img;
    EXPECT(image_read(tmp_path("opaque.png"), &img, TONEMAP_SRGB));
    if (img.rgb) EXPECT(img.rgb[4] == tonemap_decode(50, TONEMAP_SRGB));
    image_free(&img);
    rgba[7] = 0;
    write_png_raw(tmp_path("clear.png"), 2, 1, 8, PNG_COLOR_TYPE_RGBA, rgba, NULL, 0, NULL);
    expect_refused(tmp_path("clear.png"), "transparent");
    const png_color palette[2] = {{0, 0, 0}, {200, 100, 50}};
    const uint8_t index[2] = {0x40, 0}; /* 2 bits a pixel: entries 1 then 0 */
    const uint8_t opaque[2] = {255, 255}, see_through[2] = {255, 0};
    write_png_raw(tmp_path("palette.png"), 2, 1, 2, PNG_COLOR_TYPE_PALETTE, index, palette, 2,
                  opaque);
    EXPECT(image_read(tmp_path("palette.png"), &img, TONEMAP_SRGB));
    if (img.rgb)
        EXPECT(img.rgb[0] == tonemap_decode(200, TONEMAP_SRGB) &&
               img.rgb[2] == tonemap_decode(50, TONEMAP_SRGB) && img.rgb[3] == 0.0f);
    image_free(&img);
    write_png_raw(tmp_path("palette_clear.png"), 2, 1, 2, PNG_COLOR_TYPE_PALETTE, index, palette, 2,
                  see_through);
    expect_refused(tmp_path("palette_clear.png"), "transparent");
    const uint8_t gray[2] = {0x12, 0x34};
    write_png_raw(tmp_path("gray16.png"), 1, 1, 16, PNG_COLOR_TYPE_GRAY, gray, NULL, 0, NULL);
    EXPECT(image_read(tmp_path("gray16.png"), &img, TONEMAP_LINEAR));
    if (img.rgb)
        EXPECT(img.rgb[0] == (float)(0x1234 / 65535.0) && img.rgb[1] == img.rgb[0] &&
               img.rgb[2] == img.rgb[0]);
    image_free(&img);
}

/* A PNG whose IDAT's CRC is wrong, or whose pixel data is damaged, is refused, not read as a
 * different image. */
static void test_png_corrupt(void) {
    size_t len;
    unsigned char *png = written_png("sound.png", &len);
    unsigned char *idat = NULL;
    for (size_t k = 8; png && k + 8 < len && !idat; k++)
        if (!memcmp(png + k, "IDAT", 4)) idat = png + k;
    EXPECT(idat != NULL);
    if (idat) {
        /* The chunk's CRC alone: the pixels are sound, the file is not. */
        uint32_t size = (uint32_t)idat[-4] << 24 | idat[-3] << 16 | idat[-2] << 8 | idat[-1];
        idat[4 + size] ^= 0x01;
        tmp_file_write(tmp_path("bad_crc.png"), png, len);
        expect_refused(tmp_path("bad_crc.png"), "CRC error");
        idat[4 + size] ^= 0x01;
        idat[4 + 10] ^= 0x01; /* a byte of the compressed pixels, well inside the chunk */
        tmp_file_write(tmp_path("damaged.png"), png, len);
        expect_refused(tmp_path("damaged.png"), "corrupt");
    }
    free(png);
}

int main(void) {
    if (!tmp_dir_make("test_image_files")) {
        perror("mkdtemp");
        return 1;
    }
    /* the expected errors are noise; TRAZADOR_TEST_VERBOSE=1 shows them */
    if (!getenv("TRAZADOR_TEST_VERBOSE")) log_set_level((log_level)(LOG_ERROR + 1));
    CHECK_CASE(test_png_16bit);
    CHECK_CASE(test_png_alpha);
    CHECK_CASE(test_png_corrupt);
    CHECK_CASE(test_write_errors);
    CHECK_CASE(test_write_interrupted);
    CHECK_CASE(test_write_killed);
    CHECK_CASE(test_write_special);
    CHECK_CASE(test_write_links);
    CHECK_CASE(test_overwrite);
    CHECK_CASE(test_malformed);
    remove_tree(tmpdir);
    return check_summary("test_image_files");
}
