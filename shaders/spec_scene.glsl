/* spec_scene.glsl: the spheres and lights of an unrolled scene as specialization constants: float
 * i of struct gpu_unrolled is constant_id TZ_SPEC_SCENE + i (src/render/vk/render_vk.c fills
 * them), so that lavapipe compiles the unrolled loops with immediate operands. Included by
 * trace.comp. */
#ifndef TRAZADOR_SPEC_SCENE_GLSL
#define TRAZADOR_SPEC_SCENE_GLSL

/* The constant vec4 `name`, vec4 n of gpu_unrolled; the fields of sphere and light k. */
#define TZ_SPEC_VEC4(name, n)                                                     \
    layout(constant_id = TZ_SPEC_SCENE + 4 * (n)) const float name##_x = 0.0;     \
    layout(constant_id = TZ_SPEC_SCENE + 4 * (n) + 1) const float name##_y = 0.0; \
    layout(constant_id = TZ_SPEC_SCENE + 4 * (n) + 2) const float name##_z = 0.0; \
    layout(constant_id = TZ_SPEC_SCENE + 4 * (n) + 3) const float name##_w = 0.0; \
    const vec4 name = vec4(name##_x, name##_y, name##_z, name##_w);
#define TZ_SPEC_SPHERE(k)                           \
    TZ_SPEC_VEC4(sphere_##k##_center_radius, 3 * k) \
    TZ_SPEC_VEC4(sphere_##k##_color_ks, 3 * k + 1)  \
    TZ_SPEC_VEC4(sphere_##k##_params, 3 * k + 2)
#define TZ_SPEC_LIGHT(k)                                                        \
    TZ_SPEC_VEC4(light_##k##_position_power, 3 * TZ_UNROLL_MAX_SPHERES + 2 * k) \
    TZ_SPEC_VEC4(light_##k##_color, 3 * TZ_UNROLL_MAX_SPHERES + 2 * k + 1)

/* TZ_UNROLL_MAX_SPHERES spheres and TZ_UNROLL_MAX_LIGHTS lights. */
TZ_SPEC_SPHERE(0) TZ_SPEC_SPHERE(1) TZ_SPEC_SPHERE(2) TZ_SPEC_SPHERE(3)
TZ_SPEC_SPHERE(4) TZ_SPEC_SPHERE(5) TZ_SPEC_SPHERE(6) TZ_SPEC_SPHERE(7)
TZ_SPEC_SPHERE(8) TZ_SPEC_SPHERE(9) TZ_SPEC_SPHERE(10) TZ_SPEC_SPHERE(11)
TZ_SPEC_SPHERE(12) TZ_SPEC_SPHERE(13) TZ_SPEC_SPHERE(14) TZ_SPEC_SPHERE(15)
TZ_SPEC_LIGHT(0) TZ_SPEC_LIGHT(1) TZ_SPEC_LIGHT(2) TZ_SPEC_LIGHT(3)

/* Keeps `field` of sphere (light) n in v when n is k and unrolled: with k a constant, as in the
 * unrolled loops, the selects fold to that one constant. */
#define TZ_PICK_SPHERE(field, n) v = int(UNROLLED_SPHERES) > n && k == n ? sphere_##n##_##field : v;
#define TZ_PICK_LIGHT(field, n) v = int(UNROLLED_LIGHTS) > n && k == n ? light_##n##_##field : v;
#define TZ_SPEC_SPHERE_FIELD(field)                                                   \
    vec4 spec_sphere_##field(int k) {                                                 \
        vec4 v = sphere_0_##field;                                                    \
        TZ_PICK_SPHERE(field, 1) TZ_PICK_SPHERE(field, 2) TZ_PICK_SPHERE(field, 3)    \
        TZ_PICK_SPHERE(field, 4) TZ_PICK_SPHERE(field, 5) TZ_PICK_SPHERE(field, 6)    \
        TZ_PICK_SPHERE(field, 7) TZ_PICK_SPHERE(field, 8) TZ_PICK_SPHERE(field, 9)    \
        TZ_PICK_SPHERE(field, 10) TZ_PICK_SPHERE(field, 11) TZ_PICK_SPHERE(field, 12) \
        TZ_PICK_SPHERE(field, 13) TZ_PICK_SPHERE(field, 14) TZ_PICK_SPHERE(field, 15) \
        return v;                                                                     \
    }
#define TZ_SPEC_LIGHT_FIELD(field)                                              \
    vec4 spec_light_##field(int k) {                                            \
        vec4 v = light_0_##field;                                               \
        TZ_PICK_LIGHT(field, 1) TZ_PICK_LIGHT(field, 2) TZ_PICK_LIGHT(field, 3) \
        return v;                                                               \
    }

/* spec_sphere_center_radius(k) .. spec_light_color(k): the fields of unrolled sphere (light) k. */
TZ_SPEC_SPHERE_FIELD(center_radius)
TZ_SPEC_SPHERE_FIELD(color_ks)
TZ_SPEC_SPHERE_FIELD(params)
TZ_SPEC_LIGHT_FIELD(position_power)
TZ_SPEC_LIGHT_FIELD(color)

#endif
