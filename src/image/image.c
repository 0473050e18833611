/* image.c: float RGB images: film resolve, tonemapping, and atomic PPM/PNG/PFM read and write (the
 * PNG coding itself in image_png.c). */
#include "image/image.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "image/exr.h"
#include "image/image_png.h"
#include "util/atomic_file.h"
#include "util/big_memory.h"
#include "util/log.h"

typedef enum image_format {
    FORMAT_NONE,
    FORMAT_PPM,
    FORMAT_PNG,
    FORMAT_PFM,
    FORMAT_EXR
} image_format;

/* The format called `name` ("ppm", "png", "pfm" or "exr", any case). */
static image_format format_named(const char *name) {
    if (strcasecmp(name, "ppm") == 0) return FORMAT_PPM;
    if (strcasecmp(name, "png") == 0) return FORMAT_PNG;
    if (strcasecmp(name, "pfm") == 0) return FORMAT_PFM;
    if (strcasecmp(name, "exr") == 0) return FORMAT_EXR;
    return FORMAT_NONE;
}

/* The format of a path's extension. */
static image_format format_of(const char *path) {
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash + 1 : path, '.');
    return dot ? format_named(dot + 1) : FORMAT_NONE;
}

const char *image_path_format(const char *path) {
    static const char *const names[] = {
        [FORMAT_PPM] = "ppm", [FORMAT_PNG] = "png", [FORMAT_PFM] = "pfm", [FORMAT_EXR] = "exr"};
    image_format fmt = format_of(path);
    return fmt == FORMAT_NONE ? NULL : names[fmt];
}

static bool size_ok(long width, long height) {
    return width >= 1 && height >= 1 && width <= IMAGE_MAX_DIM && height <= IMAGE_MAX_DIM;
}

bool image_init(image *img, int width, int height) {
    *img = (image){0};
    if (!size_ok(width, height)) {
        log_error("image size %dx%d is outside 1..%d", width, height, IMAGE_MAX_DIM);
        return false;
    }
    img->rgb = big_calloc((size_t)width * (size_t)height * 3, sizeof(float));
    if (!img->rgb) {
        log_error("out of memory for a %dx%d image", width, height);
        return false;
    }
    img->width = width;
    img->height = height;
    return true;
}

bool image_from_film(const film *f, image *out) {
    if (!f->accum) {
        *out = (image){0};
        log_error("cannot resolve an empty film");
        return false;
    }
    if (!image_init(out, f->width, f->height)) return false;
    size_t n = (size_t)f->width * (size_t)f->height;
    for (size_t i = 0; i < n; i++) {
        const float *a = f->accum + 4 * i;
        for (int c = 0; c < 3; c++) out->rgb[3 * i + c] = a[3] > 0.0f ? a[c] / a[3] : 0.0f;
    }
    return true;
}

void image_free(image *img) {
    free(img->rgb);
    *img = (image){0};
}

double tonemap_encode(float linear, tonemap tm) {
    double v = linear;
    if (!(v > 0.0)) return 0.0; /* negatives and NaN */
    if (v > 1.0) v = 1.0;
    if (tm == TONEMAP_SRGB) v = v < 0.0031308 ? 12.92 * v : 1.055 * pow(v, 1.0 / 2.4) - 0.055;
    return v;
}

uint8_t tonemap_channel(float linear, tonemap tm) {
    return (uint8_t)(tonemap_encode(linear, tm) * 255.0 + 0.5);
}

void tonemap_table_init(tonemap_table *t, tonemap tm) {
    /* Non-negative floats order as their bit patterns, and the encoding never decreases. */
    const uint32_t one = 0x3f800000u;
    float f;
    t->bound[0] = 0.0f;
    for (int k = 1; k < 256; k++) {
        uint32_t lo = 0, hi = one; /* tonemap_channel(1.0f) is 255 >= k */
        while (lo < hi) {
            uint32_t mid = lo + (hi - lo) / 2;
            memcpy(&f, &mid, sizeof f);
            if (tonemap_channel(f, tm) >= k)
                hi = mid;
            else
                lo = mid + 1;
        }
        memcpy(&t->bound[k], &lo, sizeof lo);
    }
    t->bound[256] = INFINITY;
    for (uint32_t i = 0; i < TONEMAP_TABLE_STARTS; i++) {
        uint32_t bits = i << 16;
        memcpy(&f, &bits, sizeof f);
        t->start[i] = tonemap_channel(f, tm);
    }
}

float tonemap_decode(uint8_t value, tonemap tm) {
    double c = value / 255.0;
    if (tm == TONEMAP_SRGB) c = c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4);
    return (float)c;
}

/* ---- writing: each writer returns 0 or an errno value ---- */

static int write_error(void) { return errno ? errno : EIO; }

static uint8_t *encode_8bit(const image *img, tonemap tm) {
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    uint8_t *bytes = big_malloc(n);
    tonemap_table table;
    tonemap_table_init(&table, tm);
    if (bytes)
        for (size_t i = 0; i < n; i++) bytes[i] = tonemap_table_channel(&table, img->rgb[i]);
    return bytes;
}

static int write_ppm(FILE *fp, const image *img, tonemap tm) {
    uint8_t *bytes = encode_8bit(img, tm);
    if (!bytes) return ENOMEM;
    size_t n = (size_t)img->width * (size_t)img->height * 3;
    int err = 0;
    if (fprintf(fp, "P6\n%d %d\n255\n", img->width, img->height) < 0 ||
        fwrite(bytes, 1, n, fp) != n)
        err = write_error();
    free(bytes);
    return err;
}

static int write_pfm(FILE *fp, const image *img, tonemap tm) {
    (void)tm; /* PFM is linear */
    size_t row_floats = (size_t)img->width * 3;
    uint8_t *row = malloc(row_floats * 4);
    if (!row) return ENOMEM;
    int err = 0;
    if (fprintf(fp, "PF\n%d %d\n-1.0\n", img->width, img->height) < 0) err = write_error();
    /* PFM rows run bottom to top; the negative scale says little-endian */
    for (int y = img->height - 1; y >= 0 && !err; y--) {
        const float *src = img->rgb + (size_t)y * row_floats;
        for (size_t i = 0; i < row_floats; i++) {
            uint32_t u;
            memcpy(&u, &src[i], 4);
            for (int b = 0; b < 4; b++) row[4 * i + b] = (uint8_t)(u >> (8 * b));
        }
        if (fwrite(row, 4, row_floats, fp) != row_floats) err = write_error();
    }
    free(row);
    return err;
}

static int (*const writers[])(FILE *, const image *, tonemap) = {
    [FORMAT_PPM] = write_ppm, [FORMAT_PNG] = image_png_write, [FORMAT_PFM] = write_pfm};

typedef struct image_sink {
    image_format format;
    const image *img;
    tonemap tm;
} image_sink;

static int write_image(FILE *fp, const void *context) {
    const image_sink *sink = context;
    return writers[sink->format](fp, sink->img, sink->tm);
}

bool image_write(const char *path, const image *img, tonemap tm) {
    return image_write_as(path, NULL, img, tm);
}

bool image_write_film(const char *path, const char *format, const film *f, tonemap tm,
                      bool exr_half) {
    image img = {0};
    image_format fmt = format ? format_named(format) : format_of(path);
    bool ok = image_from_film(f, &img) &&
              (fmt == FORMAT_EXR ? exr_write_image_aov(path, &img, exr_half, &f->aov)
                                 : image_write_as(path, format, &img, tm));
    image_free(&img);
    return ok;
}

bool image_write_as(const char *path, const char *format, const image *img, tonemap tm) {
    image_format fmt = format ? format_named(format) : format_of(path);
    if (fmt == FORMAT_NONE) {
        log_error("%s: unknown image format (supported: .ppm, .png, .pfm, .exr)", path);
        return false;
    }
    if (fmt == FORMAT_EXR) return exr_write_image(path, img, true); /* half: exr.h for float */
    if (!img->rgb || !size_ok(img->width, img->height)) {
        log_error("%s: cannot write an invalid %dx%d image", path, img->width, img->height);
        return false;
    }
    /* A failed or interrupted write never leaves a truncated image nor destroys an existing one. */
    image_sink sink = {fmt, img, tm};
    return atomic_file_write(path, write_image, &sink);
}

/* ---- reading: each reader logs its own errors; image_read frees out on failure ---- */

/* Reads the next whitespace-separated header token, skipping # comments; false at EOF or when
   longer than size - 1. Consumes the one whitespace character after the token. */
static bool read_token(FILE *fp, char *buf, size_t size) {
    int c;
    for (;;) {
        c = getc(fp);
        if (c == '#')
            while (c != '\n' && c != EOF) c = getc(fp);
        if (c == EOF) return false;
        if (!isspace(c)) break;
    }
    size_t n = 0;
    while (c != EOF && !isspace(c) && c != '#') {
        if (n + 1 >= size) return false;
        buf[n++] = (char)c;
        c = getc(fp);
    }
    if (c == '#') ungetc(c, fp);
    buf[n] = '\0';
    return true;
}

/* Decimal digits only, at most max. */
static bool parse_uint(const char *s, long max, long *out) {
    long v = 0;
    if (!*s) return false;
    for (; *s; s++) {
        if (!isdigit((unsigned char)*s)) return false;
        v = v * 10 + (*s - '0');
        if (v > max) return false;
    }
    *out = v;
    return true;
}

static bool parse_size(const char *path, const char *ws, const char *hs, int *w, int *h) {
    long lw, lh;
    if (!parse_uint(ws, IMAGE_MAX_DIM, &lw) || !parse_uint(hs, IMAGE_MAX_DIM, &lh) ||
        !size_ok(lw, lh)) {
        log_error("%s: image size '%s x %s' is not within 1..%d", path, ws, hs, IMAGE_MAX_DIM);
        return false;
    }
    *w = (int)lw;
    *h = (int)lh;
    return true;
}

/* False when a regular file has fewer than `need` bytes left, so that a truncated file fails
   before any large allocation. */
static bool bytes_left(FILE *fp, uint64_t need) {
    struct stat st;
    long pos = ftell(fp);
    if (pos < 0 || fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode)) return true;
    return st.st_size >= pos && (uint64_t)(st.st_size - pos) >= need;
}

static bool fail_header(FILE *fp, const char *path, const char *kind) {
    if (ferror(fp))
        log_error("%s: %s", path, strerror(errno));
    else
        log_error("%s: truncated or malformed %s header", path, kind);
    return false;
}

static bool fail_truncated(FILE *fp, const char *path) {
    if (ferror(fp))
        log_error("%s: %s", path, strerror(errno));
    else
        log_error("%s: truncated file (less pixel data than the header says)", path);
    return false;
}

static bool read_ppm(FILE *fp, const char *path, image *out, tonemap tm) {
    char tok[4][24];
    for (int i = 0; i < 4; i++) {
        if (!read_token(fp, tok[i], sizeof tok[i])) return fail_header(fp, path, "PPM");
    }
    bool ascii = strcmp(tok[0], "P3") == 0;
    if (!ascii && strcmp(tok[0], "P6") != 0) {
        log_error("%s: not a P6 or P3 PPM file", path);
        return false;
    }
    int w, h;
    long maxval;
    if (!parse_size(path, tok[1], tok[2], &w, &h)) return false;
    if (!parse_uint(tok[3], 65535, &maxval) || maxval != 255) {
        log_error("%s: unsupported PPM maxval '%s' (only 255)", path, tok[3]);
        return false;
    }
    size_t n = (size_t)w * (size_t)h * 3;
    /* a P3 sample takes at least a digit and a separator */
    if (!bytes_left(fp, ascii ? 2 * n - 1 : n)) return fail_truncated(fp, path);
    if (!image_init(out, w, h)) return false;
    float lut[256];
    for (int i = 0; i < 256; i++) lut[i] = tonemap_decode((uint8_t)i, tm);
    if (ascii) {
        for (size_t i = 0; i < n; i++) {
            char num[8];
            long v;
            if (!read_token(fp, num, sizeof num) || !parse_uint(num, 255, &v)) {
                log_error("%s: bad or missing P3 sample %zu of %zu", path, i + 1, n);
                return false;
            }
            out->rgb[i] = lut[v];
        }
        return true;
    }
    size_t row_bytes = (size_t)w * 3;
    uint8_t *row = malloc(row_bytes);
    if (!row) {
        log_error("%s: %s", path, strerror(ENOMEM));
        return false;
    }
    bool ok = true;
    for (int y = 0; y < h && ok; y++) {
        ok = fread(row, 1, row_bytes, fp) == row_bytes;
        for (size_t i = 0; i < row_bytes && ok; i++)
            out->rgb[(size_t)y * row_bytes + i] = lut[row[i]];
    }
    free(row);
    return ok || fail_truncated(fp, path);
}

static bool read_pfm(FILE *fp, const char *path, image *out) {
    char tok[4][40];
    for (int i = 0; i < 4; i++) {
        if (!read_token(fp, tok[i], sizeof tok[i])) return fail_header(fp, path, "PFM");
    }
    int channels = strcmp(tok[0], "PF") == 0 ? 3 : strcmp(tok[0], "Pf") == 0 ? 1 : 0;
    if (!channels) {
        log_error("%s: not a PF or Pf PFM file", path);
        return false;
    }
    int w, h;
    if (!parse_size(path, tok[1], tok[2], &w, &h)) return false;
    char *end;
    double scale = strtod(tok[3], &end);
    if (*end || !isfinite(scale) || scale == 0.0) {
        log_error("%s: bad PFM scale '%s'", path, tok[3]);
        return false;
    }
    bool little = scale < 0.0; /* the magnitude is only a hint and is ignored, as usual */
    size_t row_floats = (size_t)w * (size_t)channels;
    if (!bytes_left(fp, (uint64_t)row_floats * (uint64_t)h * 4)) return fail_truncated(fp, path);
    if (!image_init(out, w, h)) return false;
    uint8_t *row = malloc(row_floats * 4);
    if (!row) {
        log_error("%s: %s", path, strerror(ENOMEM));
        return false;
    }
    bool ok = true;
    for (int y = h - 1; y >= 0 && ok; y--) { /* rows run bottom to top */
        ok = fread(row, 4, row_floats, fp) == row_floats;
        for (size_t i = 0; i < row_floats && ok; i++) {
            const uint8_t *b = row + 4 * i;
            uint32_t u = little ? (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 |
                                      (uint32_t)b[3] << 24
                                : (uint32_t)b[3] | (uint32_t)b[2] << 8 | (uint32_t)b[1] << 16 |
                                      (uint32_t)b[0] << 24;
            float v;
            memcpy(&v, &u, 4);
            float *px = out->rgb + ((size_t)y * (size_t)w + i / (size_t)channels) * 3;
            if (channels == 1)
                px[0] = px[1] = px[2] = v;
            else
                px[i % 3] = v;
        }
    }
    free(row);
    return ok || fail_truncated(fp, path);
}

bool image_read(const char *path, image *out, tonemap tm) {
    *out = (image){0};
    image_format fmt = format_of(path);
    if (fmt == FORMAT_NONE) {
        log_error("%s: unknown image format (supported: .ppm, .png, .pfm, .exr)", path);
        return false;
    }
    if (fmt == FORMAT_EXR) return exr_read_image(path, out);
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        log_error("%s: %s", path, strerror(errno));
        return false;
    }
    bool ok = fmt == FORMAT_PPM   ? read_ppm(fp, path, out, tm)
              : fmt == FORMAT_PNG ? image_png_read(fp, path, out, tm)
                                  : read_pfm(fp, path, out);
    fclose(fp);
    if (!ok) image_free(out);
    return ok;
}
