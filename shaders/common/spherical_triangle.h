/* spherical_triangle.h: a triangle seen from a point as a spherical triangle, one text for C and
 * GLSL (dialect.h): its solid angle (Van Oosterom and Strackee, IEEE Trans. Biomed. Eng. 30(2),
 * 1983) and a direction uniform within it (Arvo, "Stratified sampling of spherical triangles",
 * SIGGRAPH 1995, arranged as pbrt-v4's SampleSphericalTriangle), from transcendental.h's
 * functions so that every back end draws the same bits. Light sampling takes a triangle light by
 * solid angle from points near its plane, where that measures better than by area (docs/PERF.md);
 * farther, and where the float angle sum cancels (tiny solid angles) or nearly covers the
 * sphere, by area. */
#ifndef TRAZADOR_COMMON_SPHERICAL_TRIANGLE_H
#define TRAZADOR_COMMON_SPHERICAL_TRIANGLE_H

#include "dialect.h"
#include "transcendental.h"

/* The solid angles, in steradians, that are sampled as a spherical triangle (pbrt-v4's). */
#define TZ_MIN_SPHERICAL_SAMPLE 3e-4f
#define TZ_MAX_SPHERICAL_SAMPLE 6.22f

/* Light sampling takes a triangle by solid angle from points within this many of its longest
 * edges from its plane: farther, area sampling's weight varies little over the triangle, and it
 * costs less (docs/PERF.md). */
#define TZ_SOLID_ANGLE_REACH 0.5f

/* Whether o is within TZ_SOLID_ANGLE_REACH longest edges of the plane of the triangle (a, b, c):
 * its distance along the unit normal, squared, against reach^2 edge^2. Unit, not the cross
 * product: with it (up to the parser's 1.3e19) the squared distance overflowed in scenes the
 * parser takes. */
TZ_FN TZ_BOOL near_triangle_plane(vec3 a, vec3 b, vec3 c, vec3 o) {
    TZ_PRECISE vec3 ab = v3_sub(b, a), ac = v3_sub(c, a), bc = v3_sub(c, b);
    vec3 normal = v3_normalize(v3_cross(ab, ac));
    TZ_PRECISE float h = v3_dot(normal, v3_sub(o, a));
    TZ_PRECISE float edge2 = TZ_MAX(TZ_MAX(v3_dot(ab, ab), v3_dot(ac, ac)), v3_dot(bc, bc));
    TZ_PRECISE float reach2 = TZ_SOLID_ANGLE_REACH * TZ_SOLID_ANGLE_REACH * edge2;
    return h * h < reach2;
}

/* The corners a, b, c as unit directions from the point, and the solid angle they span. */
TZ_STRUCT(spherical_triangle) {
    vec3 a;
    vec3 b;
    vec3 c;
    float solid_angle;
}
TZ_STRUCT_END(spherical_triangle)

/* The spherical triangle of corners a, b, c seen from o: the solid angle is
 * 2 atan(|a . (b x c)| / (1 + a.b + b.c + c.a)) of the unit directions, NaN where a corner is o. */
TZ_FN spherical_triangle spherical_triangle_of(vec3 a, vec3 b, vec3 c, vec3 o) {
    spherical_triangle s;
    s.a = v3_normalize(v3_sub(a, o));
    s.b = v3_normalize(v3_sub(b, o));
    s.c = v3_normalize(v3_sub(c, o));
    TZ_PRECISE float volume = TZ_ABS(v3_dot(s.a, v3_cross(s.b, s.c)));
    TZ_PRECISE float den = 1.0f + v3_dot(s.a, s.b) + v3_dot(s.b, s.c) + v3_dot(s.c, s.a);
    TZ_PRECISE float omega = 2.0f * angle_of(volume, den);
    s.solid_angle = omega;
    return s;
}

/* Whether a spherical triangle of solid angle omega is sampled as one (false for NaN). */
TZ_FN TZ_BOOL by_solid_angle(float omega) {
    return (omega >= TZ_MIN_SPHERICAL_SAMPLE) TZ_AND(omega <= TZ_MAX_SPHERICAL_SAMPLE);
}

/* v made orthogonal to the unit vector w and normalized (one Gram-Schmidt step). */
TZ_FN vec3 orthonormal_to(vec3 v, vec3 w) {
    TZ_PRECISE vec3 r = v3_sub(v, v3_scale(w, v3_dot(v, w)));
    return v3_normalize(r);
}

/* The direction uniform in solid angle within s (by_solid_angle) for uniform ua, ub: ua picks the
 * sub-triangle (a, b, c') of solid angle ua times s's, c' on the arc from a to c, and ub the
 * point on the arc from b to c' that splits it in proportion. */
TZ_FN vec3 spherical_triangle_direction(spherical_triangle s, float ua, float ub) {
    /* alpha, the angle at a between the planes (a, b) and (a, c): its cosine and sine */
    TZ_PRECISE vec3 n_ab = v3_cross(s.a, s.b), n_ca = v3_cross(s.c, s.a);
    TZ_PRECISE float norms = v3_length(n_ab) * v3_length(n_ca);
    TZ_PRECISE float cos_alpha = -v3_dot(n_ab, n_ca) / norms;
    TZ_PRECISE float sin_alpha = v3_length(v3_cross(n_ab, n_ca)) / norms;
    /* the sub-triangle's area plus pi is pi + ua omega: its sine and cosine are -sin, -cos of ua
     * omega, a fraction of a turn below 1 (omega <= TZ_MAX_SPHERICAL_SAMPLE) */
    cos_sin part = cos_sin_turn(ua * (s.solid_angle * 0.159154937f)); /* 1 / (2 pi) in float */
    TZ_PRECISE float sin_phi = part.c * sin_alpha - part.s * cos_alpha;
    TZ_PRECISE float cos_phi = -part.c * cos_alpha - part.s * sin_alpha;
    TZ_PRECISE float k1 = cos_phi + cos_alpha;
    TZ_PRECISE float k2 = sin_phi - sin_alpha * v3_dot(s.a, s.b);
    TZ_PRECISE float cos_bp = (k2 + (k2 * cos_phi - k1 * sin_phi) * cos_alpha) /
                              ((k2 * sin_phi + k1 * cos_phi) * sin_alpha);
    cos_bp = cos_bp > 1.0f ? 1.0f : cos_bp;
    cos_bp = cos_bp > -1.0f ? cos_bp : -1.0f; /* NaN too */
    TZ_PRECISE float sin_bp = TZ_SQRT(TZ_MAX(1.0f - cos_bp * cos_bp, 0.0f));
    TZ_PRECISE vec3 cp = v3_add(v3_scale(s.a, cos_bp), v3_scale(orthonormal_to(s.c, s.a), sin_bp));
    TZ_PRECISE float cos_t = 1.0f - ub * (1.0f - v3_dot(cp, s.b));
    TZ_PRECISE float sin_t = TZ_SQRT(TZ_MAX(1.0f - cos_t * cos_t, 0.0f));
    TZ_PRECISE vec3 w = v3_add(v3_scale(s.b, cos_t), v3_scale(orthonormal_to(cp, s.b), sin_t));
    return w;
}

#endif
