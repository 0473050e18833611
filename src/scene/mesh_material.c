/* mesh_material.c: a model file's materials as trazador's (the table of scenes/README.md,
 * `mesh`): OBJ/MTL's values and glTF's metallic-roughness factors mapped to lambertian, Phong,
 * mirror and glass, the values it refuses said, what it cannot show named. */
#include "scene/mesh_material.h"

#include <assimp/GltfMaterial.h>
#include <assimp/ObjMaterial.h>
#include <assimp/material.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

/* A mean specular colour at least this, over a black diffuse colour, is a mirror. */
#define MIRROR_KS 0.95f
static float clamp01(float x) { return x < 0.0f ? 0.0f : x > 1.0f ? 1.0f : x; }

/* A material's values as the mapping reads them; the first value it refuses (a colour that is
 * not finite or has a negative channel, a number that is not finite) named in `bad`. */
typedef struct material_reader {
    const assimp_lib *ai;
    const struct aiMaterial *m;
    char bad[160];
} material_reader;

static vec3 color_of(material_reader *r, const char *name, const char *key, unsigned type,
                     unsigned index, bool *found) {
    struct aiColor4D c;
    *found = r->ai->get_material_color(r->m, key, type, index, &c) == aiReturn_SUCCESS;
    if (!*found) return v3(0, 0, 0);
    bool finite = isfinite(c.r) && isfinite(c.g) && isfinite(c.b);
    if ((!finite || c.r < 0.0f || c.g < 0.0f || c.b < 0.0f) && !r->bad[0])
        snprintf(r->bad, sizeof r->bad, "its %s is %s: %g %g %g", name,
                 finite ? "negative" : "not finite", (double)c.r, (double)c.g, (double)c.b);
    return finite ? v3(c.r, c.g, c.b) : v3(0, 0, 0);
}

static float float_of(material_reader *r, const char *name, const char *key, unsigned type,
                      unsigned index, float fallback, bool *found) {
    ai_real value;
    unsigned one = 1;
    *found =
        r->ai->get_material_float_array(r->m, key, type, index, &value, &one) == aiReturn_SUCCESS &&
        one == 1;
    if (*found && !isfinite(value) && !r->bad[0])
        snprintf(r->bad, sizeof r->bad, "its %s is not finite: %g", name, (double)value);
    *found = *found && isfinite(value);
    return *found ? (float)value : fallback;
}

/* A factor that must lie in [0, 1] (glTF's metallic and roughness), named in r->bad if not. */
static void check_unit(material_reader *r, const char *name, float value, bool found) {
    if (found && !(value >= 0.0f && value <= 1.0f) && !r->bad[0])
        snprintf(r->bad, sizeof r->bad, "its %s is %g, outside [0, 1]", name, (double)value);
}

void mesh_note_unsupported(char *list, size_t size, const char *what) {
    if (strstr(list, what)) return;
    size_t used = strlen(list);
    snprintf(list + used, size - used, "%s%s", used ? ", " : "", what);
}

/* Whether material m comes from glTF's importer (which sets glTF's alpha mode on every one). */
static bool from_gltf(const assimp_lib *ai, const struct aiMaterial *m) {
    struct aiString mode = {0};
    return ai->get_material_string(m, AI_MATKEY_GLTF_ALPHAMODE, &mode) == aiReturn_SUCCESS;
}

/* The affine map of UVs into rows (u' = r0 u + r1 v + r2, v' = r3 u + r4 v + r5) of the first
 * texture of `type` of glTF material m: KHR_texture_transform (offset o, rotation r, scale S:
 * uv' = o + R S uv in glTF's UVs, v down, R = (cos r, sin r; -sin r, cos r) by rows, with which
 * the extension's TextureTransformTest model renders right), recovered from the aiUVTransform
 * assimp 5.2's glTF
 * importer makes of it by inverting its formulas, and written for trazador's UVs (v = 1 - v_glTF,
 * as assimp flips them). The identity without one, for other formats (whose aiUVTransform
 * follows assimp's own rule) or with a non-finite value. */
static void uv_transform_of(const assimp_lib *ai, const struct aiMaterial *m,
                            enum aiTextureType type, float rows[6]) {
    static const float identity[6] = {1.0f, 0.0f, 0.0f, 0.0f, 1.0f, 0.0f};
    memcpy(rows, identity, sizeof identity);
    float t[5]; /* aiUVTransform: translation x y, scaling x y, rotation r */
    unsigned int count = 5;
    if (!from_gltf(ai, m) ||
        ai->get_material_float_array(m, _AI_MATKEY_UVTRANSFORM_BASE, type, 0, t, &count) !=
            aiReturn_SUCCESS ||
        count != 5)
        return;
    double sx = t[2], sy = t[3], c = cos(-(double)t[4]), s = sin(-(double)t[4]);
    double ox = t[0] - 0.5 * sx * (1.0 - c + s);
    double oy = -(double)t[1] + 0.5 * sy * (s + c - 1.0) + 1.0 - sy;
    double g = -s; /* sin r: the importer keeps r, and builds the translation from -r */
    double out[6] = {c * sx, g * sy, ox - g * sy, -g * sx, c * sy, 1.0 - c * sy - oy};
    for (int k = 0; k < 6; k++)
        if (!isfinite((float)out[k])) return;
    for (int k = 0; k < 6; k++) rows[k] = (float)out[k];
}

/* The texture of `type` (its first) of material m into map, its wrap modes and srgb in flags;
 * false (map empty) when it has none. */
static bool map_of(const assimp_lib *ai, const struct aiMaterial *m, enum aiTextureType type,
                   bool srgb, mesh_map *map) {
    struct aiString path = {0};
    if (ai->get_material_texture_count(m, type) == 0 ||
        ai->get_material_string(m, _AI_MATKEY_TEXTURE_BASE, type, 0, &path) != aiReturn_SUCCESS ||
        path.length == 0 || path.length >= sizeof map->path)
        return false;
    memcpy(map->path, path.data, path.length);
    map->path[path.length] = '\0';
    for (char *c = map->path; *c; c++) /* MTL files written on Windows: .\\wood.jpg */
        if (*c == '\\') *c = '/';
    int mode[2] = {aiTextureMapMode_Wrap, aiTextureMapMode_Wrap};
    ai->get_material_integer_array(m, _AI_MATKEY_MAPPINGMODE_U_BASE, type, 0, &mode[0], NULL);
    ai->get_material_integer_array(m, _AI_MATKEY_MAPPINGMODE_V_BASE, type, 0, &mode[1], NULL);
    uint32_t wrap[2];
    for (int k = 0; k < 2; k++)
        wrap[k] = mode[k] == aiTextureMapMode_Mirror ? TZ_WRAP_MIRROR
                  : mode[k] == aiTextureMapMode_Clamp || mode[k] == aiTextureMapMode_Decal
                      ? TZ_WRAP_CLAMP
                      : TZ_WRAP_REPEAT;
    map->flags = wrap[0] | wrap[1] << 4 | (srgb ? TZ_SLOT_SRGB : 0u);
    map->param = 1.0f;
    uv_transform_of(ai, m, type, map->transform);
    return true;
}

/* glTF's alpha mode of material m as its base colour map's alpha (MAP_ALPHA): MASK cuts where the
 * texture's alpha times the factor's is below alphaCutoff (0.5 by default), BLEND keeps that
 * product's share of rays (TZ_SLOT_STOCHASTIC); the factor folded into the slot's parameter
 * (cutoff / factor, 1 / factor). Nothing for OPAQUE, other formats or without a texture. */
static void gltf_alpha_map(const assimp_lib *ai, const struct aiMaterial *m, mesh_material *out) {
    struct aiString mode = {0};
    if (ai->get_material_string(m, AI_MATKEY_GLTF_ALPHAMODE, &mode) != aiReturn_SUCCESS ||
        !out->maps[MAP_COLOR].path[0])
        return;
    bool mask = !strcmp(mode.data, "MASK"), blend = !strcmp(mode.data, "BLEND");
    if (!mask && !blend) return;
    struct aiColor4D base = {1.0f, 1.0f, 1.0f, 1.0f};
    ai->get_material_color(m, AI_MATKEY_BASE_COLOR, &base);
    float cutoff = 0.5f;
    ai->get_material_float_array(m, AI_MATKEY_GLTF_ALPHACUTOFF, &cutoff, NULL);
    float factor = base.a > 0.0f && base.a <= 1.0f ? base.a : base.a > 1.0f ? 1.0f : 0.0f;
    float param = factor > 0.0f ? (mask ? cutoff : 1.0f) / factor : 2.0f; /* 0: every ray cut */
    mesh_map *alpha = &out->maps[MAP_ALPHA];
    *alpha = out->maps[MAP_COLOR];
    alpha->flags = (alpha->flags & ~TZ_SLOT_SRGB) | (blend ? TZ_SLOT_STOCHASTIC : 0u);
    alpha->param = isfinite(param) ? param : 2.0f;
}

/* The textures of material m trazador keeps (MAP_*): the colour (glTF's base colour, else the
 * diffuse map: MTL's map_Kd), emission (glTF's emissive texture, MTL's map_Ke), normal (glTF's
 * normal texture, MTL's norm; map_Bump is a height map, not one), alpha (MTL's map_d, its first
 * channel where it has no alpha; glTF's base colour alpha by its alpha mode), glTF's
 * metallic-roughness, else MTL's map_Pr and map_Pm. */
static void read_maps(const assimp_lib *ai, const struct aiMaterial *m, mesh_material *out) {
    if (!map_of(ai, m, aiTextureType_BASE_COLOR, true, &out->maps[MAP_COLOR]))
        map_of(ai, m, aiTextureType_DIFFUSE, true, &out->maps[MAP_COLOR]);
    map_of(ai, m, aiTextureType_EMISSIVE, true, &out->maps[MAP_EMISSION]);
    map_of(ai, m, aiTextureType_NORMALS, false, &out->maps[MAP_NORMAL]);
    if (map_of(ai, m, aiTextureType_OPACITY, false, &out->maps[MAP_ALPHA])) {
        out->maps[MAP_ALPHA].flags |= TZ_SLOT_ALPHA_RED;
        out->maps[MAP_ALPHA].param = 0.5f;
    }
    gltf_alpha_map(ai, m, out);
    /* assimp 5.2's glTF importer gives the metallic-roughness texture as UNKNOWN's first, and the
     * same image as the metallic and roughness textures, whose red channel is not theirs. */
    if (!map_of(ai, m, aiTextureType_UNKNOWN, false, &out->maps[MAP_METALLIC_ROUGHNESS])) {
        map_of(ai, m, aiTextureType_DIFFUSE_ROUGHNESS, false, &out->maps[MAP_ROUGHNESS]);
        map_of(ai, m, aiTextureType_METALNESS, false, &out->maps[MAP_METALLIC]);
    }
}

/* The texture kinds a material uses, named into list (those the renderer shades left out; the
 * metallic and roughness ones shade the microfacet kinds alone, as their factors do). */
static void note_textures(const assimp_lib *ai, const struct aiMaterial *m, char *list,
                          size_t size) {
    static const struct {
        enum aiTextureType type;
        const char *name;
    } kinds[] = {
        {aiTextureType_DIFFUSE, "diffuse texture"},
        {aiTextureType_SPECULAR, "specular texture"},
        {aiTextureType_AMBIENT, "ambient texture"},
        {aiTextureType_EMISSIVE, "emissive texture"},
        {aiTextureType_HEIGHT, "bump texture"},
        {aiTextureType_NORMALS, "normal map"},
        {aiTextureType_SHININESS, "shininess texture"},
        {aiTextureType_OPACITY, "opacity texture"},
        {aiTextureType_DISPLACEMENT, "displacement texture"},
        {aiTextureType_LIGHTMAP, "light map"},
        {aiTextureType_REFLECTION, "reflection texture"},
        {aiTextureType_BASE_COLOR, "base colour texture"},
        {aiTextureType_METALNESS, "metallic texture"},
        {aiTextureType_DIFFUSE_ROUGHNESS, "roughness texture"},
        {aiTextureType_UNKNOWN, "other texture"},
    };
    for (size_t k = 0; k < sizeof kinds / sizeof kinds[0]; k++) {
        enum aiTextureType type = kinds[k].type;
        if (type == aiTextureType_DIFFUSE || type == aiTextureType_BASE_COLOR ||
            type == aiTextureType_NORMALS || type == aiTextureType_UNKNOWN ||
            type == aiTextureType_METALNESS || type == aiTextureType_DIFFUSE_ROUGHNESS ||
            type == aiTextureType_EMISSIVE || type == aiTextureType_OPACITY)
            continue; /* the maps shaded (read_maps') */
        if (ai->get_material_texture_count(m, kinds[k].type) > 0)
            mesh_note_unsupported(list, size, kinds[k].name);
    }
}

/* Whether c is grey of level v, exactly. */
static bool grey(vec3 c, float v) { return c.x == v && c.y == v && c.z == v; }

/* The material every face of a file without materials gets: the README's lambertian 0.8 grey. */
static mesh_material no_material(void) {
    return (mesh_material){
        .kind = TZ_MATERIAL_LAMBERTIAN, .color = v3(0.8f, 0.8f, 0.8f), .ior = 1.0f};
}

/* The file's material as trazador's (scenes/README.md, `mesh`, has the table); a value it
 * refuses is said in r->bad. */
static mesh_material map_material(material_reader *r, const char *name, char *unsupported,
                                  size_t size) {
    const struct aiMaterial *m = r->m;
    bool has_kd, has_ks, has_ns, has_ni, has_d, has_base, has_metal, has_rough, has_trans, found;
    vec3 kd = color_of(r, "diffuse colour (Kd)", AI_MATKEY_COLOR_DIFFUSE, &has_kd);
    vec3 base = color_of(r, "base colour", AI_MATKEY_BASE_COLOR, &has_base);
    vec3 ks = color_of(r, "specular colour (Ks)", AI_MATKEY_COLOR_SPECULAR, &has_ks);
    vec3 ke = color_of(r, "emission (Ke)", AI_MATKEY_COLOR_EMISSIVE, &found);
    float ns = float_of(r, "shininess (Ns)", AI_MATKEY_SHININESS, 0.0f, &has_ns);
    float ni = float_of(r, "index of refraction (Ni)", AI_MATKEY_REFRACTI, 1.5f, &has_ni);
    float d = float_of(r, "opacity (d)", AI_MATKEY_OPACITY, 1.0f, &has_d);
    float metallic = float_of(r, "metallic factor", AI_MATKEY_METALLIC_FACTOR, 0.0f, &has_metal);
    float roughness = float_of(r, "roughness factor", AI_MATKEY_ROUGHNESS_FACTOR, 1.0f, &has_rough);
    float transmission =
        float_of(r, "transmission factor", AI_MATKEY_TRANSMISSION_FACTOR, 0.0f, &has_trans);
    int illum = 2;
    r->ai->get_material_integer_array(m, AI_MATKEY_OBJ_ILLUM, &illum, NULL);
    /* A material assimp made up for faces the file gives none: named AI_DEFAULT_MATERIAL_NAME
     * (STL: diffuse and specular 1; OBJ without MTL: diffuse 0.6), or unnamed with a loader's
     * own values (PLY: diffuse and specular 1; OFF: diffuse 0.6; glTF's default: base colour,
     * metallic and roughness 1). Mapped, the first made Phong ks 1 over white: more light out
     * than in, fireflies in path mode. */
    bool unnamed = !name[0];
    if (!strcmp(name, AI_DEFAULT_MATERIAL_NAME) ||
        (unnamed && !has_base && !has_metal && has_kd && grey(kd, 1.0f) && has_ks &&
         grey(ks, 1.0f)) ||
        (unnamed && !has_base && !has_metal && has_kd && grey(kd, 0.6f) && !has_ks) ||
        (unnamed && has_base && grey(base, 1.0f) && metallic == 1.0f && roughness == 1.0f &&
         grey(ke, 0.0f)))
        return no_material();
    note_textures(r->ai, m, unsupported, size);
    vec3 color = has_base ? base : has_kd ? kd : v3(0.8f, 0.8f, 0.8f);
    color = v3(clamp01(color.x), clamp01(color.y), clamp01(color.z));
    mesh_material out = {
        .kind = TZ_MATERIAL_LAMBERTIAN,
        .color = color,
        .ior = 1.0f,
        .emission = v3(fmaxf(ke.x, 0.0f), fmaxf(ke.y, 0.0f), fmaxf(ke.z, 0.0f)),
    };
    float ks_mean = clamp01((ks.x + ks.y + ks.z) / 3.0f);
    bool glass = (has_d && d < 1.0f) || illum == 4 || illum == 6 || illum == 7 ||
                 (has_trans && transmission > 0.0f);
    if (glass) {
        /* glTF's transmission is glass as rough as its roughness factor (1 by default) */
        bool rough = has_trans && has_rough && transmission > 0.0f;
        check_unit(r, "roughness factor", roughness, rough);
        out.roughness = rough ? clamp01(roughness) : 0.0f;
        out.kind = out.roughness > 0.0f ? TZ_MATERIAL_DIELECTRIC : TZ_MATERIAL_REFRACTIVE;
        out.ior = has_ni && ni >= 1.0f ? ni : 1.5f;
        if (!has_base && !has_kd) out.color = v3(1, 1, 1);
        return out;
    }
    if (has_metal || has_rough) {
        /* glTF's metallic-roughness model (and MTL's Pm, Pr) is the pbr material, exactly. */
        check_unit(r, "metallic factor", metallic, has_metal);
        check_unit(r, "roughness factor", roughness, has_rough);
        out.kind = TZ_MATERIAL_PBR;
        out.metallic = clamp01(metallic);
        out.roughness = clamp01(roughness);
        out.ior = has_ni && ni >= 1.0f ? ni : 1.5f;
        return out;
    }
    bool black = kd.x <= 0.0f && kd.y <= 0.0f && kd.z <= 0.0f;
    if (illum == 3 || (has_ks && black && ks_mean >= MIRROR_KS)) {
        out.kind = TZ_MATERIAL_MIRROR;
        out.color =
            has_ks && ks_mean > 0.0f ? v3(clamp01(ks.x), clamp01(ks.y), clamp01(ks.z)) : out.color;
        return out;
    }
    if (has_ks && ks_mean > 0.0f) {
        out.kind = TZ_MATERIAL_PHONG;
        out.ks = ks_mean;
        out.alpha = has_ns && ns > 0.0f ? ns : 1.0f;
    }
    return out;
}

bool mesh_map_material(const assimp_lib *ai, const struct aiMaterial *m, unsigned index,
                       mesh_material *out, char *unsupported, size_t size, char *error,
                       size_t error_size) {
    material_reader r = {.ai = ai, .m = m};
    struct aiString name = {0};
    ai->get_material_string(m, AI_MATKEY_NAME, &name);
    name.data[name.length < sizeof name.data ? name.length : sizeof name.data - 1] = '\0';
    *out = map_material(&r, name.data, unsupported, size);
    read_maps(ai, m, out);
    snprintf(out->name, sizeof out->name, "%.*s", (int)sizeof out->name - 1, name.data);
    if (!r.bad[0]) return true;
    if (name.data[0])
        snprintf(error, error_size, "material '%s': %s", name.data, r.bad);
    else
        snprintf(error, error_size, "material %u: %s", index, r.bad);
    return false;
}
