/* scene_texture.c: the texture keys of a material (scenes/README.md, "Textures"): each image file
 * decoded once a scene (scene.images, keyed by device and inode, or by name for a model's
 * embedded image), the slots that read them (scene.slots, one for each way of reading an image)
 * and the material's maps, indices of its slots. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "scene/directives.h"
#include "scene/parser.h"

/* The identity transform of UVs. */
static const float identity_uv[6] = {1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};

/* Appends image (its texels taken) to the scene under name and identity; its index in *index.
 * False (reported at col) out of memory, the image freed. */
static bool image_add(parser *p, int col, texture_image *image, const char *name, uint64_t device,
                      uint64_t inode, uint32_t *index) {
    scene_image *grown = realloc(p->s.images, (size_t)(p->s.image_count + 1) * sizeof *grown);
    if (!grown) {
        texture_image_free(image);
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, col, "out of memory");
    }
    p->s.images = grown;
    scene_image *added = &p->s.images[p->s.image_count];
    *added = (scene_image){.texels = *image, .device = device, .inode = inode};
    snprintf(added->name, sizeof added->name, "%s", name);
    p->s.texel_bytes += image->word_count * sizeof *image->words;
    *index = (uint32_t)p->s.image_count++;
    return true;
}

/* Whether every texel of t has alpha 1: an image without an alpha channel (the decoders give
 * such images alpha 1), whose alpha map reads its first channel (TZ_SLOT_ALPHA_RED). */
static bool image_opaque(const texture_image *t) {
    for (size_t k = 0; k < t->word_count; k++) {
        bool alpha = t->format == TZ_TEXEL_RGBA8 || k % 4 == 3;
        if (!alpha) continue;
        bool one = t->format == TZ_TEXEL_RGBA8 ? t->words[k] >> 24 == 255u
                                               : t->words[k] == 0x3f800000u; /* 1.0f */
        if (!one) return false;
    }
    return true;
}

/* The slot reading image with flags, param and transform: an existing one when the same, else a
 * new one; *slot its index + 1. False (reported at col) out of memory. */
static bool slot_add(parser *p, int col, uint32_t image, uint32_t flags, float param,
                     const float transform[6], uint32_t *slot) {
    if ((flags & TZ_SLOT_ALPHA_RED) && !image_opaque(&p->s.images[image].texels))
        flags &= ~TZ_SLOT_ALPHA_RED;
    texture_slot s = {.image = image, .flags = flags, .param = param};
    memcpy(s.transform, transform, sizeof s.transform);
    for (int k = 0; k < p->s.slot_count; k++) {
        if (!memcmp(&p->s.slots[k], &s, sizeof s)) {
            *slot = (uint32_t)k + 1u;
            return true;
        }
    }
    if ((uint32_t)p->s.slot_count >= TZ_MAX_SLOTS)
        return parser_fail(p, col, "more than %u texture slots (images with their wrap modes)",
                           TZ_MAX_SLOTS);
    texture_slot *grown = realloc(p->s.slots, (size_t)(p->s.slot_count + 1) * sizeof *grown);
    if (!grown) {
        if (p->err) p->err->out_of_memory = true;
        return parser_fail(p, col, "out of memory");
    }
    p->s.slots = grown;
    p->s.slots[p->s.slot_count++] = s;
    *slot = (uint32_t)p->s.slot_count;
    return true;
}

/* An image that cannot be read: an error, or for a model's own textures (textures_optional) a
 * warning naming it, its map dropped (*slot 0: the material renders without it). */
static bool texture_refused(parser *p, int col, const char *name, const char *why, uint32_t *slot) {
    if (!p->textures_optional) return parser_fail(p, col, "texture '%s': %s", name, why);
    parser_warn(p, p->line, col, "texture '%s' not shown: %s", name, why);
    *slot = 0;
    return true;
}

/* What is left of the scene's texel budget. */
static size_t budget_left(const parser *p) { return TEXTURE_MAX_SCENE_BYTES - p->s.texel_bytes; }

bool texture_slot_of_file(parser *p, int col, const char *path, uint32_t flags, float param,
                          const float transform[6], uint32_t *slot) {
    struct stat st;
    bool known = stat(path, &st) == 0;
    int found = -1;
    for (int k = 0; known && k < p->s.image_count && found < 0; k++)
        if (p->s.images[k].device == (uint64_t)st.st_dev &&
            p->s.images[k].inode == (uint64_t)st.st_ino)
            found = k;
    uint32_t image = (uint32_t)found;
    if (found < 0) {
        texture_image decoded;
        char why[320];
        if (!texture_load_file(path, budget_left(p), &decoded, why, sizeof why))
            return texture_refused(p, col, path, why, slot);
        if (!image_add(p, col, &decoded, path, (uint64_t)st.st_dev, (uint64_t)st.st_ino, &image))
            return false;
    }
    return slot_add(p, col, image, flags, param, transform, slot);
}

bool texture_slot_of_bytes(parser *p, int col, const char *name, const uint8_t *bytes, size_t size,
                           uint32_t flags, float param, const float transform[6], uint32_t *slot) {
    int found = -1;
    for (int k = 0; k < p->s.image_count && found < 0; k++)
        if (p->s.images[k].device == 0 && p->s.images[k].inode == 0 &&
            !strncmp(p->s.images[k].name, name, sizeof p->s.images[k].name))
            found = k;
    uint32_t image = (uint32_t)found;
    if (found < 0) {
        texture_image decoded;
        char why[320];
        if (!texture_decode(bytes, size, budget_left(p), &decoded, why, sizeof why))
            return texture_refused(p, col, name, why, slot);
        if (!image_add(p, col, &decoded, name, 0, 0, &image)) return false;
    }
    return slot_add(p, col, image, flags, param, transform, slot);
}

bool material_maps_read(parser *p, int first, const key_values *kv, material *m) {
    static const struct {
        int key, map;
        bool srgb;
    } maps[] = {
        {MAT_COLOR_MAP, MAP_COLOR, true},
        {MAT_EMISSION_MAP, MAP_EMISSION, true},
        {MAT_NORMAL_MAP, MAP_NORMAL, false},
        {MAT_ALPHA_MAP, MAP_ALPHA, false},
        {MAT_METALLIC_ROUGHNESS_MAP, MAP_METALLIC_ROUGHNESS, false},
    };
    if (!(kv->given & (MATERIAL_TEXTURE_KEYS << first))) return true;
    if (p->primitives_only) return false; /* files are read in order (see the header) */
    uint32_t wrap = kv->given & BIT(first + MAT_WRAP) ? (uint32_t)kv->value[first + MAT_WRAP][0]
                                                      : TZ_WRAP_REPEAT;
    for (size_t k = 0; k < sizeof maps / sizeof maps[0]; k++) {
        int key = first + maps[k].key;
        if (!(kv->given & BIT(key))) continue;
        const token *t = &p->tokens[kv->value_token[key][0]];
        if (maps[k].map == MAP_EMISSION && !material_emits(m))
            parser_warn(p, p->line, t->col,
                        "emission_map without emission: it scales `emission`, "
                        "so nothing is emitted");
        char path[PATH_MAX];
        if (!directive_file_path(p, t, "texture", path, sizeof path)) return false;
        float param =
            maps[k].map == MAP_NORMAL  ? (float)parser_value_or(kv, first + MAT_NORMAL_SCALE, 1.0)
            : maps[k].map == MAP_ALPHA ? (float)parser_value_or(kv, first + MAT_ALPHA_CUTOFF, 0.5)
                                       : 0.0f;
        uint32_t flags = wrap | wrap << 4 | (maps[k].srgb ? TZ_SLOT_SRGB : 0u) |
                         (maps[k].map == MAP_ALPHA ? TZ_SLOT_ALPHA_RED : 0u);
        if (!texture_slot_of_file(p, t->col, path, flags, param, identity_uv,
                                  &m->maps[maps[k].map]))
            return false;
    }
    return true;
}
