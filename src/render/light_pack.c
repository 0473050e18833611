/* light_pack.c: the scene's lights as the shaders read them (struct gpu_light, shaders/
 * shared_layout.h): point lights, spots with glTF KHR_lights_punctual's falloff, suns; in path
 * mode a sun with a disc becomes an emitter instead (DESIGN section 3.6). */
#include <math.h>

#include "render/scene_pack.h"

#define PI 3.14159265358979323846

/* A light as the shaders read it: a spot's falloff as glTF writes it, scale 1 / max(1e-3,
 * cos_inner - cos_outer) and offset -cos_outer scale, in double; a sun's direction toward it. */
static struct gpu_light gpu_light_of(const light *l) {
    struct gpu_light g = {
        .position_power = vec4_from(l->position, l->power),
        .color = vec4_from(l->color, 0.0f),
    };
    vec3 d = l->direction;
    if (l->kind == LIGHT_SPOT) {
        double scale = 1.0 / fmax(1e-3, (double)l->cos_inner - l->cos_outer);
        g.color.w = (float)(-(double)l->cos_outer * scale);
        g.shape = vec4_from(d, (float)scale);
    } else if (l->kind == LIGHT_SUN) {
        g.position_power = (tz_vec4){-d.x, -d.y, -d.z, l->power};
        g.shape = (tz_vec4){0.0f, 0.0f, 0.0f, -1.0f};
    }
    return g;
}

sun_disc lights_pack(const scene *s, bool path_mode, double scene_radius, packed_scene *out) {
    sun_disc disc = {{0.0f, 0.0f, 0.0f}, 0.0};
    uint32_t n = 0;
    bool shaped = false;
    for (int k = 0; k < s->light_count; k++) {
        const light *l = &s->lights[k];
        shaped |= l->kind != LIGHT_POINT;
        if (!(path_mode && l->kind == LIGHT_SUN && l->angle > 0.0f)) {
            out->lights[n++] = gpu_light_of(l);
            continue;
        }
        /* A disc of half-angle a and radiance L gives a surface facing it pi sin^2(a) L: the
         * irradiance E asked for. */
        double half = 0.5 * l->angle * (PI / 180.0), sin_half = sin(half);
        double radiance = l->power / (PI * sin_half * sin_half);
        double mean = ((double)l->color.x + l->color.y + l->color.z) / 3.0;
        disc.radiance = v3((float)(radiance * l->color.x), (float)(radiance * l->color.y),
                           (float)(radiance * l->color.z));
        disc.power = l->power * mean * scene_radius * scene_radius / PI;
        double s_quarter = sin(0.5 * half);
        vec3 d = l->direction;
        out->frame.sun = (tz_vec4){-d.x, -d.y, -d.z, (float)(2.0 * s_quarter * s_quarter)};
        if (disc.power > 0.0) out->frame.flags |= TZ_FLAG_SUN_DISC;
    }
    out->frame.light_count = n;
    if (shaped) out->frame.flags |= TZ_FLAG_SHAPED_LIGHTS;
    return disc;
}
