/* lights.h: what the scene's point lights give a diffuse hit, one text for C and GLSL
 * (dialect.h) over the includer's scene accessors (see path.h), for both integrators. */
#ifndef TRAZADOR_COMMON_LIGHTS_H
#define TRAZADOR_COMMON_LIGHTS_H

#include "dialect.h"
#include "ray.h"
#include "shade.h"

/* The Phong BRDF of sphere id at the lobe cosine x (phong_from_lobe). */
TZ_FN vec3 sphere_brdf_at(TZ_SCENE_PARAM int id, float x) {
    TZ_VEC4 color_ks = sphere_color_ks(TZ_SCENE_ARG id);
    float alpha = sphere_params(TZ_SCENE_ARG id).x;
    float lobe = color_ks.w > 0.0f ? phong_lobe(x, alpha) : 0.0f;
    return phong_from_lobe(xyz(color_ks), color_ks.w, alpha, lobe);
}

/* Light from every point light at pos (facing normal n, wo the way back) on sphere id, through
 * shadow rays that leave offset_origin(pos, n). */
TZ_FN vec3 point_lights(TZ_SCENE_PARAM int id, vec3 pos, vec3 n, vec3 wo) {
    vec3 o = offset_origin(pos, n);
    TZ_PRECISE vec3 sum = v3(0.0f, 0.0f, 0.0f);
    TZ_UNROLL for (TZ_UINT k = 0u; k < light_count(TZ_SCENE_ONLY); k++) {
        light_sample l = point_light(light_position_power(TZ_SCENE_ARG TZ_INT(k)),
                                     light_color(TZ_SCENE_ARG TZ_INT(k)), pos, n);
        if (l.cos_i <= 0.0f || integrator_occluded(TZ_SCENE_ARG o, l.wi, l.dist, id)) continue;
        sum = v3_add(
            sum, v3_mul(sphere_brdf_at(TZ_SCENE_ARG id, phong_lobe_cos(n, l.wi, wo)), l.radiance));
    }
    return sum;
}

#endif
