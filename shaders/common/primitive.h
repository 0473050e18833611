/* primitive.h: spheres and triangles as one kind of thing, one text for C and GLSL (dialect.h)
 * over the includer's scene accessors (path.h lists them): primitive ids number the spheres
 * first, then the triangles; a primitive's distance along a ray, the surface at a hit (its
 * normals and material), and what an emitting triangle needs for light sampling. */
#ifndef TRAZADOR_COMMON_PRIMITIVE_H
#define TRAZADOR_COMMON_PRIMITIVE_H

#include "bsdf.h"
#include "dialect.h"
#include "instance.h"
#include "ray.h"
#include "texture.h"

/* Whether the scene has triangles, from the flags: where they are a specialization constant
 * (trace.comp), lavapipe drops the triangle code of sphere scenes (docs/PERF.md, "Triangles'
 * cost to sphere scenes"). */
#define TZ_HAS_TRIANGLES ((TZ_FLAGS & TZ_FLAG_TRIANGLES) != 0u)

/* Whether primitive id is a triangle (else a sphere); TZ_HAS_TRIANGLES first. */
TZ_FN TZ_BOOL is_triangle(TZ_SCENE_PARAM int id) {
    return TZ_HAS_TRIANGLES TZ_AND(id >= TZ_INT(TZ_FRAME.sphere_count));
}

/* The corners of triangle primitive id. */
TZ_STRUCT(triangle_corners) {
    vec3 a;
    vec3 b;
    vec3 c;
}
TZ_STRUCT_END(triangle_corners)

/* The triangle index of triangle primitive id (an instance's face's too). */
TZ_FN int triangle_of(TZ_SCENE_PARAM int id) {
    if (is_instance_key(TZ_SCENE_ARG id)) return triangle_of_key(TZ_SCENE_ARG id);
    return id - TZ_INT(TZ_FRAME.sphere_count);
}

/* Corners k of triangle primitive id in world space: an instance's moved by its transform. */
TZ_FN triangle_corners corners_in_world(TZ_SCENE_PARAM int id, triangle_corners k) {
    if (is_instance_key(TZ_SCENE_ARG id)) {
        int i = instance_of_key(TZ_SCENE_ARG id);
        if (!instance_is_identity(TZ_SCENE_ARG i)) {
            k.a = instance_point(TZ_SCENE_ARG i, k.a);
            k.b = instance_point(TZ_SCENE_ARG i, k.b);
            k.c = instance_point(TZ_SCENE_ARG i, k.c);
        }
    }
    return k;
}

/* The shading normal n of triangle primitive id in world space: an instance's by its inverse
 * transpose (the blend is normalized after). */
TZ_FN vec3 normal_in_world(TZ_SCENE_PARAM int id, vec3 n) {
    if (is_instance_key(TZ_SCENE_ARG id)) {
        int i = instance_of_key(TZ_SCENE_ARG id);
        if (!instance_is_identity(TZ_SCENE_ARG i)) return instance_normal(TZ_SCENE_ARG i, n);
    }
    return n;
}

TZ_FN triangle_corners corners_of(TZ_SCENE_PARAM int id) {
    int t = triangle_of(TZ_SCENE_ARG id);
    triangle_corners k;
    k.a = xyz(triangle_v0(TZ_SCENE_ARG t));
    k.b = xyz(triangle_v1(TZ_SCENE_ARG t));
    k.c = xyz(triangle_v2(TZ_SCENE_ARG t));
    return corners_in_world(TZ_SCENE_ARG id, k);
}

/* Whether the scene has cut-outs (faces with alpha maps), from the flags. */
#define TZ_HAS_CUTOUTS ((TZ_FLAGS & TZ_FLAG_CUTOUTS) != 0u)
/* The same of packed scene p, for the C walks' own loops. */
#define TZ_HAS_CUTOUTS_OF(p) (((p)->frame.flags & TZ_FLAG_CUTOUTS) != 0u)

/* The UV where the ray from o of shear sh (shear_of(d)) meets face k of corner data `corners`
 * (gpu_normals index, TZ_FLAT for none: then (0, 0)): its corners' UVs blended by the barycentric
 * weights of the walk's own edge functions, as triangle_surface blends them. */
TZ_FN tex_uv face_uv_along(TZ_SCENE_PARAM triangle_corners k, TZ_UINT corners, vec3 o,
                           ray_shear sh) {
    tex_uv uv = tex_uv_of(0.0f, 0.0f);
    if (corners != TZ_FLAT) {
        triangle_edges e = triangle_edge_functions(k.a, k.b, k.c, o, sh);
        TZ_PRECISE float inv = 1.0f / e.det;
        TZ_PRECISE float b0 = e.u * inv, b1 = e.v * inv, b2 = e.w * inv;
        uv = corner_uv(TZ_SCENE_ARG corners, b0, b1, b2);
    }
    return uv;
}

/* A uniform number of the ray from o of shear sh meeting primitive id: a hash of their bits, the
 * same on every back end, for glTF's BLEND (alpha_cut). */
TZ_FN float face_ray_uniform(int id, vec3 o, ray_shear sh) {
    TZ_UINT h = rng_hash(TZ_UINT_OF(id) ^ rng_hash(uint_bits(sh.sx) ^ rng_hash(uint_bits(sh.sy))));
    h = rng_hash(h ^ uint_bits(sh.sz) ^ rng_hash(uint_bits(o.x) ^ rng_hash(uint_bits(o.y))));
    h = rng_hash(h ^ uint_bits(o.z));
    return TZ_FLOAT(h >> 8) * (1.0f / 16777216.0f);
}

/* Whether face primitive id (corners k) is cut away where the ray from o of shear sh meets it:
 * its material's alpha map at the hit's UV (alpha_cut); false without one. Every walk asks it of
 * each face it hits, under TZ_FLAG_CUTOUTS alone, so a cut face is no hit for any ray. */
TZ_FN TZ_BOOL face_cut(TZ_SCENE_PARAM int id, triangle_corners k, vec3 o, ray_shear sh) {
    int t = id - TZ_INT(TZ_FRAME.sphere_count);
    TZ_UINT material = uint_bits(triangle_v0(TZ_SCENE_ARG t).w);
    TZ_UINT slot = map_slot(material_maps(TZ_SCENE_ARG TZ_INT(material)), TZ_MAP_ALPHA);
    TZ_BOOL cut = TZ_FALSE;
    if (slot != 0u) {
        TZ_UINT corners = uint_bits(triangle_v1(TZ_SCENE_ARG t).w);
        tex_uv uv = face_uv_along(TZ_SCENE_ARG k, corners, o, sh);
        cut = alpha_cut(TZ_SCENE_ARG slot, uv, face_ray_uniform(id, o, sh));
    }
    return cut;
}

/* Distance to triangle primitive id along o + t d, sh the ray's shear_of(d) (triangle_distance);
 * infinity where the face is cut away there (face_cut), looked up only for hits at most best
 * (the walk's hit so far: a farther one loses to it, cut or not). */
TZ_FN float triangle_distance_at(TZ_SCENE_PARAM int id, vec3 o, ray_shear sh, float tmin, int self,
                                 float best) {
    triangle_corners k = corners_of(TZ_SCENE_ARG id);
    float t = sheared_triangle_distance(k.a, k.b, k.c, o, sh, tmin, id == self);
    if (TZ_HAS_CUTOUTS && t < TZ_INFINITY && t <= best && face_cut(TZ_SCENE_ARG id, k, o, sh))
        t = TZ_INFINITY;
    return t;
}

/* Distance to primitive id along o + t d: the nearest t > tmin, infinity for a miss; self is
 * the primitive the ray leaves, sh the ray's shear_of(d), made once a walk, best the walk's hit
 * so far (triangle_distance_at). */
TZ_FN float primitive_distance(TZ_SCENE_PARAM int id, vec3 o, vec3 d, ray_shear sh, float tmin,
                               int self, float best) {
    if (is_triangle(TZ_SCENE_ARG id))
        return triangle_distance_at(TZ_SCENE_ARG id, o, sh, tmin, self, best);
    TZ_VEC4 cr = sphere_center_radius(TZ_SCENE_ARG id);
    return sphere_distance(cr.x, cr.y, cr.z, cr.w, o, d, tmin, id == self);
}

/* The unit geometric normal of a triangle, cross(b - a, c - a) normalized. */
TZ_FN vec3 triangle_normal(triangle_corners k) {
    TZ_PRECISE vec3 e1 = v3_sub(k.b, k.a), e2 = v3_sub(k.c, k.a);
    return v3_normalize(v3_cross(e1, e2));
}

/* A hit surface: pos the point, nout its outward normal (a sphere's, or a triangle's geometric
 * one), shading the shading normal on nout's side (nout itself for spheres and flat faces), m its
 * material, emitter its emitter slot (-1: none). */
TZ_STRUCT(surface) {
    vec3 pos;
    vec3 nout;
    vec3 shading;
    bsdf_material m;
    int emitter;
}
TZ_STRUCT_END(surface)

/* No surface: every field zero (where a ray met nothing). */
TZ_FN surface surface_none(void) {
    surface s;
    s.pos = v3(0.0f, 0.0f, 0.0f);
    s.nout = s.pos;
    s.shading = s.pos;
    s.m = bsdf_material_of(TZ_VEC4_ZERO, TZ_VEC4_ZERO);
    s.emitter = -1;
    return s;
}

/* The surface of triangle primitive id at pos, hit by o + t d: an instance's face as its
 * corners and normals are in world space, moved there right after the hit. */
TZ_FN surface triangle_surface(TZ_SCENE_PARAM int id, vec3 pos, vec3 o, vec3 d) {
    int t = triangle_of(TZ_SCENE_ARG id);
    TZ_VEC4 v0 = triangle_v0(TZ_SCENE_ARG t), v1 = triangle_v1(TZ_SCENE_ARG t);
    TZ_VEC4 v2 = triangle_v2(TZ_SCENE_ARG t);
    triangle_corners k; /* corners_of's, from the fields read once */
    k.a = xyz(v0);
    k.b = xyz(v1);
    k.c = xyz(v2);
    k = corners_in_world(TZ_SCENE_ARG id, k);
    surface s;
    s.nout = triangle_normal(k);
    s.pos = plane_hit(k.a, s.nout, o, d, pos);
    s.shading = s.nout;
    TZ_UINT material = uint_bits(v0.w), normals = uint_bits(v1.w);
    s.m = bsdf_material_of(material_color_ks(TZ_SCENE_ARG TZ_INT(material)),
                           material_params(TZ_SCENE_ARG TZ_INT(material)));
    s.emitter = TZ_INT(v2.w) - 1;
    tex_uv uv = tex_uv_of(0.0f, 0.0f); /* a face without UVs reads its textures there */
    if (normals != TZ_FLAT) {
        /* Barycentric weights of the hit from the very edge functions the walk tested. */
        triangle_edges e = triangle_edge_functions(k.a, k.b, k.c, o, shear_of(d));
        TZ_PRECISE float inv = 1.0f / e.det;
        TZ_PRECISE float b0 = e.u * inv, b1 = e.v * inv, b2 = e.w * inv;
        vec3 n0 = normal_in_world(TZ_SCENE_ARG id, xyz(normals_n0(TZ_SCENE_ARG TZ_INT(normals))));
        vec3 n1 = normal_in_world(TZ_SCENE_ARG id, xyz(normals_n1(TZ_SCENE_ARG TZ_INT(normals))));
        vec3 n2 = normal_in_world(TZ_SCENE_ARG id, xyz(normals_n2(TZ_SCENE_ARG TZ_INT(normals))));
        TZ_PRECISE vec3 n = v3_add(v3_add(v3_scale(n0, b0), v3_scale(n1, b1)), v3_scale(n2, b2));
        TZ_PRECISE float len = v3_length(n);
        vec3 unit = v3_scale(n, 1.0f / len);
        /* A normal that interpolates to nothing (a flat face that has corner data for its UVs
         * alone: zero normals) or faces away from the face: the face's own. */
        TZ_BOOL usable = (len > 0.0f) TZ_AND(v3_dot(unit, s.nout) > 0.0f);
        s.shading = select3(usable, unit, s.nout);
        if (TZ_HAS_TEXTURES) uv = corner_uv(TZ_SCENE_ARG normals, b0, b1, b2);
    }
    if (TZ_HAS_TEXTURES) {
        TZ_UVEC4 maps = material_maps(TZ_SCENE_ARG TZ_INT(material));
        s.m = textured_material(TZ_SCENE_ARG s.m, maps, uv);
        TZ_UINT normal_map = map_slot(maps, TZ_MAP_NORMAL);
        if ((normal_map != 0u) TZ_AND(normals != TZ_FLAT)) {
            uv_frame f = face_uv_frame(TZ_SCENE_ARG normals, k.a, k.b, k.c);
            s.shading = normal_mapped(TZ_SCENE_ARG normal_map, uv, f, s.shading, s.nout);
        }
    }
    return s;
}

/* Surface s of sphere primitive id (its point, outward normal and material filled in) with its
 * material's maps applied at the point's sphere_uv (the packet builds call it on the spheres
 * they gather themselves). */
TZ_FN surface sphere_textured(TZ_SCENE_PARAM int id, surface s) {
    TZ_UVEC4 maps = material_maps(TZ_SCENE_ARG sphere_material_index(TZ_SCENE_ARG id));
    if (has_maps(maps)) {
        tex_uv uv = sphere_uv(s.nout);
        s.m = textured_material(TZ_SCENE_ARG s.m, maps, uv);
        TZ_UINT normal_map = map_slot(maps, TZ_MAP_NORMAL);
        if (normal_map != 0u)
            s.shading = normal_mapped(TZ_SCENE_ARG normal_map, uv, sphere_uv_frame(s.nout),
                                      s.shading, s.nout);
    }
    return s;
}

/* The point o + t d where a ray meets a primitive (a face's is then put on its plane). */
TZ_LANE_FN vec3 ray_point(vec3 o, vec3 d, float t) {
    TZ_PRECISE vec3 pos = v3_add(o, v3_scale(d, t));
    return pos;
}

/* The outward normal of the sphere of centre c and radius r at its point pos. */
TZ_LANE_FN vec3 sphere_normal(vec3 c, float r, vec3 pos) {
    TZ_PRECISE vec3 n = v3_scale(v3_sub(pos, c), 1.0f / r);
    return n;
}

/* The surface of primitive id where the ray o + t d meets it. */
TZ_FN surface surface_at(TZ_SCENE_PARAM int id, vec3 o, vec3 d, float t) {
    vec3 pos = ray_point(o, d, t);
    if (is_triangle(TZ_SCENE_ARG id)) return triangle_surface(TZ_SCENE_ARG id, pos, o, d);
    TZ_VEC4 cr = sphere_center_radius(TZ_SCENE_ARG id);
    surface s;
    s.pos = pos;
    vec3 nout = sphere_normal(xyz(cr), cr.w, pos);
    s.nout = nout;
    s.shading = nout;
    TZ_VEC4 params = sphere_params(TZ_SCENE_ARG id);
    s.m = bsdf_material_of(sphere_color_ks(TZ_SCENE_ARG id), params);
    s.emitter = TZ_INT(params.w) - 1;
    if (TZ_HAS_TEXTURES) s = sphere_textured(TZ_SCENE_ARG id, s);
    return s;
}

/* The shading normal of surface s facing the ray d: the side is the geometric normal's. */
TZ_FN vec3 facing_shading(surface s, vec3 d) {
    TZ_BOOL front = v3_dot(s.nout, d) < 0.0f;
    return select3(front, s.shading, v3_scale(s.shading, -1.0f));
}

/* The emitter slot of primitive id, -1 when it emits nothing. */
TZ_FN int emitter_of(TZ_SCENE_PARAM int id) {
    if (is_triangle(TZ_SCENE_ARG id))
        return TZ_INT(triangle_v2(TZ_SCENE_ARG triangle_of(TZ_SCENE_ARG id)).w) - 1;
    return TZ_INT(sphere_params(TZ_SCENE_ARG id).w) - 1;
}

#endif
