/* lights.h: the BRDF and what the scene's point lights give a diffuse hit, one text for C and
 * GLSL (dialect.h) over the includer's scene accessors (see path.h), for both integrators. */
#ifndef TRAZADOR_COMMON_LIGHTS_H
#define TRAZADOR_COMMON_LIGHTS_H

#include "dialect.h"
#include "primitive.h"
#include "ray.h"
#include "shade.h"

/* The Phong BRDF of a material (color_ks, alpha) at the lobe cosine x (phong_from_lobe). */
TZ_FN vec3 brdf_at(TZ_VEC4 color_ks, float alpha, float x) {
    float lobe = color_ks.w > 0.0f ? phong_lobe(x, alpha) : 0.0f;
    return phong_from_lobe(xyz(color_ks), color_ks.w, alpha, lobe);
}

/* Light from every point light at surface s of primitive id (facing shading normal n, facing
 * geometric normal ng, wo the way back), through shadow rays that leave offset_origin(pos, ng);
 * a light behind either normal gives nothing. */
TZ_FN vec3 point_lights(TZ_SCENE_PARAM surface s, int id, vec3 n, vec3 ng, vec3 wo) {
    vec3 o = offset_origin(s.pos, ng);
    TZ_PRECISE vec3 sum = v3(0.0f, 0.0f, 0.0f);
    TZ_UNROLL for (TZ_UINT k = 0u; k < light_count(TZ_SCENE_ONLY); k++) {
        light_sample l = point_light(light_position_power(TZ_SCENE_ARG TZ_INT(k)),
                                     light_color(TZ_SCENE_ARG TZ_INT(k)), s.pos, n);
        if (l.cos_i <= 0.0f || v3_dot(ng, l.wi) <= 0.0f ||
            integrator_occluded(TZ_SCENE_ARG o, l.wi, l.dist, id))
            continue;
        vec3 f = brdf_at(s.color_ks, s.params.x, phong_lobe_cos(n, l.wi, wo));
        sum = v3_add(sum, v3_mul(f, l.radiance));
    }
    return sum;
}

#endif
