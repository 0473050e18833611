/* texture_exr.c: an OpenEXR image's bytes as texels through OpenEXRCore: its data window's R, G,
 * B and A channels (or Y, a grey image), half, float or uint, as four linear floats a texel;
 * alpha 1 where it has none. Single-part scanline files; an image without colour channels is
 * refused. */
#include <openexr.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "scene/texture.h"
#include "shared_layout.h"

typedef struct exr_memory {
    const uint8_t *bytes;
    size_t size;
    char message[160];
} exr_memory;

static void on_error(exr_const_context_t ctxt, exr_result_t code, const char *msg) {
    void *user = NULL;
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user) return;
    exr_memory *m = user;
    if (!m->message[0])
        snprintf(m->message, sizeof m->message, "%s",
                 msg ? msg : exr_get_default_error_message(code));
}

static int64_t on_read(exr_const_context_t ctxt, void *user, void *buffer, uint64_t size,
                       uint64_t offset, exr_stream_error_func_ptr_t error_cb) {
    (void)ctxt;
    (void)error_cb;
    const exr_memory *m = user;
    if (offset >= m->size) return 0;
    uint64_t n = m->size - offset < size ? m->size - offset : size;
    memcpy(buffer, m->bytes + offset, (size_t)n);
    return (int64_t)n;
}

static int64_t on_size(exr_const_context_t ctxt, void *user) {
    (void)ctxt;
    return (int64_t)((const exr_memory *)user)->size;
}

/* Which texel channel (0 R, 1 G, 2 B, 3 A) an EXR channel fills, 4 for Y, -1 for none. */
static int texel_channel(const char *name) {
    static const char *names[5] = {"R", "G", "B", "A", "Y"};
    for (int c = 0; c < 5; c++)
        if (!strcmp(name, names[c])) return c;
    return -1;
}

/* Decodes every scanline chunk into planes (R, G, B, A, Y and a scratch plane for the other
 * channels: a float plane each of out's size); false with the reason in error. Planes, not out's
 * interleaved texels: OpenEXRCore 3.1's interleaving unpacker put R, G, B, A in reverse order;
 * every channel gets a plane: its unpackers wrote through a NULL one. */
static bool decode_pixels(exr_context_t ctx, exr_attr_box2i_t data, const texture_image *out,
                          float *planes, exr_memory *m, char *error, size_t error_size) {
    int32_t lines = 1;
    exr_result_t rc = exr_get_scanlines_per_chunk(ctx, 0, &lines);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool started = false;
    size_t plane = (size_t)out->width * out->height;
    for (int y = data.min.y; rc == EXR_ERR_SUCCESS && y <= data.max.y; y += lines) {
        exr_chunk_info_t chunk;
        rc = exr_read_scanline_chunk_info(ctx, 0, y, &chunk);
        if (rc != EXR_ERR_SUCCESS) break;
        rc = started ? exr_decoding_update(ctx, 0, &chunk, &dec)
                     : exr_decoding_initialize(ctx, 0, &chunk, &dec);
        if (rc != EXR_ERR_SUCCESS) break;
        for (int16_t k = 0; k < dec.channel_count; k++) {
            exr_coding_channel_info_t *ch = &dec.channels[k];
            int c = texel_channel(ch->channel_name);
            if (c < 0) c = 5;
            ch->user_bytes_per_element = 4;
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_pixel_stride = 4;
            ch->user_line_stride = (int32_t)(4u * out->width);
            ch->decode_to_ptr = (uint8_t *)(planes + (size_t)c * plane +
                                            (size_t)(chunk.start_y - data.min.y) * out->width);
        }
        if (!started) rc = exr_decoding_choose_default_routines(ctx, 0, &dec);
        started = true;
        if (rc == EXR_ERR_SUCCESS) rc = exr_decoding_run(ctx, 0, &dec);
    }
    if (started) exr_decoding_destroy(ctx, &dec);
    if (rc == EXR_ERR_SUCCESS) return true;
    snprintf(error, error_size, "corrupt or truncated OpenEXR pixels (OpenEXR: %s)",
             m->message[0] ? m->message : exr_get_default_error_message(rc));
    return false;
}

/* The image's size and colour channels checked, its texels allocated and decoded. */
static bool decode_part(exr_context_t ctx, exr_memory *m, size_t budget_bytes, texture_image *out,
                        char *error, size_t error_size) {
    int parts = 0;
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    exr_attr_box2i_t data;
    const exr_attr_chlist_t *list = NULL;
    exr_result_t rc = exr_get_count(ctx, &parts);
    if (rc == EXR_ERR_SUCCESS) rc = exr_get_storage(ctx, 0, &storage);
    if (rc == EXR_ERR_SUCCESS) rc = exr_get_data_window(ctx, 0, &data);
    if (rc == EXR_ERR_SUCCESS) rc = exr_get_channels(ctx, 0, &list);
    if (rc != EXR_ERR_SUCCESS) {
        snprintf(error, error_size, "unreadable OpenEXR header (OpenEXR: %s)",
                 m->message[0] ? m->message : exr_get_default_error_message(rc));
        return false;
    }
    if (parts != 1 || storage != EXR_STORAGE_SCANLINE) {
        snprintf(error, error_size, "OpenEXR of %d parts, storage %d: one scanline part is read",
                 parts, (int)storage);
        return false;
    }
    bool found[5] = {false};
    for (int c = 0; c < list->num_channels; c++) {
        int t = texel_channel(list->entries[c].name.str);
        if (list->entries[c].x_sampling != 1 || list->entries[c].y_sampling != 1) {
            snprintf(error, error_size, "OpenEXR with subsampled channels (not read)");
            return false;
        }
        if (t >= 0) found[t] = true;
    }
    bool rgb = found[0] && found[1] && found[2], grey = found[4];
    if (!rgb && !grey) {
        snprintf(error, error_size, "OpenEXR without colour channels (R, G and B, or Y)");
        return false;
    }
    long long w = (long long)data.max.x - data.min.x + 1,
              h = (long long)data.max.y - data.min.y + 1;
    if (w < 1 || h < 1 || w > TEXTURE_MAX_SIDE || h > TEXTURE_MAX_SIDE) {
        snprintf(error, error_size, "OpenEXR data window of %lld x %lld pixels: at most %d a side",
                 w, h, TEXTURE_MAX_SIDE);
        return false;
    }
    if (!texture_image_alloc(out, (uint32_t)w, (uint32_t)h, TZ_TEXEL_RGBA32F, budget_bytes, error,
                             error_size))
        return false;
    size_t texels = (size_t)w * (size_t)h;
    float *planes = calloc(6 * texels, sizeof *planes);
    if (!planes) {
        snprintf(error, error_size, "out of memory decoding the OpenEXR");
        return false;
    }
    for (size_t k = 0; k < texels; k++) planes[3 * texels + k] = 1.0f; /* alpha where none */
    bool ok = decode_pixels(ctx, data, out, planes, m, error, error_size);
    float *f = (float *)out->words;
    for (size_t k = 0; ok && k < texels; k++) /* a grey image's Y in R, G and B */
        for (size_t c = 0; c < 4; c++) f[4 * k + c] = planes[(c < 3 && !rgb ? 4 : c) * texels + k];
    free(planes);
    return ok;
}

bool texture_decode_exr(const uint8_t *bytes, size_t size, size_t budget_bytes, texture_image *out,
                        char *error, size_t error_size) {
    exr_memory m = {.bytes = bytes, .size = size};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.user_data = &m;
    init.read_fn = on_read;
    init.size_fn = on_size;
    init.error_handler_fn = on_error;
    init.max_image_width = TEXTURE_MAX_SIDE;
    init.max_image_height = TEXTURE_MAX_SIDE;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION;
    exr_context_t ctx = NULL;
    exr_result_t rc = exr_start_read(&ctx, "texture", &init);
    bool ok;
    if (rc != EXR_ERR_SUCCESS) {
        snprintf(error, error_size, "corrupt or truncated OpenEXR (OpenEXR: %s)",
                 m.message[0] ? m.message : exr_get_default_error_message(rc));
        ok = false;
    } else {
        ok = decode_part(ctx, &m, budget_bytes, out, error, error_size);
    }
    if (ctx) exr_finish(&ctx);
    return ok;
}
