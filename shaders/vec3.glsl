/* vec3.glsl: the vector helpers of src/vec3.h, written out so that every sum runs in the C
 * order; `precise` forbids the compiler to fuse or reorder them (GLSL's dot(), length() and
 * normalize() promise neither an order nor a rounding). */
#ifndef TRAZADOR_VEC3_GLSL
#define TRAZADOR_VEC3_GLSL

float v3_dot(vec3 a, vec3 b) {
    precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
    return r;
}

float v3_length(vec3 a) {
    precise float r = sqrt(v3_dot(a, a));
    return r;
}

vec3 v3_normalize(vec3 a) {
    precise vec3 r = a * (1.0 / v3_length(a));
    return r;
}

float v3_max_abs(vec3 a) { return max(abs(a.x), max(abs(a.y), abs(a.z))); }

#endif
