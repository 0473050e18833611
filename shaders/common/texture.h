/* texture.h: image textures, one text for C and GLSL (dialect.h) over the includer's accessors
 * texture_word(i) (word i of the texture table, shared_layout.h's TZ_TEXTURE_*) and
 * material_maps(m) (gpu_material.maps): a slot's texel at a UV, filtered bilinearly here, not by
 * a sampler (drivers' samplers differ in their weights' bits), and what a hit's material takes
 * from its maps. UVs follow OpenGL's rule: v = 0 is the image's bottom row, v = 1 its top. */
#ifndef TRAZADOR_COMMON_TEXTURE_H
#define TRAZADOR_COMMON_TEXTURE_H

#include "bsdf.h"
#include "dialect.h"
#include "rng.h"
#include "transcendental.h"

/* A texture coordinate pair. */
TZ_STRUCT(tex_uv) {
    float u;
    float v;
}
TZ_STRUCT_END(tex_uv)

/* A filtered texel: linear RGB and alpha. */
TZ_STRUCT(texel) {
    vec3 rgb;
    float a;
}
TZ_STRUCT_END(texel)

TZ_LANE_FN tex_uv tex_uv_of(float u, float v) {
    tex_uv t;
    t.u = u;
    t.v = v;
    return t;
}

/* Word i of the texture table as a float. */
TZ_FN float texture_float(TZ_SCENE_PARAM TZ_UINT i) {
    return float_from_bits(texture_word(TZ_SCENE_ARG i));
}

/* Coordinate t of a texture of `size` texels on one axis, reduced by wrap mode: [0, 1) for
 * repeat, [0, 2) for mirrored repeat (a period of the image and its mirror), [0, 1] for clamp;
 * NaN and magnitudes past 2^30 count as 0 (integer texel indices must not overflow). */
TZ_LANE_FN float wrap_reduce(float t, TZ_UINT mode) {
    t = TZ_ABS(t) < 1073741824.0f ? t : 0.0f;
    TZ_PRECISE float repeat = t - TZ_FLOOR(t);
    TZ_PRECISE float mirror = t - 2.0f * TZ_FLOOR(t * 0.5f);
    float clamped = TZ_MIN(TZ_MAX(t, 0.0f), 1.0f);
    return mode == TZ_WRAP_CLAMP ? clamped : (mode == TZ_WRAP_MIRROR ? mirror : repeat);
}

/* Texel index i (from -1 to 2 size, as bilinear filtering of a reduced coordinate gives) of an
 * axis of `size` texels by wrap mode: every operand of % non-negative, as GLSL requires. */
TZ_LANE_FN int wrap_texel(int i, int size, TZ_UINT mode) {
    int period = 2 * size;
    int m = (i + period) % period;
    int mirrored = m < size ? m : period - 1 - m;
    int clamped = TZ_MIN(TZ_MAX(i, 0), size - 1);
    int repeated = (i + size) % size;
    return mode == TZ_WRAP_CLAMP ? clamped : (mode == TZ_WRAP_MIRROR ? mirrored : repeated);
}

/* Texel (x, y) of the image whose texels start at word `first` (width, format TZ_TEXEL_*); an
 * 8-bit texel's RGB through the sRGB table where srgb, else the linear one. */
TZ_FN texel texel_at(TZ_SCENE_PARAM TZ_UINT first, TZ_UINT width, TZ_UINT format, int x, int y,
                     TZ_BOOL srgb) {
    TZ_UINT k = TZ_UINT_OF(y) * width + TZ_UINT_OF(x);
    texel t;
    if (format == TZ_TEXEL_RGBA8) {
        TZ_UINT w = texture_word(TZ_SCENE_ARG first + k);
        TZ_UINT table = srgb ? TZ_TEXTURE_SRGB : TZ_TEXTURE_LINEAR;
        t.rgb = v3(texture_float(TZ_SCENE_ARG table + (w & 255u)),
                   texture_float(TZ_SCENE_ARG table + ((w >> 8) & 255u)),
                   texture_float(TZ_SCENE_ARG table + ((w >> 16) & 255u)));
        t.a = texture_float(TZ_SCENE_ARG TZ_TEXTURE_LINEAR + (w >> 24));
    } else {
        TZ_UINT at = first + 4u * k;
        t.rgb = v3(texture_float(TZ_SCENE_ARG at), texture_float(TZ_SCENE_ARG at + 1u),
                   texture_float(TZ_SCENE_ARG at + 2u));
        t.a = texture_float(TZ_SCENE_ARG at + 3u);
    }
    return t;
}

/* The weights of bilinear filtering of an axis at reduced coordinate t over `size` texels: the
 * first texel's index and the second's weight (the first's is 1 minus it). */
TZ_STRUCT(bilinear_axis) {
    int i0;
    float f;
}
TZ_STRUCT_END(bilinear_axis)

TZ_LANE_FN bilinear_axis bilinear_axis_of(float t, int size) {
    TZ_PRECISE float x = t * TZ_FLOAT(size) - 0.5f;
    float x0 = TZ_FLOOR(x);
    bilinear_axis b;
    b.i0 = TZ_INT(x0);
    TZ_PRECISE float f = x - x0;
    b.f = f;
    return b;
}

/* The texel of texture slot `slot` (TZ_SLOT_WORDS words from TZ_TEXTURE_FIRST_SLOT) at uv: the
 * slot's transform, its wrap modes, then bilinear filtering of the four nearest texels. */
TZ_FN texel texture_sample(TZ_SCENE_PARAM TZ_UINT slot, tex_uv uv) {
    TZ_UINT s = TZ_TEXTURE_FIRST_SLOT + slot * TZ_SLOT_WORDS;
    TZ_UINT image = texture_word(TZ_SCENE_ARG s), flags = texture_word(TZ_SCENE_ARG s + 1u);
    TZ_PRECISE float u = texture_float(TZ_SCENE_ARG s + 3u) * uv.u +
                         texture_float(TZ_SCENE_ARG s + 4u) * uv.v +
                         texture_float(TZ_SCENE_ARG s + 5u);
    TZ_PRECISE float v = texture_float(TZ_SCENE_ARG s + 6u) * uv.u +
                         texture_float(TZ_SCENE_ARG s + 7u) * uv.v +
                         texture_float(TZ_SCENE_ARG s + 8u);
    TZ_UINT at = texture_word(TZ_SCENE_ARG TZ_TEXTURE_HEADER + 1u) + image * TZ_IMAGE_WORDS;
    TZ_UINT first = texture_word(TZ_SCENE_ARG at);
    TZ_UINT width = texture_word(TZ_SCENE_ARG at + 1u);
    TZ_UINT height = texture_word(TZ_SCENE_ARG at + 2u);
    TZ_UINT format = texture_word(TZ_SCENE_ARG at + 3u);
    TZ_UINT wrap_u = flags & 15u, wrap_v = (flags >> 4) & 15u;
    TZ_BOOL srgb = (flags & TZ_SLOT_SRGB) != 0u;
    int w = TZ_INT(width), h = TZ_INT(height);
    /* Rows are stored top first and v runs up the image. */
    TZ_PRECISE float down = 1.0f - v;
    bilinear_axis bx = bilinear_axis_of(wrap_reduce(u, wrap_u), w);
    bilinear_axis by = bilinear_axis_of(wrap_reduce(down, wrap_v), h);
    int x0 = wrap_texel(bx.i0, w, wrap_u), x1 = wrap_texel(bx.i0 + 1, w, wrap_u);
    int y0 = wrap_texel(by.i0, h, wrap_v), y1 = wrap_texel(by.i0 + 1, h, wrap_v);
    texel c00 = texel_at(TZ_SCENE_ARG first, width, format, x0, y0, srgb);
    texel c10 = texel_at(TZ_SCENE_ARG first, width, format, x1, y0, srgb);
    texel c01 = texel_at(TZ_SCENE_ARG first, width, format, x0, y1, srgb);
    texel c11 = texel_at(TZ_SCENE_ARG first, width, format, x1, y1, srgb);
    TZ_PRECISE float gx = 1.0f - bx.f, gy = 1.0f - by.f;
    TZ_PRECISE float w00 = gx * gy, w10 = bx.f * gy, w01 = gx * by.f, w11 = bx.f * by.f;
    texel t;
    TZ_PRECISE vec3 rgb = v3_add(v3_add(v3_scale(c00.rgb, w00), v3_scale(c10.rgb, w10)),
                                 v3_add(v3_scale(c01.rgb, w01), v3_scale(c11.rgb, w11)));
    TZ_PRECISE float a = (c00.a * w00 + c10.a * w10) + (c01.a * w01 + c11.a * w11);
    t.rgb = rgb;
    t.a = a;
    return t;
}

/* The UV of a sphere's point of outward unit normal n (equirectangular, +y up): u from the
 * azimuth about +y (0.5 toward +x, rising toward +z), v from the polar angle (1 at the +y pole,
 * 0 at the -y one). */
TZ_FN tex_uv sphere_uv(vec3 n) {
    float azimuth = angle_of(TZ_ABS(n.z), n.x);
    azimuth = n.z < 0.0f ? -azimuth : azimuth;
    TZ_PRECISE float ring = TZ_SQRT(TZ_MAX(0.0f, 1.0f - n.y * n.y));
    float polar = angle_of(ring, n.y);
    TZ_PRECISE float u = 0.5f + azimuth * (0.5f / TZ_PI);
    TZ_PRECISE float v = 1.0f - polar * (1.0f / TZ_PI);
    return tex_uv_of(u, v);
}

/* Whether the scene has textures, from the flags (compiled out of the others where the flags are
 * a specialization constant). */
#define TZ_HAS_TEXTURES ((TZ_FLAGS & TZ_FLAG_TEXTURES) != 0u)
/* The same of packed scene p, for the C packet builds' own loops. */
#define TZ_HAS_TEXTURES_OF(p) (((p)->frame.flags & TZ_FLAG_TEXTURES) != 0u)

/* The UV at barycentric weights b0, b1, b2 of the face whose corner data are gpu_normals index
 * `corners` (its UVs at that index of the table's UVs). */
TZ_FN tex_uv corner_uv(TZ_SCENE_PARAM TZ_UINT corners, float b0, float b1, float b2) {
    TZ_UINT at = texture_word(TZ_SCENE_ARG TZ_TEXTURE_HEADER + 2u) + 6u * corners;
    TZ_PRECISE float u = texture_float(TZ_SCENE_ARG at) * b0 +
                         texture_float(TZ_SCENE_ARG at + 2u) * b1 +
                         texture_float(TZ_SCENE_ARG at + 4u) * b2;
    TZ_PRECISE float v = texture_float(TZ_SCENE_ARG at + 1u) * b0 +
                         texture_float(TZ_SCENE_ARG at + 3u) * b1 +
                         texture_float(TZ_SCENE_ARG at + 5u) * b2;
    return tex_uv_of(u, v);
}

/* Slot + 1 of map `which` (TZ_MAP_*) among a material's maps (gpu_material.maps), 0 for none. */
TZ_LANE_FN TZ_UINT map_slot(TZ_UVEC4 maps, int which) {
    TZ_UINT word = which < 2 ? maps.x : (which < 4 ? maps.y : (which < 6 ? maps.z : maps.w));
    return ((which & 1) != 0 ? word >> 16 : word) & 65535u;
}

/* Whether a material has any map. */
TZ_LANE_FN TZ_BOOL has_maps(TZ_UVEC4 maps) { return (maps.x | maps.y | maps.z | maps.w) != 0u; }

/* The factors map `which` (a grey or glTF metallic-roughness image) scales values by: its
 * texel at uv, each channel clamped to [0, 1]; 1 in each without the map. One lookup serves
 * every channel a map holds (glTF's metallic in blue, roughness in green). */
TZ_FN vec3 map_factors(TZ_SCENE_PARAM TZ_UVEC4 maps, int which, tex_uv uv) {
    TZ_UINT slot = map_slot(maps, which);
    vec3 f = v3(1.0f, 1.0f, 1.0f);
    if (slot != 0u) {
        vec3 c = texture_sample(TZ_SCENE_ARG slot - 1u, uv).rgb;
        f = v3(TZ_MIN(TZ_MAX(c.x, 0.0f), 1.0f), TZ_MIN(TZ_MAX(c.y, 0.0f), 1.0f),
               TZ_MIN(TZ_MAX(c.z, 0.0f), 1.0f));
    }
    return f;
}

/* Material m of a hit at uv with its maps (gpu_material.maps) applied: the colour map's RGB,
 * clamped to [0, 1], times the colour; for the microfacet kinds the metallic and roughness maps
 * times pbr's metallic and the roughness (glTF's rule), the width roughness^2 kept at least
 * TZ_GGX_MIN_ALPHA (a factor below its square root then maps a little rougher than squared). */
TZ_FN bsdf_material textured_material(TZ_SCENE_PARAM bsdf_material m, TZ_UVEC4 maps, tex_uv uv) {
    TZ_UINT color = map_slot(maps, TZ_MAP_COLOR);
    if (color != 0u) {
        texel c = texture_sample(TZ_SCENE_ARG color - 1u, uv);
        vec3 unit = v3(TZ_MIN(TZ_MAX(c.rgb.x, 0.0f), 1.0f), TZ_MIN(TZ_MAX(c.rgb.y, 0.0f), 1.0f),
                       TZ_MIN(TZ_MAX(c.rgb.z, 0.0f), 1.0f));
        m.color = v3_mul(m.color, unit);
    }
    if (is_microfacet(m.kind)) {
        vec3 gltf = map_factors(TZ_SCENE_ARG maps, TZ_MAP_METALLIC_ROUGHNESS, uv);
        float metallic = gltf.z * map_factors(TZ_SCENE_ARG maps, TZ_MAP_METALLIC, uv).x;
        float rough = gltf.y * map_factors(TZ_SCENE_ARG maps, TZ_MAP_ROUGHNESS, uv).x;
        float width = m.alpha * (rough * rough);
        m.ks = m.kind == TZ_MATERIAL_PBR ? m.ks * metallic : m.ks;
        m.alpha = TZ_MAX(width, TZ_GGX_MIN_ALPHA);
    }
    return m;
}

/* Whether the alpha map of slot + 1 `slot` cuts its face away at uv: the map's alpha (its red
 * where the image has none, TZ_SLOT_ALPHA_RED) below the slot's parameter (the cutoff over
 * glTF's alpha factor), or for a stochastic slot (glTF's BLEND, the parameter the factor's
 * inverse) below the parameter times u, a uniform number of the ray (face_ray_uniform), so that
 * the share of rays kept is the alpha. */
TZ_FN TZ_BOOL alpha_cut(TZ_SCENE_PARAM TZ_UINT slot, tex_uv uv, float u) {
    TZ_UINT s = TZ_TEXTURE_FIRST_SLOT + (slot - 1u) * TZ_SLOT_WORDS;
    TZ_UINT flags = texture_word(TZ_SCENE_ARG s + 1u);
    float param = texture_float(TZ_SCENE_ARG s + 2u);
    texel t = texture_sample(TZ_SCENE_ARG slot - 1u, uv);
    float alpha = (flags & TZ_SLOT_ALPHA_RED) != 0u ? t.rgb.x : t.a;
    float threshold = (flags & TZ_SLOT_STOCHASTIC) != 0u ? param * u : param;
    return alpha < threshold;
}

/* The surface's derivatives of position along u and along v, from which a normal map's tangent
 * frame is made (zero where the UVs leave it undefined). */
TZ_STRUCT(uv_frame) {
    vec3 dpdu;
    vec3 dpdv;
}
TZ_STRUCT_END(uv_frame)

/* The UV frame of the face of corners a, b, c whose corner data are gpu_normals index
 * `corners`: the edges solved against the UV differences, up to the sign of their determinant,
 * which is all the frame needs. */
TZ_FN uv_frame face_uv_frame(TZ_SCENE_PARAM TZ_UINT corners, vec3 a, vec3 b, vec3 c) {
    TZ_UINT at = texture_word(TZ_SCENE_ARG TZ_TEXTURE_HEADER + 2u) + 6u * corners;
    float u0 = texture_float(TZ_SCENE_ARG at), v0 = texture_float(TZ_SCENE_ARG at + 1u);
    float du1 = texture_float(TZ_SCENE_ARG at + 2u) - u0;
    float dv1 = texture_float(TZ_SCENE_ARG at + 3u) - v0;
    float du2 = texture_float(TZ_SCENE_ARG at + 4u) - u0;
    float dv2 = texture_float(TZ_SCENE_ARG at + 5u) - v0;
    float det = du1 * dv2 - du2 * dv1;
    float sign = det < 0.0f ? -1.0f : 1.0f;
    vec3 e1 = v3_sub(b, a), e2 = v3_sub(c, a);
    uv_frame f;
    f.dpdu = v3_scale(v3_sub(v3_scale(e1, dv2), v3_scale(e2, dv1)), sign);
    f.dpdv = v3_scale(v3_sub(v3_scale(e2, du1), v3_scale(e1, du2)), sign);
    TZ_BOOL degenerate = det == 0.0f;
    f.dpdu = select3(degenerate, v3(0.0f, 0.0f, 0.0f), f.dpdu);
    f.dpdv = select3(degenerate, v3(0.0f, 0.0f, 0.0f), f.dpdv);
    return f;
}

/* The UV frame of a sphere's point of outward unit normal n (sphere_uv's): u along the azimuth,
 * v up toward +y; zero at the poles. */
TZ_LANE_FN uv_frame sphere_uv_frame(vec3 n) {
    uv_frame f;
    f.dpdu = v3(-n.z, 0.0f, n.x);
    f.dpdv = v3_cross(f.dpdu, n);
    return f;
}

/* Shading normal `shading` (unit, on geometric normal nout's side) bent by the normal map of
 * slot + 1 `slot` at uv in frame f: the map's tangent-space normal (2 rgb - 1, x and y times the
 * slot's scale; OpenGL's convention, green along +v, as glTF's) in the frame of the tangent
 * (dpdu made orthogonal to `shading`), the bitangent on dpdv's side and `shading`. Unbent where
 * the frame is degenerate or the bent normal would leave nout's side. */
TZ_FN vec3 normal_mapped(TZ_SCENE_PARAM TZ_UINT slot, tex_uv uv, uv_frame f, vec3 shading,
                         vec3 nout) {
    TZ_UINT s = TZ_TEXTURE_FIRST_SLOT + (slot - 1u) * TZ_SLOT_WORDS;
    float scale = texture_float(TZ_SCENE_ARG s + 2u);
    vec3 c = texture_sample(TZ_SCENE_ARG slot - 1u, uv).rgb;
    float x = (2.0f * c.x - 1.0f) * scale, y = (2.0f * c.y - 1.0f) * scale;
    float z = 2.0f * c.z - 1.0f;
    vec3 along = v3_sub(f.dpdu, v3_scale(shading, v3_dot(shading, f.dpdu)));
    float along_length = v3_length(along);
    vec3 tangent = v3_scale(along, 1.0f / along_length);
    vec3 bitangent = v3_cross(shading, tangent);
    bitangent = v3_dot(bitangent, f.dpdv) < 0.0f ? v3_scale(bitangent, -1.0f) : bitangent;
    vec3 bent = v3_add(v3_add(v3_scale(tangent, x), v3_scale(bitangent, y)), v3_scale(shading, z));
    float bent_length = v3_length(bent);
    vec3 unit = v3_scale(bent, 1.0f / bent_length);
    TZ_BOOL usable =
        (along_length > 0.0f) TZ_AND(bent_length > 0.0f) TZ_AND(v3_dot(unit, nout) > 0.0f);
    return select3(usable, unit, shading);
}

#endif
