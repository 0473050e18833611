/* camera.h: a sample's camera ray, one text for C and GLSL (dialect.h) for both modes and the
 * packet builds: the jitter numbers come first in the pixel's sample, then the lens's (a thin
 * lens only), then the ray through the plane, perspective or orthographic. */
#ifndef TRAZADOR_COMMON_CAMERA_H
#define TRAZADOR_COMMON_CAMERA_H

#include "dialect.h"
#include "ray.h"
#include "sampler.h"
#include "sampling.h"
#include "shade.h"

/* The numbers of a camera ray: the jitter (u, v) in the pixel, the lens's (lu, lv). */
TZ_STRUCT(camera_numbers) {
    float u;
    float v;
    float lu;
    float lv;
}
TZ_STRUCT_END(camera_numbers)

/* Draws a camera ray's numbers from rng: both jitter numbers always, so that the numbers after
 * them do not depend on the flag; the lens's pair only for a lens, so that pinhole cameras keep
 * every number of their samples. */
TZ_FN camera_numbers camera_draw(TZ_UINT flags, TZ_INOUT(sampler_state) rng) {
    camera_numbers c;
    sample_2d(flags, rng, TZ_REF(c.u), TZ_REF(c.v));
    if ((flags & TZ_FLAG_JITTER) == 0u) c.u = c.v = 0.5f;
    c.lu = c.lv = 0.5f;
    if ((flags & TZ_FLAG_LENS) != 0u) sample_2d(flags, rng, TZ_REF(c.lu), TZ_REF(c.lv));
    return c;
}

/* The camera ray of pixel (i, j) for numbers c (gpu_frame's origin, right, up, forward, near
 * and lens): from the camera position through the plane point, or (orthographic) from the plane
 * point along F; a lens then moves the origin to a point of its disc and aims at where the ray
 * met the plane in focus, lens.y along F. Rays start `near` along their direction. */
TZ_FN next_ray camera_ray_through(TZ_UINT flags, TZ_VEC4 origin, TZ_VEC4 right, TZ_VEC4 up,
                                  TZ_VEC4 forward, float near_distance, TZ_VEC4 lens, TZ_UINT i,
                                  TZ_UINT j, camera_numbers c) {
    next_ray r;
    if ((flags & TZ_FLAG_ORTHOGRAPHIC) != 0u) {
        TZ_PRECISE float x = right.w + (TZ_FLOAT(i) + c.u) * origin.w;
        TZ_PRECISE float y = up.w - (TZ_FLOAT(j) + c.v) * origin.w;
        TZ_PRECISE vec3 o =
            v3_add(xyz(origin), v3_add(v3_scale(xyz(right), x), v3_scale(xyz(up), y)));
        r.o = o;
        r.d = xyz(forward);
    } else {
        r.d = camera_direction(right, up, forward, origin.w, i, j, c.u, c.v);
        r.o = xyz(origin);
    }
    if ((flags & TZ_FLAG_LENS) != 0u) {
        disc_point p = concentric_disc(c.lu, c.lv);
        /* from the lens point to the ray's point in focus: d t - offset, with no cancellation of
         * the camera's position */
        TZ_PRECISE float t = lens.y / v3_dot(r.d, xyz(forward));
        TZ_PRECISE vec3 offset =
            v3_add(v3_scale(xyz(right), p.x * lens.x), v3_scale(xyz(up), p.y * lens.x));
        TZ_PRECISE vec3 o = v3_add(r.o, offset);
        r.d = v3_normalize(v3_sub(v3_scale(r.d, t), offset));
        r.o = o;
    }
    TZ_PRECISE vec3 start = v3_add(r.o, v3_scale(r.d, near_distance));
    r.o = near_distance > 0.0f ? start : r.o;
    return r;
}

/* The camera ray of pixel (i, j), its numbers drawn from the sampler rng. */
TZ_FN next_ray camera_ray(TZ_SCENE_PARAM TZ_UINT i, TZ_UINT j, TZ_INOUT(sampler_state) rng) {
    camera_numbers c = camera_draw(TZ_FLAGS, rng);
    return camera_ray_through(TZ_FLAGS, TZ_FRAME.origin, TZ_FRAME.right, TZ_FRAME.up,
                              TZ_FRAME.forward, TZ_FRAME.near_distance, TZ_FRAME.lens, i, j, c);
}

#endif
