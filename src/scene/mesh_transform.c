/* mesh_transform.c: a model's transform on a `mesh` or `camera file` line (directives.h): scale,
 * rotation about a unit axis, translation, in double, applied to points, directions and normals. */
#include <math.h>

#include "scene/directives.h"

mesh_transform mesh_transform_make(const double scale[3], const double rotate[4],
                                   const double translate[3]) {
    mesh_transform m;
    double length = sqrt(rotate[0] * rotate[0] + rotate[1] * rotate[1] + rotate[2] * rotate[2]);
    double u[3] = {rotate[0] / length, rotate[1] / length, rotate[2] / length};
    double angle = rotate[3] * 3.14159265358979323846 / 180.0, c = cos(angle), s = sin(angle);
    /* Rodrigues: c I + s [u]x + (1 - c) u u^T (right-handed). */
    double cross[3][3] = {{0, -u[2], u[1]}, {u[2], 0, -u[0]}, {-u[1], u[0], 0}};
    for (int i = 0; i < 3; i++) {
        m.scale[i] = scale[i];
        m.translate[i] = translate[i];
        for (int j = 0; j < 3; j++)
            m.r[i][j] = (i == j ? c : 0.0) + s * cross[i][j] + (1.0 - c) * u[i] * u[j];
    }
    return m;
}

bool mesh_transform_point(const mesh_transform *m, vec3 v, vec3 *out) {
    double in[3] = {(double)v.x * m->scale[0], (double)v.y * m->scale[1],
                    (double)v.z * m->scale[2]};
    float o[3];
    for (int i = 0; i < 3; i++) {
        double x = m->r[i][0] * in[0] + m->r[i][1] * in[1] + m->r[i][2] * in[2] + m->translate[i];
        if (!(fabs(x) <= 1e18)) return false;
        o[i] = (float)x;
    }
    *out = v3(o[0], o[1], o[2]);
    return true;
}

vec3 mesh_transform_direction(const mesh_transform *m, vec3 v) {
    double in[3] = {(double)v.x * m->scale[0], (double)v.y * m->scale[1],
                    (double)v.z * m->scale[2]};
    float o[3];
    for (int i = 0; i < 3; i++)
        o[i] = (float)(m->r[i][0] * in[0] + m->r[i][1] * in[1] + m->r[i][2] * in[2]) + 0.0f;
    return v3(o[0], o[1], o[2]);
}

bool mesh_transform_normal(const mesh_transform *m, vec3 n, vec3 *out) {
    double in[3] = {n.x / m->scale[0], n.y / m->scale[1], n.z / m->scale[2]}, o[3];
    for (int i = 0; i < 3; i++) o[i] = m->r[i][0] * in[0] + m->r[i][1] * in[1] + m->r[i][2] * in[2];
    double length = sqrt(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    if (!(length > 0.0) || !isfinite(length)) return false;
    *out = v3((float)(o[0] / length), (float)(o[1] / length), (float)(o[2] / length));
    return true;
}

void mesh_transform_rows(const mesh_transform *m, double out[3][4]) {
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++) out[i][j] = m->r[i][j] * m->scale[j];
        out[i][3] = m->translate[i];
    }
}
