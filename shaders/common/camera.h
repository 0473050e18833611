/* camera.h: a sample's camera ray, one text for C and GLSL (dialect.h) for both modes: the
 * jitter numbers come first in the pixel's sample, then the ray through the plane. */
#ifndef TRAZADOR_COMMON_CAMERA_H
#define TRAZADOR_COMMON_CAMERA_H

#include "dialect.h"
#include "ray.h"
#include "sampler.h"
#include "shade.h"

/* The camera ray of pixel (i, j), i to the right, j down, from the sampler rng: both jitter
 * numbers are always drawn, so the numbers after them do not depend on the flag. */
TZ_FN next_ray camera_ray(TZ_SCENE_PARAM TZ_UINT i, TZ_UINT j, TZ_INOUT(sampler_state) rng) {
    float u, v;
    sample_2d(TZ_FLAGS, rng, TZ_REF(u), TZ_REF(v));
    if ((TZ_FLAGS & TZ_FLAG_JITTER) == 0u) u = v = 0.5f;
    next_ray r;
    r.d = camera_direction(TZ_FRAME.right, TZ_FRAME.up, TZ_FRAME.forward, TZ_FRAME.origin.w, i, j,
                           u, v);
    r.o = camera_origin(TZ_FRAME.origin, TZ_FRAME.near_distance, r.d);
    return r;
}

#endif
