/* test_spherical_triangle.c: light sampling of a triangle by solid angle
 * (shaders/common/spherical_triangle.h): the float solid angle against Van Oosterom and
 * Strackee's formula in double; the directions' chi-square over the spherical triangle's parts
 * (the planar triangle cut into n^2 congruent sub-triangles, each expecting its own solid angle's
 * share), for a triangle seen face on, seen nearly edge on, seen from close by and a small one;
 * the directions meet the triangle under the watertight test (all but a rounding's share) and
 * end on it (triangle_light_distance); which points take the solid angle at every scale; and the
 * test's power: a wrong warp is rejected. */
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

#include "check.h"
#include "common/ray.h"
#include "common/rng.h"
#include "common/spherical_triangle.h"

#define PI 3.14159265358979323846
#define SAMPLES 400000
#define CUTS 8 /* n: n^2 sub-triangles */
#define MIN_EXPECTED 5.0

typedef struct dvec {
    double x, y, z;
} dvec;

static dvec dv(vec3 v) { return (dvec){v.x, v.y, v.z}; }
static dvec dsub(dvec a, dvec b) { return (dvec){a.x - b.x, a.y - b.y, a.z - b.z}; }
static dvec dadd(dvec a, dvec b) { return (dvec){a.x + b.x, a.y + b.y, a.z + b.z}; }
static dvec dscale(dvec a, double s) { return (dvec){a.x * s, a.y * s, a.z * s}; }
static double ddot(dvec a, dvec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static dvec dcross(dvec a, dvec b) {
    return (dvec){a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

/* The solid angle of the triangle a, b, c seen from the origin, in double. */
static double solid_angle(dvec a, dvec b, dvec c) {
    double la = sqrt(ddot(a, a)), lb = sqrt(ddot(b, b)), lc = sqrt(ddot(c, c));
    double den = la * lb * lc + ddot(a, b) * lc + ddot(a, c) * lb + ddot(b, c) * la;
    return 2.0 * atan2(fabs(ddot(a, dcross(b, c))), den);
}

/* A triangle light and the point it is seen from. */
typedef struct view {
    const char *name;
    vec3 a, b, c, o;
} view;

/* Point (u, v) of the triangle in its own coordinates, relative to the origin o. */
static dvec point_at(const view *w, double u, double v) {
    dvec a = dsub(dv(w->a), dv(w->o)), b = dsub(dv(w->b), dv(w->o)), c = dsub(dv(w->c), dv(w->o));
    return dadd(a, dadd(dscale(dsub(b, a), u), dscale(dsub(c, a), v)));
}

/* The chi-square z score (Wilson-Hilferty) of spherical_triangle_direction's samples for w, or
 * with wrong_warp ub squared first; *misses counts the directions that the watertight test finds
 * off the triangle, *lost those that triangle_light_distance does not end on its plane. */
static double chi_square_z(const view *w, bool wrong_warp, int *misses, int *lost) {
    static double observed[CUTS][CUTS][2];
    memset(observed, 0, sizeof observed);
    spherical_triangle st = spherical_triangle_of(w->a, w->b, w->c, w->o);
    dvec a = point_at(w, 0, 0), ab = dsub(point_at(w, 1, 0), a), ac = dsub(point_at(w, 0, 1), a);
    dvec normal = dcross(ab, ac);
    uint32_t rng = rng_seed(5, 0, 0);
    *misses = *lost = 0;
    for (int k = 0; k < SAMPLES; k++) {
        float ua = rng_next(&rng), ub = rng_next(&rng);
        if (wrong_warp) ub *= ub;
        vec3 d = spherical_triangle_direction(st, ua, ub);
        float t = triangle_distance(w->a, w->b, w->c, w->o, d, 0.0f, 0);
        *lost += !(triangle_light_distance(w->a, w->b, w->c, w->o, d) < INFINITY);
        *misses += !(t < INFINITY);
        /* where the direction meets the plane, in the triangle's coordinates (u, v) */
        dvec p = dscale(dv(d), ddot(a, normal) / ddot(dv(d), normal));
        dvec rel = dsub(p, a), m = dcross(rel, ac), n = dcross(ab, rel);
        double area2 = ddot(normal, normal);
        double x = ddot(m, normal) / area2 * CUTS, y = ddot(n, normal) / area2 * CUTS;
        int i = (int)floor(x), j = (int)floor(y);
        i = i < 0 ? 0 : i >= CUTS ? CUTS - 1 : i;
        j = j < 0 ? 0 : j >= CUTS ? CUTS - 1 : j;
        if (i + j >= CUTS) i = CUTS - 1 - j; /* rounding past the far edge */
        int down = (x - i) + (y - j) >= 1.0 && i + j < CUTS - 1;
        observed[i][j][down]++;
    }
    double omega = solid_angle(point_at(w, 0, 0), point_at(w, 1, 0), point_at(w, 0, 1));
    double chi2 = 0.0, pooled_observed = 0.0, pooled_expected = 0.0;
    int cells = 0;
    for (int i = 0; i < CUTS; i++) {
        for (int j = 0; i + j < CUTS; j++) {
            for (int down = 0; down < 2; down++) {
                if (down && i + j == CUTS - 1) continue; /* the far row has up cells only */
                double u0 = (double)i / CUTS, v0 = (double)j / CUTS, s = 1.0 / CUTS;
                dvec p = down ? point_at(w, u0 + s, v0) : point_at(w, u0, v0);
                dvec q = down ? point_at(w, u0 + s, v0 + s) : point_at(w, u0 + s, v0);
                dvec r = point_at(w, u0, v0 + s);
                double expected = SAMPLES * solid_angle(p, q, r) / omega;
                if (expected < MIN_EXPECTED) {
                    pooled_observed += observed[i][j][down];
                    pooled_expected += expected;
                    continue;
                }
                double diff = observed[i][j][down] - expected;
                chi2 += diff * diff / expected;
                cells++;
            }
        }
    }
    if (pooled_expected > 0.0) {
        double diff = pooled_observed - pooled_expected;
        chi2 += diff * diff / pooled_expected;
        cells++;
    }
    double k = cells - 1;
    return (cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / sqrt(2.0 / (9.0 * k));
}

static const view views[] = {
    {"face on", {-1.0f, -1.0f, 3.0f}, {2.0f, -0.5f, 3.5f}, {0.0f, 2.0f, 2.5f}, {0, 0, 0}},
    {"nearly edge on", {-1.0f, 0.0f, 1.0f}, {1.0f, 0.0f, 1.0f}, {0.0f, 0.0f, 3.0f}, {0, 0.05f, 0}},
    {"from close by", {-3.0f, -3.0f, 0.5f}, {3.0f, -3.0f, 0.5f}, {0.0f, 3.0f, 0.5f}, {0, 0, 0}},
    {"small", {0.0f, 0.0f, 10.0f}, {0.3f, 0.0f, 10.0f}, {0.0f, 0.25f, 10.2f}, {0.1f, 0, 0}},
};

/* The float solid angle within 1e-5 (relative) of double's, for views and for a sweep of
 * distances down to the smallest sampled by solid angle; the octant is pi / 2. */
static void test_solid_angle(void) {
    for (size_t k = 0; k < sizeof views / sizeof views[0]; k++) {
        const view *w = &views[k];
        double want = solid_angle(point_at(w, 0, 0), point_at(w, 1, 0), point_at(w, 0, 1));
        float got = spherical_triangle_of(w->a, w->b, w->c, w->o).solid_angle;
        printf("%s: solid angle %.6g sr (float %.6g)\n", w->name, want, (double)got);
        CHECK(fabs(got - want) <= 1e-5 * want, "%s: solid angle %.9g, want %.9g", w->name,
              (double)got, want);
        CHECK(by_solid_angle(got), "%s: not sampled by solid angle (%g sr)", w->name, (double)got);
    }
    double worst = 0.0;
    for (float z = 1.0f; z < 100.0f; z *= 1.1f) {
        vec3 a = v3(-0.5f, -0.4f, z), b = v3(0.6f, -0.3f, z + 0.2f), c = v3(0.1f, 0.7f, z);
        double want = solid_angle(dv(a), dv(b), dv(c));
        float got = spherical_triangle_of(a, b, c, v3(0, 0, 0)).solid_angle;
        if (by_solid_angle(got)) worst = fmax(worst, fabs(got - want) / want);
    }
    printf("solid angle: max relative error %.3g over distances 1 to 100\n", worst);
    CHECK(worst <= 1e-4, "solid angle: relative error %.3g", worst);
    float octant =
        spherical_triangle_of(v3(1, 0, 0), v3(0, 1, 0), v3(0, 0, 1), v3(0, 0, 0)).solid_angle;
    CHECK(fabsf(octant - (float)(PI / 2)) <= 4e-7f, "octant: %.9g sr", (double)octant);
    CHECK(!by_solid_angle(NAN) && !by_solid_angle(1e-5f) && !by_solid_angle(6.25f),
          "by_solid_angle takes NaN, tiny or whole-hemisphere angles");
}

static void test_directions(void) {
    for (size_t k = 0; k < sizeof views / sizeof views[0]; k++) {
        int misses = 0, lost = 0;
        double z = chi_square_z(&views[k], false, &misses, &lost);
        printf("%s: chi-square z score %.2f, %d of %d directions off the triangle, %d lost\n",
               views[k].name, z, misses, SAMPLES, lost);
        CHECK(z < 4.0, "%s: chi-square z score %.2f", views[k].name, z);
        CHECK(misses <= SAMPLES / 2000, "%s: %d directions miss the triangle", views[k].name,
              misses);
        CHECK(lost == 0, "%s: %d directions end nowhere", views[k].name, lost);
    }
    int misses = 0, lost = 0;
    double wrong = chi_square_z(&views[0], true, &misses, &lost);
    CHECK(wrong > 10.0, "power: ub squared gives z score %.2f", wrong);
}

/* Which points take the solid angle does not depend on the scene's scale: the same answers with
 * every coordinate times 2^30 or 2^-30 (exact; cross products near the parser's bounds). */
static void test_near_plane(void) {
    vec3 a = v3(-0.5f, 0.0f, -0.5f), b = v3(0.5f, 0.0f, -0.5f), c = v3(0.0f, 0.0f, 0.5f);
    int near = 0, same = 0, count = 0;
    for (float y = -1.0f; y <= 1.0f; y += 0.0625f) {
        for (float x = -2.0f; x <= 2.0f; x += 0.25f) {
            vec3 o = v3(x, y, 0.25f);
            int at_one = near_triangle_plane(a, b, c, o);
            float big = 0x1p30f, small = 0x1p-30f;
            int at_big = near_triangle_plane(v3_scale(a, big), v3_scale(b, big), v3_scale(c, big),
                                             v3_scale(o, big));
            int at_small = near_triangle_plane(v3_scale(a, small), v3_scale(b, small),
                                               v3_scale(c, small), v3_scale(o, small));
            near += at_one, same += at_one == at_big && at_one == at_small, count++;
        }
    }
    printf("near the plane: %d of %d points, %d the same at every scale\n", near, count, same);
    CHECK(same == count && near > 0 && near < count, "near_triangle_plane: %d of %d agree, %d near",
          same, count, near);
}

int main(void) {
    test_solid_angle();
    test_near_plane();
    test_directions();
    return check_summary("test_spherical_triangle");
}
