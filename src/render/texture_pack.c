/* texture_pack.c: the scene's images, slots and the faces' UVs as the texture table the shaders
 * read (shared_layout.h, TZ_TEXTURE_*; shaders/common/texture.h), with the GGX tables where a
 * material needs them (shaders/common/microfacet.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render/ggx_albedo.h"
#include "render/scene_pack.h"
#include "util/log.h"

_Static_assert(TZ_GGX_TABLE_WORDS == TZ_GGX_TABLE_SIZE * TZ_GGX_TABLE_SIZE + TZ_GGX_TABLE_SIZE,
               "the GGX tables: E, then E_avg");
_Static_assert(TZ_TEXTURE_HEADER == TZ_TEXTURE_GGX + TZ_GGX_TABLE_WORDS, "the header follows them");
_Static_assert(TZ_TEXTURE_FIRST_SLOT == TZ_TEXTURE_HEADER + 4u, "the slots follow the header");

/* The float bits of x. */
static uint32_t bits_of(float x) {
    uint32_t u;
    memcpy(&u, &x, sizeof u);
    return u;
}

/* sRGB's decoding of 8-bit value k (IEC 61966-2-1), in double, rounded once. */
static float srgb_decoded(int k) {
    double c = k / 255.0;
    return (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
}

bool texture_pack(const scene *s, packed_scene *out) {
    bool microfacet = scene_has_microfacet(s);
    if (s->slot_count == 0 && !microfacet) {
        out->texture_words = calloc(1, sizeof *out->texture_words);
        out->texture_word_count = 0;
        return out->texture_words != NULL;
    }
    size_t slots = TZ_TEXTURE_FIRST_SLOT;
    size_t images = slots + (size_t)s->slot_count * TZ_SLOT_WORDS;
    size_t uvs = images + (size_t)s->image_count * TZ_IMAGE_WORDS;
    size_t texels = uvs + 6u * out->normals_count;
    size_t total = texels;
    for (int k = 0; k < s->image_count; k++) total += s->images[k].texels.word_count;
    if (total > UINT32_MAX) {
        log_error("the scene's textures need %zu words, past the 2^32 the shaders address", total);
        return false;
    }
    uint32_t *w = calloc(total, sizeof *w);
    if (!w) {
        log_error("out of memory packing %zu words of textures", total);
        return false;
    }
    for (int k = 0; k < 256; k++) {
        w[TZ_TEXTURE_SRGB + (uint32_t)k] = bits_of(srgb_decoded(k));
        w[TZ_TEXTURE_LINEAR + (uint32_t)k] = bits_of((float)(k / 255.0));
    }
    if (microfacet) {
        ggx_albedo_prepare();
        memcpy(w + TZ_TEXTURE_GGX, ggx_albedo_words, TZ_GGX_TABLE_WORDS * sizeof *w);
    }
    w[TZ_TEXTURE_HEADER] = (uint32_t)slots;
    w[TZ_TEXTURE_HEADER + 1] = (uint32_t)images;
    w[TZ_TEXTURE_HEADER + 2] = (uint32_t)uvs;
    for (int k = 0; k < s->slot_count; k++) {
        const texture_slot *sl = &s->slots[k];
        uint32_t *at = w + slots + (size_t)k * TZ_SLOT_WORDS;
        at[0] = sl->image;
        at[1] = sl->flags;
        at[2] = bits_of(sl->param);
        for (int c = 0; c < 6; c++) at[3 + c] = bits_of(sl->transform[c]);
    }
    size_t first = texels;
    for (int k = 0; k < s->image_count; k++) {
        const texture_image *t = &s->images[k].texels;
        uint32_t *at = w + images + (size_t)k * TZ_IMAGE_WORDS;
        at[0] = (uint32_t)first;
        at[1] = t->width;
        at[2] = t->height;
        at[3] = t->format;
        memcpy(w + first, t->words, t->word_count * sizeof *t->words);
        first += t->word_count;
    }
    /* The UVs at the faces' gpu_normals indices, which pack_triangles gives in scene order: the
     * scene's faces, then its models' (instances). */
    uint32_t n = 0;
    for (int k = 0; k < s->triangle_count + s->model_face_count; k++) {
        const triangle *t =
            k < s->triangle_count ? &s->triangles[k] : &s->model_faces[k - s->triangle_count];
        if (t->normals == TRIANGLE_FLAT) continue;
        const face_normals *fn = &s->normals[t->normals];
        for (int c = 0; c < 3; c++) {
            w[uvs + 6u * n + 2u * (uint32_t)c] = bits_of(fn->uv[c][0]);
            w[uvs + 6u * n + 2u * (uint32_t)c + 1u] = bits_of(fn->uv[c][1]);
        }
        n++;
    }
    out->texture_words = w;
    out->texture_word_count = total;
    return true;
}
