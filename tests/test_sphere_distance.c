/* test_sphere_distance.c: sphere_distance (shaders/common/ray.h) against the exact root in long
 * double from the same float inputs: random spheres and rays, rays aimed at a sphere's
 * silhouette, and rooms of radius-1e5 walls seen from inside (origins at least one unit from
 * every wall). The bounds are a little above what was measured; a hit where the exact ray misses
 * (or the reverse) is allowed only for a few tangent rays in a million. */
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "check.h"
#include "common/ray.h"

#define RAYS 1000000
#define MAX_REL_ERROR_RANDOM 1.0e-4
#define MAX_REL_ERROR_SILHOUETTE 5.0e-5
#define MAX_REL_ERROR_WALLS 1.0e-2
#define MEAN_REL_ERROR_WALLS 2.0e-4
#define MAX_DISAGREEMENTS 10
#define TMIN 1e-4f

/* A float in [0, 1) from a 64-bit LCG (the same cases on every machine). */
static uint64_t lcg_state = 7u;
static float uniform(void) {
    lcg_state = lcg_state * 6364136223846793005u + 1442695040888963407u;
    return (float)(lcg_state >> 40) * (1.0f / 16777216.0f);
}

/* The root of |o + t d - c| = r that sphere_distance means (nearest above TMIN), exactly from the
 * float inputs: infinity for a miss. */
static long double exact_distance(vec3 c, float r, vec3 o, vec3 d) {
    long double ox = (long double)o.x - c.x, oy = (long double)o.y - c.y,
                oz = (long double)o.z - c.z;
    long double dd = (long double)d.x * d.x + (long double)d.y * d.y + (long double)d.z * d.z;
    long double b = (ox * d.x + oy * d.y + oz * d.z) / dd;
    long double fx = ox - b * d.x, fy = oy - b * d.y, fz = oz - b * d.z;
    long double disc = (long double)r * r - (fx * fx + fy * fy + fz * fz);
    if (disc < 0.0L) return INFINITY;
    long double s = sqrtl(disc / dd);
    if (-b - s > TMIN) return -b - s;
    return -b + s > TMIN ? -b + s : INFINITY;
}

typedef struct errors {
    double max, sum;
    int hits, disagreements;
} errors;

static void measure(errors *e, vec3 c, float r, vec3 o, vec3 d) {
    float t = sphere_distance(c.x, c.y, c.z, r, o, d, TMIN, false);
    long double exact = exact_distance(c, r, o, d);
    if (isinf(t) || isinf((double)exact)) {
        e->disagreements += isinf(t) != isinf((double)exact);
        return;
    }
    double err = (double)(fabsl(t - exact) / fmaxl(fabsl(exact), 1.0L));
    e->max = fmax(e->max, err), e->sum += err, e->hits++;
}

static vec3 unit(vec3 v) { return v3_normalize(v); }

static vec3 random_point(float lo, float hi) {
    return v3(lo + uniform() * (hi - lo), lo + uniform() * (hi - lo), lo + uniform() * (hi - lo));
}

static void report(const char *name, const errors *e, double max_bound) {
    printf("%s: %d hits, max rel error %.3g, mean %.3g, %d disagreements\n", name, e->hits, e->max,
           e->hits ? e->sum / e->hits : 0.0, e->disagreements);
    CHECK(e->hits > RAYS / 20, "%s: only %d hits", name, e->hits);
    CHECK(e->max <= max_bound, "%s: max rel error %.3g above %.3g", name, e->max, max_bound);
    CHECK(e->disagreements <= MAX_DISAGREEMENTS, "%s: %d hits or misses differ", name,
          e->disagreements);
}

/* Spheres of radius 0.1 to 100 in a 20-unit box, origins in a 100-unit box, any direction. */
static void test_random(void) {
    errors e = {0};
    for (int k = 0; k < RAYS; k++) {
        float r = powf(10.0f, uniform() * 3.0f - 1.0f);
        vec3 c = random_point(-10.0f, 10.0f), o = random_point(-50.0f, 50.0f);
        vec3 d = random_point(-1.0f, 1.0f);
        if (v3_length(d) > 0.1f) measure(&e, c, r, o, unit(d));
    }
    report("random", &e, MAX_REL_ERROR_RANDOM);
}

/* Rays aimed within the bounding cube of a unit sphere: many graze it. */
static void test_silhouette(void) {
    errors e = {0};
    vec3 c = v3(50.0f, 50.0f, 50.0f);
    for (int k = 0; k < RAYS; k++) {
        vec3 o = random_point(0.0f, 100.0f), aim = v3_add(c, random_point(-1.0f, 1.0f));
        measure(&e, c, 1.0f, o, unit(v3_sub(aim, o)));
    }
    report("silhouette", &e, MAX_REL_ERROR_SILHOUETTE);
}

/* A 100-unit room whose six walls are spheres of radius 1e5, as smallpt's: rays from inside, at
 * least one unit from every wall, toward one wall each. */
static void test_walls(void) {
    errors e = {0};
    const float r = 1e5f;
    for (int k = 0; k < RAYS; k++) {
        int axis = k % 3, side = (k / 3) % 2;
        float centre[3] = {50.0f, 50.0f, 50.0f};
        centre[axis] = side ? 50.0f + (r + 50.0f) : 50.0f - (r + 50.0f);
        vec3 o = random_point(1.0f, 99.0f);
        vec3 d = random_point(-1.0f, 1.0f);
        if (v3_length(d) > 0.1f) measure(&e, v3(centre[0], centre[1], centre[2]), r, o, unit(d));
    }
    report("walls", &e, MAX_REL_ERROR_WALLS);
    CHECK(e.sum / e.hits <= MEAN_REL_ERROR_WALLS, "walls: mean rel error %.3g", e.sum / e.hits);
}

int main(void) {
    CHECK_CASE(test_random);
    CHECK_CASE(test_silhouette);
    CHECK_CASE(test_walls);
    return check_summary("test_sphere_distance");
}
