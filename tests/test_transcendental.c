/* test_transcendental.c: cos_sin_turn, angle_of and pow_unit (shaders/common/transcendental.h)
 * against double precision over their whole domains: every turn k / 2^24 and a sweep of the other
 * floats of [0, 1); the power at a sweep of the floats of (0, 1] and every float near 1, times
 * exponents over the parser's whole range [0, FLT_MAX]; the exact values and the flushes to 0. The
 * bounds are a little above what was measured (stated in transcendental.h). */
#include <float.h>
#include <math.h>
#include <stdio.h>

#include "check.h"
#include "common/transcendental.h"

#define TWO_PI 6.283185307179586477
#define MAX_ABS_ERROR_TURN 1.0e-7
#define MAX_ABS_ERROR_ANGLE 3.0e-7
/* pow_unit's relative error where the result is above 1e-3, 1e-30 and the normal range */
#define MAX_REL_ERROR_POW_1E3 1.6e-6
#define MAX_REL_ERROR_POW_1E30 1.5e-5
#define MAX_REL_ERROR_POW_NORMAL 1.6e-5

static float float_of(uint32_t bits) { return float_from_bits(bits); }

/* The largest error of cos_sin_turn against double at u, into *worst (and where). */
static void turn_error(float u, double *worst, float *worst_u) {
    cos_sin r = cos_sin_turn(u);
    double a = TWO_PI * (double)u;
    double e = fmax(fabs(r.c - cos(a)), fabs(r.s - sin(a)));
    if (e > *worst) *worst = e, *worst_u = u;
}

static void test_turn(void) {
    double worst = 0.0;
    float worst_u = 0.0f;
    for (uint32_t k = 0; k < (1u << 24); k++)
        turn_error((float)k * (1.0f / 16777216.0f), &worst, &worst_u);
    printf("cos_sin_turn: max abs error %.3g at u = %.9g over k / 2^24\n", worst, worst_u);
    CHECK(worst <= MAX_ABS_ERROR_TURN, "cos_sin_turn: error %.3g at k / 2^24 = %.9g", worst,
          worst_u);
    worst = 0.0;
    for (uint32_t bits = 0x00800000u; bits < 0x3f800000u; bits += 97u)
        turn_error(float_of(bits), &worst, &worst_u);
    printf("cos_sin_turn: max abs error %.3g at u = %.9g over every 97th float\n", worst, worst_u);
    CHECK(worst <= MAX_ABS_ERROR_TURN, "cos_sin_turn: error %.3g at %.9g", worst, worst_u);
    /* exact at the axes; a denormal u is 0 */
    const float axes[] = {0.0f, 0.25f, 0.5f, 0.75f};
    const float want_c[] = {1.0f, 0.0f, -1.0f, 0.0f}, want_s[] = {0.0f, 1.0f, 0.0f, -1.0f};
    for (int k = 0; k < 4; k++) {
        cos_sin r = cos_sin_turn(axes[k]);
        CHECK(r.c == want_c[k] && r.s == want_s[k], "cos_sin_turn(%g) = (%g, %g)", axes[k], r.c,
              r.s);
    }
    cos_sin tiny = cos_sin_turn(float_of(0x007fffffu));
    CHECK(tiny.c == 1.0f && tiny.s == 0.0f, "cos_sin_turn of a denormal: (%g, %g)", tiny.c, tiny.s);
}

typedef struct pow_errors {
    double rel_1e3, rel_1e30, rel_normal, abs_below;
    float at_x, at_y;
    long bad; /* NaN, a denormal, or a value where 0 or 1 was due */
} pow_errors;

static void pow_error(float x, float y, pow_errors *e) {
    float r = pow_unit(x, y);
    double want = pow((double)x, (double)y);
    if (r != r || (r != 0.0f && r < FLT_MIN) || (y == 0.0f && r != 1.0f)) {
        if (e->bad++ < 5) printf("pow_unit(%.9g, %.9g) = %.9g\n", x, y, r);
        return;
    }
    if (want < 0x1p-125) { /* at the flush: 0 or the value itself */
        double a = fabs(r - want);
        if (a > e->abs_below) e->abs_below = a;
        return;
    }
    double rel = fabs(r - want) / want;
    if (want >= 1e-3 && rel > e->rel_1e3) e->rel_1e3 = rel, e->at_x = x, e->at_y = y;
    if (want >= 1e-30 && rel > e->rel_1e30) e->rel_1e30 = rel;
    if (rel > e->rel_normal) e->rel_normal = rel;
}

static void test_pow(void) {
    /* 0, tiny, then every quarter decade from 1e-12 to 1e38, and FLT_MAX; and 1 / (alpha + 1) of
     * phong_lobe_direction for the same alphas */
    float exponents[2 * 204 + 4];
    int count = 0;
    exponents[count++] = 0.0f;
    exponents[count++] = 1e-30f;
    exponents[count++] = FLT_MAX;
    exponents[count++] = 1.0f / (FLT_MAX + 1.0f);
    for (int k = -48; k <= 152; k++) {
        float alpha = (float)pow(10.0, k / 4.0);
        exponents[count++] = alpha;
        exponents[count++] = 1.0f / (alpha + 1.0f);
    }
    pow_errors e = {0};
    for (int j = 0; j < count; j++) {
        float y = exponents[j];
        for (uint32_t bits = 0x00800000u; bits <= 0x3f800000u; bits += 4093u)
            pow_error(float_of(bits), y, &e);
        for (uint32_t bits = 0x3f800000u - 20000u; bits <= 0x3f800000u; bits++)
            pow_error(float_of(bits), y, &e);
    }
    printf(
        "pow_unit: max rel error %.3g above 1e-3 (at %.9g^%.9g), %.3g above 1e-30, %.3g above "
        "2^-125; max abs error %.3g below\n",
        e.rel_1e3, e.at_x, e.at_y, e.rel_1e30, e.rel_normal, e.abs_below);
    CHECK(e.bad == 0, "pow_unit: %ld NaN, denormal or inexact 1 results", e.bad);
    CHECK(e.rel_1e3 <= MAX_REL_ERROR_POW_1E3, "pow_unit: rel error %.3g above 1e-3", e.rel_1e3);
    CHECK(e.rel_1e30 <= MAX_REL_ERROR_POW_1E30, "pow_unit: rel error %.3g above 1e-30", e.rel_1e30);
    CHECK(e.rel_normal <= MAX_REL_ERROR_POW_NORMAL, "pow_unit: rel error %.3g", e.rel_normal);
    CHECK(e.abs_below <= 0x1p-125, "pow_unit: abs error %.3g below 2^-125", e.abs_below);
    /* the exact values: 1 at x = 1, 0 at x = 0 (y = 0 too) and below the normal range */
    for (int j = 0; j < count; j++) {
        float y = exponents[j];
        CHECK(pow_unit(1.0f, y) == 1.0f, "pow_unit(1, %g) = %g", y, pow_unit(1.0f, y));
        CHECK(pow_unit(1.0000001f, y) == 1.0f, "pow_unit(1 + ulp, %g) is not 1", y);
        CHECK(pow_unit(0.0f, y) == 0.0f, "pow_unit(0, %g) = %g", y, pow_unit(0.0f, y));
        CHECK(pow_unit(float_of(0x007fffffu), y) == 0.0f, "pow_unit(denormal, %g) is not 0", y);
        CHECK(pow_unit(-0.5f, y) == 0.0f, "pow_unit(-0.5, %g) is not 0", y);
        CHECK(pow_unit(NAN, y) == 0.0f, "pow_unit(NaN, %g) is not 0", y);
    }
    CHECK(pow_unit(0.5f, 1.0f) == 0.5f && pow_unit(0.25f, 0.5f) == 0.5f,
          "pow_unit: 0.5^1 = %.9g, 0.25^0.5 = %.9g", pow_unit(0.5f, 1.0f), pow_unit(0.25f, 0.5f));
}

/* The largest error of angle_of against double at (x, y), into *worst (and where). */
static void angle_error(float y, float x, double *worst, float *at_y, float *at_x) {
    double e = fabs((double)angle_of(y, x) - atan2((double)y, (double)x));
    if (!(e <= *worst)) *worst = e, *at_y = y, *at_x = x;
}

/* angle_of depends on y / |x| and the sign of x: every 97th float as y at x = 1 and x = -1 covers
 * every ratio; a sweep of both coordinates adds the division's rounding; the axes are exact. */
static void test_angle(void) {
    double worst = 0.0;
    float at_y = 0.0f, at_x = 0.0f;
    for (uint32_t bits = 0; bits < 0x7f800000u; bits += 97u) {
        angle_error(float_of(bits), 1.0f, &worst, &at_y, &at_x);
        angle_error(float_of(bits), -1.0f, &worst, &at_y, &at_x);
    }
    for (uint32_t i = 0x00800000u; i < 0x7f800000u; i += 0x00800000u / 8u)
        for (uint32_t j = 0x00800000u; j < 0x7f800000u; j += 0x00800000u / 8u + 1u) {
            angle_error(float_of(i), float_of(j), &worst, &at_y, &at_x);
            angle_error(float_of(i), -float_of(j), &worst, &at_y, &at_x);
        }
    printf("angle_of: max abs error %.3g at (x, y) = (%.9g, %.9g)\n", worst, at_x, at_y);
    CHECK(worst <= MAX_ABS_ERROR_ANGLE, "angle_of: error %.3g at (%.9g, %.9g)", worst, at_x, at_y);
    CHECK(angle_of(0.0f, 1.0f) == 0.0f && angle_of(1.0f, 0.0f) == 1.57079637f &&
              angle_of(0.0f, -1.0f) == 3.14159274f,
          "angle_of at the axes: %.9g %.9g %.9g", angle_of(0.0f, 1.0f), angle_of(1.0f, 0.0f),
          angle_of(0.0f, -1.0f));
}

int main(void) {
    test_turn();
    test_angle();
    test_pow();
    return check_summary("test_transcendental");
}
