/* exr.c: OpenEXR read and write through OpenEXRCore, in memory: a write encodes the whole file
 * into a buffer that util/atomic_file.h then writes all or nothing; a read loads the file and
 * decodes it from memory, so a truncated or corrupt file is an error, never a partial image. */
#include "image/exr.h"

#include <errno.h>
#include <math.h>
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "util/atomic_file.h"
#include "util/big_memory.h"
#include "util/log.h"

/* The bytes of a file being encoded or decoded, and the first message the library reported. */
typedef struct exr_io {
    uint8_t *data;
    size_t size, capacity;
    char message[256];
} exr_io;

static void on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
    void *user = NULL;
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
    exr_io *io = user;
    if (!io->message[0])
        snprintf(io->message, sizeof io->message, "%s",
                 msg ? msg : exr_get_default_error_message(code));
}

static int64_t io_write(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t size,
                        uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
    exr_io *io = user;
    if (offset > SIZE_MAX - size) return -1;
    size_t end = (size_t)(offset + size);
    if (end > io->capacity) {
        size_t capacity = io->capacity ? io->capacity : 65536;
        while (capacity < end) capacity = capacity > SIZE_MAX / 2 ? end : capacity * 2;
        uint8_t *grown = realloc(io->data, capacity);
        if (!grown) {
            error_cb(ctxt, EXR_ERR_OUT_OF_MEMORY, "out of memory for %zu bytes", capacity);
            return -1;
        }
        io->data = grown;
        io->capacity = capacity;
    }
    if (offset > io->size) memset(io->data + io->size, 0, (size_t)offset - io->size);
    memcpy(io->data + offset, buffer, (size_t)size);
    if (end > io->size) io->size = end;
    return (int64_t)size;
}

static int64_t io_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t size,
                       uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
    (void)ctxt;
    (void)error_cb;
    const exr_io *io = user;
    if (offset >= io->size) return 0;
    size_t n = io->size - (size_t)offset < size ? io->size - (size_t)offset : (size_t)size;
    memcpy(buffer, io->data + offset, n);
    return (int64_t)n;
}

static int64_t io_size(exr_const_context_t ctxt, void *user) {
    (void)ctxt;
    return (int64_t)((const exr_io *)user)->size;
}

static int fill_from_memory(FILE *fp, const void *context) {
    const exr_io *io = context;
    return fwrite(io->data, 1, io->size, fp) == io->size ? 0 : (errno ? errno : EIO);
}

static exr_context_initializer_t initializer(exr_io *io) {
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_error;
    init.user_data = io;
    init.read_fn = io_read;
    init.size_fn = io_size;
    init.write_fn = io_write;
    init.max_image_width = IMAGE_MAX_DIM;
    init.max_image_height = IMAGE_MAX_DIM;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    return init;
}

/* Logs why the library failed, with its first message when it gave one; returns false. */
static bool fail(const char *path, const exr_io *io, exr_result_t rc, const char *what) {
    log_error("%s: %s: %s", path, what,
              io->message[0] ? io->message : exr_get_default_error_message(rc));
    return false;
}

static size_t sample_bytes(exr_sample_type type) { return type == EXR_SAMPLE_HALF ? 2 : 4; }

static exr_pixel_type_t pixel_type(exr_sample_type type) {
    return type == EXR_SAMPLE_UINT   ? EXR_PIXEL_UINT
           : type == EXR_SAMPLE_HALF ? EXR_PIXEL_HALF
                                     : EXR_PIXEL_FLOAT;
}

uint16_t exr_half_from_float(float x) {
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    uint16_t sign = (uint16_t)((u >> 16) & 0x8000u);
    uint32_t mag = u & 0x7fffffffu;
    if (mag >= 0x7f800000u) return sign | 0x7c00u | (mag > 0x7f800000u ? 0x200u : 0u);
    if (mag >= 0x477ff000u) return sign | 0x7c00u; /* 65520 and up round past 65504 */
    if (mag < 0x38800000u) /* below 2^-14: a multiple of 2^-24, rounded to even by rintf */
        return sign | (uint16_t)rintf(fabsf(x) * 0x1p24f);
    uint32_t v = mag - 0x38000000u; /* exponent bias 127 -> 15 */
    uint32_t half = v >> 13, rest = v & 0x1fffu;
    if (rest > 0x1000u || (rest == 0x1000u && (half & 1u))) half++;
    return sign | (uint16_t)half;
}

float exr_half_to_float(uint16_t h) {
    uint32_t sign = (uint32_t)(h & 0x8000u) << 16, e = (h >> 10) & 0x1fu, m = h & 0x3ffu;
    float f;
    uint32_t u;
    if (e == 0) {
        f = (float)m * 0x1p-24f;
        memcpy(&u, &f, sizeof u);
    } else {
        u = (e == 31 ? 0x7f800000u : (e + 112u) << 23) | (m << 13);
    }
    u |= sign;
    memcpy(&f, &u, sizeof f);
    return f;
}

/* Whether f can be written: sizes, windows and names; false (logged) if not. */
static bool file_valid(const char *path, const exr_file *f) {
    if (f->display_width < 1 || f->display_height < 1 || f->display_width > IMAGE_MAX_DIM ||
        f->display_height > IMAGE_MAX_DIM || f->width < 1 || f->height < 1 || f->x0 < 0 ||
        f->y0 < 0 || f->x0 + f->width > f->display_width || f->y0 + f->height > f->display_height) {
        log_error("%s: data window %dx%d at (%d, %d) is not inside a %dx%d image of at most %d",
                  path, f->width, f->height, f->x0, f->y0, f->display_width, f->display_height,
                  IMAGE_MAX_DIM);
        return false;
    }
    if (f->channel_count < 1) {
        log_error("%s: an EXR file needs at least one channel", path);
        return false;
    }
    for (int c = 0; c < f->channel_count; c++) {
        if (!f->channels[c].name[0] || !f->channels[c].data) {
            log_error("%s: channel %d has no name or no data", path, c);
            return false;
        }
        for (int d = 0; d < c; d++)
            if (!strcmp(f->channels[c].name, f->channels[d].name)) {
                log_error("%s: two channels are called '%s'", path, f->channels[c].name);
                return false;
            }
    }
    return true;
}

/* Declares the part, its channels and attributes; false (logged) on failure. */
static bool write_header(exr_context_t ctx, const char *path, const exr_io *io, const exr_file *f) {
    int part = 0;
    exr_result_t rc = exr_add_part(ctx, NULL, EXR_STORAGE_SCANLINE, &part);
    exr_attr_box2i_t display = {{{{0, 0}}}, {{{f->display_width - 1, f->display_height - 1}}}};
    exr_attr_box2i_t data = {{{{f->x0, f->y0}}}, {{{f->x0 + f->width - 1, f->y0 + f->height - 1}}}};
    exr_attr_v2f_t center = {{{0.0f, 0.0f}}};
    if (rc == EXR_ERR_SUCCESS)
        rc = exr_initialize_required_attr(
            ctx, part, &display, &data, 1.0f, &center, 1.0f, EXR_LINEORDER_INCREASING_Y,
            f->uncompressed ? EXR_COMPRESSION_NONE : EXR_COMPRESSION_ZIP);
    if (rc != EXR_ERR_SUCCESS) return fail(path, io, rc, "cannot start the header");
    bool long_names = false;
    for (int c = 0; c < f->channel_count; c++) long_names |= strlen(f->channels[c].name) > 31;
    for (int a = 0; a < f->attr_count; a++) long_names |= strlen(f->attrs[a].name) > 31;
    if (long_names && (rc = exr_set_longname_support(ctx, 1)) != EXR_ERR_SUCCESS)
        return fail(path, io, rc, "long names");
    for (int c = 0; c < f->channel_count; c++) {
        rc = exr_add_channel(ctx, part, f->channels[c].name, pixel_type(f->channels[c].type),
                             EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1);
        if (rc != EXR_ERR_SUCCESS) return fail(path, io, rc, f->channels[c].name);
    }
    for (int a = 0; a < f->attr_count; a++) {
        rc = exr_attr_set_string(ctx, part, f->attrs[a].name, f->attrs[a].value);
        if (rc != EXR_ERR_SUCCESS) return fail(path, io, rc, f->attrs[a].name);
    }
    rc = exr_write_header(ctx);
    return rc == EXR_ERR_SUCCESS || fail(path, io, rc, "cannot write the header");
}

/* Encodes every scanline chunk of f; false (logged) on failure. */
static bool write_pixels(exr_context_t ctx, const char *path, const exr_io *io, const exr_file *f) {
    int32_t lines = 1;
    exr_result_t rc = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int y = f->y0; rc == EXR_ERR_SUCCESS && y < f->y0 + f->height; y += lines) {
        exr_chunk_info_t chunk;
        rc = exr_write_scanline_chunk_info(ctx, 0, y, &chunk);
        if (rc != EXR_ERR_SUCCESS) break;
        rc = started ? exr_encoding_update(ctx, 0, &chunk, &enc)
                     : exr_encoding_initialize(ctx, 0, &chunk, &enc);
        if (rc != EXR_ERR_SUCCESS) break;
        for (int16_t k = 0; k < enc.channel_count; k++) {
            exr_coding_channel_info_t *ch = &enc.channels[k];
            const exr_channel *src = exr_file_channel(f, ch->channel_name);
            size_t bytes = sample_bytes(src->type);
            ch->user_bytes_per_element = (int16_t)bytes;
            ch->user_data_type = ch->data_type;
            ch->user_pixel_stride = (int32_t)bytes;
            ch->user_line_stride = (int32_t)(bytes * (size_t)f->width);
            ch->encode_from_ptr = (const uint8_t *)src->data +
                                  (size_t)(chunk.start_y - f->y0) * (size_t)f->width * bytes;
        }
        if (!started) rc = exr_encoding_choose_default_routines(ctx, 0, &enc);
        started = true;
        if (rc == EXR_ERR_SUCCESS) rc = exr_encoding_run(ctx, 0, &enc);
    }
    if (started) exr_encoding_destroy(ctx, &enc);
    return rc == EXR_ERR_SUCCESS || fail(path, io, rc, "cannot encode the pixels");
}

bool exr_file_write(const char *path, const exr_file *f) {
    if (!file_valid(path, f)) return false;
    exr_io io = {0};
    exr_context_initializer_t init = initializer(&io);
    exr_context_t ctx = NULL;
    exr_result_t rc = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    bool ok = rc == EXR_ERR_SUCCESS
                  ? write_header(ctx, path, &io, f) && write_pixels(ctx, path, &io, f)
                  : fail(path, &io, rc, "cannot start writing");
    if (ctx) {
        rc = exr_finish(&ctx);
        if (ok && rc != EXR_ERR_SUCCESS) ok = fail(path, &io, rc, "cannot finish the file");
    }
    ok = ok && atomic_file_write(path, fill_from_memory, &io);
    free(io.data);
    return ok;
}

/* Loads the whole file into io; false (logged) on failure. */
static bool load(const char *path, exr_io *io) {
    FILE *fp = fopen(path, "rb");
    if (!fp) {
        log_error("%s: %s", path, strerror(errno));
        return false;
    }
    bool ok = true;
    for (;;) {
        if (io->size == io->capacity) {
            size_t capacity = io->capacity ? io->capacity * 2 : 65536;
            uint8_t *grown = capacity > io->capacity ? realloc(io->data, capacity) : NULL;
            if (!grown) {
                log_error("%s: out of memory reading the file", path);
                ok = false;
                break;
            }
            io->data = grown;
            io->capacity = capacity;
        }
        size_t n = fread(io->data + io->size, 1, io->capacity - io->size, fp);
        io->size += n;
        if (n == 0) {
            if (ferror(fp)) {
                log_error("%s: %s", path, strerror(errno ? errno : EIO));
                ok = false;
            }
            break;
        }
    }
    fclose(fp);
    return ok;
}

/* The type of a channel the file declares; false for none trazador knows. */
static bool sample_type_of(exr_pixel_type_t t, exr_sample_type *out) {
    if (t == EXR_PIXEL_UINT)
        *out = EXR_SAMPLE_UINT;
    else if (t == EXR_PIXEL_HALF)
        *out = EXR_SAMPLE_HALF;
    else if (t == EXR_PIXEL_FLOAT)
        *out = EXR_SAMPLE_FLOAT;
    else
        return false;
    return true;
}

/* Reads the windows, the channel list and the string attributes; false (logged) on failure. */
static bool read_header(exr_context_t ctx, const char *path, const exr_io *io, exr_file *out) {
    int parts = 0;
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    exr_result_t rc = exr_get_count(ctx, &parts);
    if (rc == EXR_ERR_SUCCESS) rc = exr_get_storage(ctx, 0, &storage);
    if (rc != EXR_ERR_SUCCESS) return fail(path, io, rc, "unreadable header");
    if (parts != 1 || storage != EXR_STORAGE_SCANLINE) {
        log_error("%s: %d parts, storage %d: only single-part scanline EXR files are read", path,
                  parts, (int)storage);
        return false;
    }
    exr_attr_box2i_t display, data;
    const exr_attr_chlist_t *list = NULL;
    rc = exr_get_display_window(ctx, 0, &display);
    if (rc == EXR_ERR_SUCCESS) rc = exr_get_data_window(ctx, 0, &data);
    if (rc == EXR_ERR_SUCCESS) rc = exr_get_channels(ctx, 0, &list);
    if (rc != EXR_ERR_SUCCESS) return fail(path, io, rc, "unreadable header");
    long dw = (long)display.max.x + 1, dh = (long)display.max.y + 1;
    long w = (long)data.max.x - data.min.x + 1, h = (long)data.max.y - data.min.y + 1;
    if (display.min.x != 0 || display.min.y != 0 || dw < 1 || dh < 1 || dw > IMAGE_MAX_DIM ||
        dh > IMAGE_MAX_DIM || data.min.x < 0 || data.min.y < 0 || w < 1 || h < 1 ||
        data.max.x >= dw || data.max.y >= dh) {
        log_error(
            "%s: display window (%d, %d)-(%d, %d) or data window (%d, %d)-(%d, %d) not "
            "supported: the display window must start at (0, 0), be at most %d wide and "
            "high, and hold the data window",
            path, display.min.x, display.min.y, display.max.x, display.max.y, data.min.x,
            data.min.y, data.max.x, data.max.y, IMAGE_MAX_DIM);
        return false;
    }
    *out = (exr_file){.display_width = (int)dw,
                      .display_height = (int)dh,
                      .x0 = data.min.x,
                      .y0 = data.min.y,
                      .width = (int)w,
                      .height = (int)h};
    out->channels = calloc((size_t)list->num_channels + 1, sizeof *out->channels);
    if (!out->channels) {
        log_error("%s: out of memory", path);
        return false;
    }
    for (int c = 0; c < list->num_channels; c++) {
        const exr_attr_chlist_entry_t *e = &list->entries[c];
        exr_channel *ch = &out->channels[c];
        if (!sample_type_of(e->pixel_type, &ch->type) || e->x_sampling != 1 || e->y_sampling != 1 ||
            e->name.length > EXR_NAME_MAX) {
            log_error("%s: channel '%s' is subsampled or of an unknown type", path, e->name.str);
            return false;
        }
        memcpy(ch->name, e->name.str, (size_t)e->name.length);
        ch->data = big_calloc((size_t)w * (size_t)h, sample_bytes(ch->type));
        if (!ch->data) {
            log_error("%s: out of memory for channel '%s'", path, ch->name);
            return false;
        }
        out->channel_count = c + 1;
    }
    int32_t count = 0;
    if ((rc = exr_get_attribute_count(ctx, 0, &count)) != EXR_ERR_SUCCESS)
        return fail(path, io, rc, "unreadable header");
    out->attrs = calloc((size_t)count + 1, sizeof *out->attrs);
    if (!out->attrs) {
        log_error("%s: out of memory", path);
        return false;
    }
    for (int32_t a = 0; a < count; a++) {
        const exr_attribute_t *attr = NULL;
        rc = exr_get_attribute_by_index(ctx, 0, EXR_ATTR_LIST_FILE_ORDER, a, &attr);
        if (rc != EXR_ERR_SUCCESS) return fail(path, io, rc, "unreadable header");
        /* Other types, and strings too long to be trazador's, are not ours to read. */
        if (attr->type != EXR_ATTR_STRING || attr->string->length < 0 ||
            attr->string->length > EXR_VALUE_MAX ||
            memchr(attr->string->str, '\0', (size_t)attr->string->length))
            continue;
        exr_attr *dst = &out->attrs[out->attr_count++];
        memcpy(dst->name, attr->name, attr->name_length);
        memcpy(dst->value, attr->string->str, (size_t)attr->string->length);
    }
    return true;
}

/* Decodes every scanline chunk into out's channels; false (logged) on failure. */
static bool read_pixels(exr_context_t ctx, const char *path, const exr_io *io, exr_file *out) {
    int32_t lines = 1;
    exr_result_t rc = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool started = false;
    for (int y = out->y0; rc == EXR_ERR_SUCCESS && y < out->y0 + out->height; y += lines) {
        exr_chunk_info_t chunk;
        rc = exr_read_scanline_chunk_info(ctx, 0, y, &chunk);
        if (rc != EXR_ERR_SUCCESS) break;
        rc = started ? exr_decoding_update(ctx, 0, &chunk, &dec)
                     : exr_decoding_initialize(ctx, 0, &chunk, &dec);
        if (rc != EXR_ERR_SUCCESS) break;
        for (int16_t k = 0; k < dec.channel_count; k++) {
            exr_coding_channel_info_t *ch = &dec.channels[k];
            const exr_channel *dst = exr_file_channel(out, ch->channel_name);
            size_t bytes = sample_bytes(dst->type);
            ch->user_bytes_per_element = (int16_t)bytes;
            ch->user_data_type = ch->data_type;
            ch->user_pixel_stride = (int32_t)bytes;
            ch->user_line_stride = (int32_t)(bytes * (size_t)out->width);
            ch->decode_to_ptr = (uint8_t *)dst->data +
                                (size_t)(chunk.start_y - out->y0) * (size_t)out->width * bytes;
        }
        if (!started) rc = exr_decoding_choose_default_routines(ctx, 0, &dec);
        started = true;
        if (rc == EXR_ERR_SUCCESS) rc = exr_decoding_run(ctx, 0, &dec);
    }
    if (started) exr_decoding_destroy(ctx, &dec);
    return rc == EXR_ERR_SUCCESS || fail(path, io, rc, "corrupt or truncated pixel data");
}

bool exr_file_read(const char *path, exr_file *out) {
    *out = (exr_file){0};
    exr_io io = {0};
    if (!load(path, &io)) {
        free(io.data);
        return false;
    }
    exr_context_initializer_t init = initializer(&io);
    exr_context_t ctx = NULL;
    exr_result_t rc = exr_start_read(&ctx, path, &init);
    bool ok = rc == EXR_ERR_SUCCESS
                  ? read_header(ctx, path, &io, out) && read_pixels(ctx, path, &io, out)
                  : fail(path, &io, rc, "not an EXR file, or a damaged or truncated one");
    if (ctx) exr_finish(&ctx);
    free(io.data);
    if (!ok) exr_file_free(out);
    return ok;
}

void exr_file_free(exr_file *f) {
    for (int c = 0; f->channels && c < f->channel_count; c++) free(f->channels[c].data);
    free(f->channels);
    free(f->attrs);
    *f = (exr_file){0};
}

const exr_channel *exr_file_channel(const exr_file *f, const char *name) {
    for (int c = 0; c < f->channel_count; c++)
        if (!strcmp(f->channels[c].name, name)) return &f->channels[c];
    return NULL;
}

const char *exr_file_attr(const exr_file *f, const char *name) {
    for (int a = 0; a < f->attr_count; a++)
        if (!strcmp(f->attrs[a].name, name)) return f->attrs[a].value;
    return NULL;
}
