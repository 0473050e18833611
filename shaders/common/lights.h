/* lights.h: what the scene's point lights give a hit of a lobe material (through its BSDF), one
 * text for C and GLSL (dialect.h) over the includer's scene accessors (see path.h), for both
 * integrators. */
#ifndef TRAZADOR_COMMON_LIGHTS_H
#define TRAZADOR_COMMON_LIGHTS_H

#include "bsdf.h"
#include "dialect.h"
#include "primitive.h"
#include "ray.h"
#include "shade.h"

/* Light from every point light at surface s of primitive id (facing shading normal n, facing
 * geometric normal ng, wo the way back), through shadow rays that leave offset_origin(pos, ng)
 * (rough glass's from below: point_light_reaches); a light behind either normal gives nothing. */
TZ_FN vec3 point_lights(TZ_SCENE_PARAM surface s, int id, vec3 n, vec3 ng, vec3 wo) {
    TZ_PRECISE vec3 sum = v3(0.0f, 0.0f, 0.0f);
    TZ_UNROLL for (TZ_UINT k = 0u; k < light_count(TZ_SCENE_ONLY); k++) {
        light_sample l = point_light(light_position_power(TZ_SCENE_ARG TZ_INT(k)),
                                     light_color(TZ_SCENE_ARG TZ_INT(k)),
                                     light_shape(TZ_SCENE_ARG TZ_INT(k)), s.pos, n);
        vec3 o = bsdf_next_origin(s.pos, ng, l.wi);
        if (!point_light_reaches(s.m.kind, l.cos_i, ng, l.wi) ||
            integrator_occluded(TZ_SCENE_ARG o, l.wi, l.dist, id))
            continue;
        vec3 f = bsdf_f(s.m, n, l.wi, wo);
        vec3 radiance = select3(l.cos_i < 0.0f, v3_scale(l.radiance, -1.0f), l.radiance);
        sum = v3_add(sum, v3_mul(f, radiance));
    }
    return sum;
}

#endif
