/* test_plane_hit.c: how far off its face's plane a hit is placed, in long double from the same
 * float inputs, in ray offsets (TZ_EPS times the larger of 1 and the ray origin's and the point's
 * largest |coordinate|, what a ray leaving the point clears): plane_hit (shaders/common/ray.h)
 * against the watertight test's own o + t d, over random faces of 0.01 to 1e6 units, 0.01 to 1e5
 * from the origin, half of them square to an axis, hit by rays aimed inside them from 0.001 to
 * 1000 away. Off by a ray offset or more, a ray leaving the hit may start behind a face sharing
 * its edge and meet it (a huge floor quad's dark seam). The bounds are a little above what was
 * measured. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "check.h"
#include "common/ray.h"

#define RAYS 1000000
/* The worst measured: 0.0023 on faces square to an axis (the test's own t: 5.2), 0.077 on others
 * (the test's own t: 0.05-0.16). */
#define MAX_OFFSETS_SQUARE 0.01
#define MAX_OFFSETS_GENERAL 0.25

/* A double in [0, 1) from a 64-bit LCG (the same cases on every machine). */
static uint64_t lcg_state = 11u;
static double uniform(void) {
    lcg_state = lcg_state * 6364136223846793005u + 1442695040888963407u;
    return (double)(lcg_state >> 11) * (1.0 / 9007199254740992.0);
}

/* The distance of p from the plane through the float corners a, b, c, in long double. */
static long double off_plane(vec3 a, vec3 b, vec3 c, vec3 p) {
    long double e1[3] = {(long double)b.x - a.x, (long double)b.y - a.y, (long double)b.z - a.z};
    long double e2[3] = {(long double)c.x - a.x, (long double)c.y - a.y, (long double)c.z - a.z};
    long double n[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                        e1[0] * e2[1] - e1[1] * e2[0]};
    long double length = sqrtl(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    return fabsl(n[0] * ((long double)p.x - a.x) + n[1] * ((long double)p.y - a.y) +
                 n[2] * ((long double)p.z - a.z)) /
           length;
}

/* A random face (square to an axis when square) and a ray aimed at a point inside it; false for
 * a face too thin to have a normal. */
static bool random_case(bool square, vec3 v[3], vec3 *o, vec3 *d) {
    double size = pow(10.0, -2.0 + 8.0 * uniform()), away = pow(10.0, -2.0 + 7.0 * uniform());
    double centre[3] = {(uniform() - 0.5) * away, (uniform() - 0.5) * away,
                        (uniform() - 0.5) * away};
    int axis = (int)(uniform() * 3.0);
    for (int k = 0; k < 3; k++) {
        double p[3];
        for (int a = 0; a < 3; a++) p[a] = centre[a] + (uniform() - 0.5) * size;
        if (square) p[axis] = centre[axis];
        v[k] = v3((float)p[0], (float)p[1], (float)p[2]);
    }
    vec3 n = v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0]));
    if (v3_is_zero(n)) return false;
    double w0 = uniform(), w1 = uniform() * (1.0 - w0), w2 = 1.0 - w0 - w1;
    vec3 target = v3((float)(w0 * v[0].x + w1 * v[1].x + w2 * v[2].x),
                     (float)(w0 * v[0].y + w1 * v[1].y + w2 * v[2].y),
                     (float)(w0 * v[0].z + w1 * v[1].z + w2 * v[2].z));
    double distance = pow(10.0, -3.0 + 6.0 * uniform());
    vec3 way = v3_normalize(
        v3((float)(uniform() - 0.5), (float)(uniform() - 0.5), (float)(uniform() - 0.5)));
    *o = v3_sub(target, v3_scale(way, (float)distance));
    *d = v3_normalize(v3_sub(target, *o));
    return true;
}

static void test_plane_hit(void) {
    double worst_plane[2] = {0.0, 0.0}, worst_test[2] = {0.0, 0.0};
    long hits[2] = {0, 0};
    for (int r = 0; r < RAYS; r++) {
        bool square = r % 2 == 1;
        vec3 v[3], o, d;
        if (!random_case(square, v, &o, &d)) continue;
        float t = triangle_distance(v[0], v[1], v[2], o, d, ray_eps(o), 0);
        if (!(t < INFINITY)) continue; /* aimed at an edge and missed by rounding */
        vec3 at = v3_add(o, v3_scale(d, t));
        vec3 n = v3_normalize(v3_cross(v3_sub(v[1], v[0]), v3_sub(v[2], v[0])));
        vec3 placed = plane_hit(v[0], n, o, d, at);
        double offset = TZ_EPS * fmax(fmax(v3_max_abs(o), v3_max_abs(placed)), 1.0);
        double by_plane = (double)off_plane(v[0], v[1], v[2], placed) / offset;
        double by_test = (double)off_plane(v[0], v[1], v[2], at) / offset;
        worst_plane[square] = fmax(worst_plane[square], by_plane);
        worst_test[square] = fmax(worst_test[square], by_test);
        hits[square]++;
    }
    printf(
        "faces square to an axis: %ld hits, worst %.3g ray offsets off the plane (the test's "
        "own t: %.3g)\n",
        hits[1], worst_plane[1], worst_test[1]);
    printf("other faces: %ld hits, worst %.3g (the test's own t: %.3g)\n", hits[0], worst_plane[0],
           worst_test[0]);
    CHECK(hits[0] > RAYS / 4 && hits[1] > RAYS / 4, "too few hits: %ld, %ld", hits[0], hits[1]);
    CHECK(worst_plane[1] < MAX_OFFSETS_SQUARE, "square faces: a hit %.3g ray offsets off its plane",
          worst_plane[1]);
    CHECK(worst_plane[0] < MAX_OFFSETS_GENERAL, "other faces: a hit %.3g ray offsets off its plane",
          worst_plane[0]);
}

int main(void) {
    CHECK_CASE(test_plane_hit);
    return check_summary("test_plane_hit");
}
