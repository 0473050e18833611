/* scene_material.c: a shape's material (DESIGN section 2; scenes/README.md): the material words
 * and the keys each takes, and the reading of a shape's line, its material and keys, into the
 * material it gets (defaults filled in) for spheres, triangles, quads and meshes alike. */
#include <stdio.h>
#include <string.h>

#include "scene/directives.h"
#include "scene/parser.h"

#define MATERIAL_COMMON_KEYS (BIT(MAT_COLOR) | BIT(MAT_EMISSION) | MATERIAL_TEXTURE_KEYS)
#define MIRROR_KEYS (MATERIAL_COMMON_KEYS | BIT(MAT_ROUGHNESS))
#define GLASS_KEYS (MATERIAL_COMMON_KEYS | BIT(MAT_IOR) | BIT(MAT_ROUGHNESS))
#define PBR_KEYS (MATERIAL_COMMON_KEYS | BIT(MAT_METALLIC) | BIT(MAT_ROUGHNESS) | BIT(MAT_IOR))
/* max(color) + ks may pass 1 by this before it warns: float rounding of values that sum to 1
 * (0.7 and 0.3, glTF's mapped 0.96 base and 0.04). */
#define BRIGHT_SLACK 1e-6f

/* The course report's Spanish names last: messages list them apart, as aliases (material_list). */
static const material_spec materials[] = {
    {"lambertian", TZ_MATERIAL_LAMBERTIAN, MATERIAL_COMMON_KEYS, 0.8f, false},
    {"phong", TZ_MATERIAL_PHONG, MATERIAL_COMMON_KEYS | BIT(MAT_KS) | BIT(MAT_ALPHA), 0.8f, false},
    {"mirror", TZ_MATERIAL_MIRROR, MIRROR_KEYS, 1.0f, false},
    {"refractive", TZ_MATERIAL_REFRACTIVE, GLASS_KEYS, 1.0f, false},
    {"pbr", TZ_MATERIAL_PBR, PBR_KEYS, 0.8f, false},
    {"lambertiana", TZ_MATERIAL_LAMBERTIAN, MATERIAL_COMMON_KEYS, 0.8f, true},
    {"espejo", TZ_MATERIAL_MIRROR, MIRROR_KEYS, 1.0f, true},
    {"refractada", TZ_MATERIAL_REFRACTIVE, GLASS_KEYS, 1.0f, true},
};

const material_spec *material_lookup(const token *word) {
    for (size_t i = 0; i < sizeof materials / sizeof materials[0]; i++) {
        if (parser_token_is(word, materials[i].word)) return &materials[i];
    }
    return NULL;
}

/* The materials a shape takes, for messages: "lambertian phong mirror refractive, or lambertiana
 * espejo refractada" (sep " ") or "lambertian, phong, mirror, refractive" (sep ", ", no aliases).
 */
void material_list(char *out, size_t size, const shape_spec *shape, const char *sep, bool aliases) {
    out[0] = '\0';
    for (int pass = 0; pass < (aliases ? 2 : 1); pass++) {
        bool first = true;
        for (size_t i = 0; i < sizeof materials / sizeof materials[0]; i++) {
            const material_spec *m = &materials[i];
            if (m->alias != (pass == 1) || (m->kind == TZ_MATERIAL_REFRACTIVE && !shape->glass))
                continue;
            directive_append(out, size, "%s%s", first ? (pass ? ", or " : "") : sep, m->word);
            first = false;
        }
    }
}

/* Reads a shape's line: its material word (token 1), then its keys and the material's into kv.
 * False (reported) on a missing or unknown material, glass on a shape that takes none, or a bad
 * or missing key. */
bool shape_read(parser *p, const shape_spec *shape, const material_spec **material,
                key_values *kv) {
    char list[128];
    if (p->token_count < 2) {
        material_list(list, sizeof list, shape, ", ", false);
        return parser_fail(p, parser_end_col(p),
                           "expected a material after '%s' (%s), got end of line", shape->word,
                           list);
    }
    const token *word = &p->tokens[1];
    const material_spec *m = material_lookup(word);
    if (!m) {
        material_list(list, sizeof list, shape, " ", true);
        return parser_fail(p, word->col, "unknown material '%s' for %s (expected one of: %s)",
                           parser_quote(p, word), shape->word, list);
    }
    if (m->kind == TZ_MATERIAL_REFRACTIVE && !shape->glass) {
        return parser_fail(p, word->col,
                           "a %s cannot be '%s': glass needs a closed mesh (load one with the "
                           "'mesh' directive)",
                           shape->word, m->word);
    }
    *material = m;
    unsigned accepted = shape->own_keys | m->keys << shape->material_first;
    return parser_keys_of(p, shape->word, m->word, shape->keys, shape->key_count, accepted, 2,
                          kv) &&
           parser_require_keys(p, shape->word, shape->keys, shape->key_count, shape->required, kv);
}

void phong_note_bright(parser *p, int col, vec3 color, float ks, const char *what) {
    float most = color.x > color.y ? color.x : color.y;
    most = most > color.z ? most : color.z;
    if (p->bright_line || !(most + ks > 1.0f + BRIGHT_SLACK)) return;
    p->bright_line = p->line;
    p->bright_col = col;
    snprintf(p->bright_what, sizeof p->bright_what,
             "%s: max(color) %g + ks %g = %g is above 1, so it reflects more light than it "
             "receives",
             what, (double)most, (double)ks, (double)(most + ks));
}

/* The material of a shape's line, defaults filled in; records the first emission, which report
 * mode refuses once the whole text is read (render mode may come later), and the first Phong
 * material brighter than the light it receives. */
material shape_material_of(parser *p, const shape_spec *shape, const material_spec *m,
                           const key_values *kv) {
    int k = shape->material_first;
    bool phong = m->kind == TZ_MATERIAL_PHONG, pbr = m->kind == TZ_MATERIAL_PBR;
    float roughness = (float)parser_value_or(kv, k + MAT_ROUGHNESS, pbr ? 0.5 : 0.0);
    float c = m->default_color;
    if ((kv->given & BIT(k + MAT_EMISSION)) && !p->emission_line) {
        p->emission_line = p->line;
        p->emission_col = p->tokens[kv->key_token[k + MAT_EMISSION]].col;
    }
    /* a mirror or glass of roughness 0 is the delta one, bit for bit */
    material_kind kind = m->kind;
    if (roughness > 0.0f && kind == TZ_MATERIAL_MIRROR) kind = TZ_MATERIAL_CONDUCTOR;
    if (roughness > 0.0f && kind == TZ_MATERIAL_REFRACTIVE) kind = TZ_MATERIAL_DIELECTRIC;
    material out = {
        .kind = kind,
        .color = parser_vec3(kv, k + MAT_COLOR, v3(c, c, c)),
        .ks = phong ? (float)parser_value_or(kv, k + MAT_KS, 0.5) : 0.0f,
        .alpha = phong ? (float)parser_value_or(kv, k + MAT_ALPHA, 32.0) : 0.0f,
        .ior = (float)parser_value_or(kv, k + MAT_IOR,
                                      m->kind == TZ_MATERIAL_REFRACTIVE || pbr ? 1.5 : 1.0),
        .roughness = roughness,
        .metallic = pbr ? (float)parser_value_or(kv, k + MAT_METALLIC, 0.0) : 0.0f,
        .emission = parser_vec3(kv, k + MAT_EMISSION, v3(0, 0, 0)),
    };
    if (phong) {
        int key = kv->given & BIT(k + MAT_KS) ? k + MAT_KS : k + MAT_COLOR;
        int col = kv->given & BIT(key) ? p->tokens[kv->key_token[key]].col : p->tokens[1].col;
        char what[64];
        snprintf(what, sizeof what, "%s phong", shape->word);
        phong_note_bright(p, col, out.color, out.ks, what);
    }
    return out;
}
