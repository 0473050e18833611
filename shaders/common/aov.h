/* aov.h: the first-hit features of a sample (the feature images a denoiser takes, image/aov.h),
 * one text for C and GLSL (dialect.h) over the scene accessors of report.h: the sample's own
 * camera ray; the albedo and normal of the first surface that is not a mirror or glass, through
 * them as OpenImageDenoise asks (its tints applied to the albedo); the depth (distance from the
 * camera), position and emission of the first hit. */
#ifndef TRAZADOR_COMMON_AOV_H
#define TRAZADOR_COMMON_AOV_H

#include "report.h"

/* A sample's features; hit: whether the camera ray met a surface (the others are zero if not). */
TZ_STRUCT(aov_features) {
    vec3 albedo;
    vec3 normal;
    float depth;
    vec3 position;
    vec3 emission;
    TZ_BOOL hit;
}
TZ_STRUCT_END(aov_features)

/* The features of sample `sample_index` of pixel (i, j), i to the right, j down. */
TZ_FN aov_features aov_sample(TZ_SCENE_PARAM TZ_UINT i, TZ_UINT j, TZ_UINT sample_index) {
    sampler_state rng =
        sampler_start(TZ_FLAGS, TZ_FRAME.seed, j * TZ_FRAME.width + i, sample_index);
    next_ray camera = camera_ray(TZ_SCENE_ARG i, j, TZ_REF(rng));
    aov_features a;
    vec3 black = v3(0.0f, 0.0f, 0.0f);
    a.albedo = black;
    a.normal = black;
    a.depth = 0.0f;
    a.position = black;
    a.emission = black;
    a.hit = TZ_FALSE;
    float t;
    int id = integrator_nearest(TZ_SCENE_ARG camera.o, camera.d, -1, TZ_REF(t));
    if (id < 0) return a;
    surface s = surface_at(TZ_SCENE_ARG id, camera.o, camera.d, t);
    a.hit = TZ_TRUE;
    a.position = s.pos;
    a.depth = v3_length(v3_sub(s.pos, xyz(TZ_FRAME.origin)));
    if (s.emitter >= 0)
        a.emission = emitted_radiance(TZ_SCENE_ARG s.emitter, id, camera.o, camera.d, s.pos);
    if (!bsdf_is_delta(s.m.kind)) {
        a.albedo = bsdf_albedo(s.m);
        a.normal = facing_shading(s, camera.d);
        return a;
    }
    next_ray next = specular_next(s.pos, s.nout, specular_normal(s.nout, s.shading, camera.d),
                                  camera.d, bsdf_refracts(s.m.kind), s.m.ior);
    specular_chain c = follow_specular(TZ_SCENE_ARG next.o, next.d, id);
    if (c.id < 0) return a;
    a.albedo = v3_mul(v3_mul(bsdf_albedo(s.m), c.weight), bsdf_albedo(c.s.m));
    a.normal = c.n;
    return a;
}

#endif
