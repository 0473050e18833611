/* affine.h: points, directions and normals moved by the rows of an affine transform (an
 * instance's, shaders/common/instance.h), one text for C and GLSL (dialect.h). */
#ifndef TRAZADOR_COMMON_AFFINE_H
#define TRAZADOR_COMMON_AFFINE_H

#include "dialect.h"

/* Point p by the affine rows r0, r1, r2 (xyz the 3 x 3 part, w the translation), the products
 * summed in that order, unfused: the same bits in C and GLSL. */
TZ_LANE_FN vec3 affine_point(TZ_VEC4 r0, TZ_VEC4 r1, TZ_VEC4 r2, vec3 p) {
    TZ_PRECISE float x = r0.x * p.x + r0.y * p.y + r0.z * p.z + r0.w;
    TZ_PRECISE float y = r1.x * p.x + r1.y * p.y + r1.z * p.z + r1.w;
    TZ_PRECISE float z = r2.x * p.x + r2.y * p.y + r2.z * p.z + r2.w;
    return v3(x, y, z);
}

/* Direction d by the 3 x 3 part of the rows, as affine_point. */
TZ_LANE_FN vec3 affine_direction(TZ_VEC4 r0, TZ_VEC4 r1, TZ_VEC4 r2, vec3 d) {
    TZ_PRECISE float x = r0.x * d.x + r0.y * d.y + r0.z * d.z;
    TZ_PRECISE float y = r1.x * d.x + r1.y * d.y + r1.z * d.z;
    TZ_PRECISE float z = r2.x * d.x + r2.y * d.y + r2.z * d.z;
    return v3(x, y, z);
}

/* A normal n of model space in world space: by the transpose of the world-to-model rows (the
 * inverse transpose of model to world), not normalized. */
TZ_LANE_FN vec3 affine_normal(TZ_VEC4 r0, TZ_VEC4 r1, TZ_VEC4 r2, vec3 n) {
    TZ_PRECISE float x = r0.x * n.x + r1.x * n.y + r2.x * n.z;
    TZ_PRECISE float y = r0.y * n.x + r1.y * n.y + r2.y * n.z;
    TZ_PRECISE float z = r0.z * n.x + r1.z * n.y + r2.z * n.z;
    return v3(x, y, z);
}

#endif
