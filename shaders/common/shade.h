/* shade.h: what happens at a hit, one text for C and GLSL (dialect.h): the normal, the mirror
 * and glass step, the Phong BRDF, the point-light term and the cosine-weighted bounce. */
#ifndef TRAZADOR_COMMON_SHADE_H
#define TRAZADOR_COMMON_SHADE_H

#include "dialect.h"
#include "ray.h"
#include "transcendental.h"

/* Normal of an opaque (two-sided) surface facing the ray d, from the outward normal. */
TZ_FN vec3 facing_normal(vec3 nout, vec3 d) {
    return select3(v3_dot(nout, d) < 0.0f, nout, v3_scale(nout, -1.0f));
}

/* A ray: origin and unit direction. */
TZ_STRUCT(next_ray) {
    vec3 o;
    vec3 d;
}
TZ_STRUCT_END(next_ray)

/* w mirrored in the plane of unit normal ng: the other direction that folds onto w. */
TZ_FN vec3 mirror_in_plane(vec3 w, vec3 ng) {
    TZ_PRECISE vec3 m = v3_sub(w, v3_scale(ng, 2.0f * v3_dot(ng, w)));
    return m;
}

/* The normal that a mirror or glass hit turns the incoming ray d about, facing d: the shading
 * normal (shading, on the side of the outward geometric normal nout) where d meets it from the
 * front, else the geometric normal. Spheres and flat faces have shading = nout: theirs. */
TZ_FN vec3 specular_normal(vec3 nout, vec3 shading, vec3 d) {
    TZ_BOOL entering = v3_dot(d, nout) < 0.0f;
    vec3 side = select3(entering, nout, v3_scale(nout, -1.0f));
    vec3 shade = select3(entering, shading, v3_scale(shading, -1.0f));
    return select3(v3_dot(d, shade) < 0.0f, shade, side);
}

/* The ray leaving a mirror or glass hit at pos (outward geometric normal nout, incoming d),
 * turned about n, specular_normal's: the mirror ray, or with refractive the refracted one
 * (Snell's law; total internal reflection keeps the mirror ray). Its origin is offset to the
 * side of the face it leaves on; a shading normal's ray that would leave on the other side is
 * mirrored in the face's plane onto this one (as a diffuse face folds its directions), so that
 * no mirror ray passes through the face nor a refracted one turns back. */
TZ_FN next_ray specular_next(vec3 pos, vec3 nout, vec3 n, vec3 d, TZ_BOOL refractive, float ior) {
    float eps = ray_eps(pos);
    TZ_BOOL entering = v3_dot(d, nout) < 0.0f;
    TZ_PRECISE vec3 side = select3(entering, nout, v3_scale(nout, -1.0f)); /* faces the ray */
    /* Normalized: nout is unit only to rounding, and the error of an unnormalized mirror ray
     * grows with each reflection until a ray escapes a closed mirror (the sphere test assumes
     * |d| = 1). */
    TZ_PRECISE vec3 mirror_d = v3_normalize(v3_sub(d, v3_scale(n, 2.0f * v3_dot(n, d))));
    vec3 mirror_folded = v3_normalize(mirror_in_plane(mirror_d, side));
    mirror_d = select3(v3_dot(mirror_d, side) > 0.0f, mirror_d, mirror_folded);
    TZ_PRECISE vec3 mirror_o = v3_add(pos, v3_scale(side, eps));
    next_ray r;
    r.o = mirror_o;
    r.d = mirror_d;
    TZ_BRANCH_IF(refractive) {
        TZ_PRECISE float eta = entering ? 1.0f / ior : ior;
        TZ_PRECISE float c1 = -v3_dot(d, n);
        TZ_PRECISE float k = 1.0f - eta * eta * (1.0f - c1 * c1);
        /* k < 0: total internal reflection, the mirror ray (the refracted one is NaN, unused). */
        TZ_BOOL refracts = refractive TZ_AND(k >= 0.0f);
        TZ_PRECISE vec3 refracted_d =
            v3_normalize(v3_add(v3_scale(d, eta), v3_scale(n, eta * c1 - TZ_SQRT(k))));
        vec3 refracted_folded = v3_normalize(mirror_in_plane(refracted_d, side));
        refracted_d = select3(v3_dot(refracted_d, side) < 0.0f, refracted_d, refracted_folded);
        TZ_PRECISE vec3 refracted_o = v3_sub(pos, v3_scale(side, eps));
        r.o = select3(refracts, refracted_o, r.o);
        r.d = select3(refracts, refracted_d, r.d);
    }
    return r;
}

/* Cosine of the Phong lobe angle: wo . wr with wr = 2(n.wi)n - wi. */
TZ_FN float phong_lobe_cos(vec3 n, vec3 wi, vec3 wo) {
    TZ_PRECISE vec3 wr = v3_sub(v3_scale(n, 2.0f * v3_dot(n, wi)), wi);
    return v3_dot(wo, wr);
}

/* The lobe of phong_from_lobe: x^alpha for x > 0, else 0 (0^alpha taken as 0, even for alpha 0,
 * and so is x below the normal range: pow_unit). Alpha 0 (bsdf_pdf's of every Lambertian
 * surface) skips pow_unit, whose x^0 is that very 1. */
TZ_FN float phong_lobe(float x, float alpha) {
    float one = x >= TZ_FLT_MIN ? 1.0f : 0.0f;
    return alpha == 0.0f ? one : pow_unit(x, alpha);
}

/* Normalized Phong BRDF kd/pi + ks (alpha+2)/(2 pi) lobe; ks 0 is Lambertian. */
TZ_FN vec3 phong_from_lobe(vec3 kd, float ks, float alpha, float lobe) {
    TZ_PRECISE vec3 f = v3_scale(kd, 1.0f / TZ_PI);
    TZ_PRECISE float spec = ks * (alpha + 2.0f) / (2.0f * TZ_PI) * lobe;
    TZ_PRECISE vec3 glossy = v3_add(f, v3(spec, spec, spec));
    return ks > 0.0f ? glossy : f;
}

/* What a point light sends to a surface point, before the BRDF and the shadow ray. */
TZ_STRUCT(light_sample) {
    vec3 wi;       /* unit direction to the light */
    float dist;    /* distance to it */
    float cos_i;   /* n . wi */
    vec3 radiance; /* power / dist^2 times its colour, times cos_i */
}
TZ_STRUCT_END(light_sample)

/* The light of gpu_light (position_power, color, shape) arriving at pos with shading normal n,
 * from the true hit point (only the shadow ray starts off the surface): a point light's
 * intensity over dist^2; a spot's times glTF's falloff; a sun's irradiance from its direction,
 * its shadow ray running to TZ_ENV_DISTANCE. */
TZ_FN light_sample point_light(TZ_VEC4 position_power, TZ_VEC4 color, TZ_VEC4 shape, vec3 pos,
                               vec3 n) {
    TZ_PRECISE vec3 to_light = v3_sub(xyz(position_power), pos);
    TZ_PRECISE float dist2 = v3_dot(to_light, to_light);
    TZ_PRECISE float dist = TZ_SQRT(dist2);
    TZ_PRECISE vec3 wi = v3_scale(to_light, 1.0f / dist);
    TZ_BOOL sun = shape.w < 0.0f;
    wi = sun ? xyz(position_power) : wi;
    float cos_i = v3_dot(n, wi);
    TZ_PRECISE float scale = sun ? cos_i * position_power.w : cos_i * position_power.w / dist2;
    /* the spot's falloff (1 exactly inside the inner cone) */
    TZ_PRECISE float cd = -v3_dot(xyz(shape), wi);
    TZ_PRECISE float fall = TZ_MIN(TZ_MAX(cd * shape.w + color.w, 0.0f), 1.0f);
    TZ_PRECISE float spot = scale * (fall * fall);
    TZ_PRECISE vec3 radiance = v3_scale(xyz(color), shape.w > 0.0f ? spot : scale);
    light_sample s;
    s.wi = wi;
    s.dist = sun ? TZ_ENV_DISTANCE : dist;
    s.cos_i = cos_i;
    s.radiance = radiance;
    return s;
}

/* Two unit tangents that make an orthonormal basis with the unit normal. */
TZ_STRUCT(tangent_frame) {
    vec3 t;
    vec3 b;
}
TZ_STRUCT_END(tangent_frame)

/* The orthonormal basis around unit n of Duff et al. 2017 (no branch, no normalization). */
TZ_FN tangent_frame basis(vec3 n) {
    float sign = n.z >= 0.0f ? 1.0f : -1.0f;
    TZ_PRECISE float a = -1.0f / (sign + n.z);
    TZ_PRECISE float c = n.x * n.y * a;
    TZ_PRECISE vec3 t = v3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
    TZ_PRECISE vec3 b = v3(c, sign + n.y * n.y * a, -n.y);
    tangent_frame f;
    f.t = t;
    f.b = b;
    return f;
}

/* The bounce direction: cosine-weighted around unit n for uniform numbers y1 (cos theta =
 * sqrt(1 - y1)) and y2 (phi = 2 pi y2). */
TZ_FN vec3 cosine_direction(vec3 n, float y1, float y2) {
    TZ_PRECISE float cos_t = TZ_SQRT(1.0f - y1);
    TZ_PRECISE float sin_t = TZ_SQRT(y1);
    cos_sin phi = cos_sin_turn(y2);
    tangent_frame f = basis(n);
    TZ_PRECISE vec3 wi = v3_add(v3_add(v3_scale(f.t, sin_t * phi.c), v3_scale(f.b, sin_t * phi.s)),
                                v3_scale(n, cos_t));
    return wi;
}

#endif
