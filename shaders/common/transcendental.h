/* transcendental.h: the cosine and sine of a turn (the azimuths of every sampled direction), the
 * angle of a point (a triangle light's solid angle) and the power of Phong's lobe, one text for C
 * and GLSL (dialect.h) in operations that round alike in both: +, -, *, /, conversions, bit casts,
 * comparisons and selects, every step precise. The C library's and the driver's cos, sin and pow
 * differ by ulps, and a path then takes another turn; these give every back end the same bits.
 * Exact reductions (by octant; by exponent and mantissa), then polynomials fitted by Chebyshev
 * (mpmath.chebyfit) with float coefficients. Below the normal range a Vulkan driver may flush to 0
 * (SPIR-V leaves it to the driver) and C does not, so inputs and results there are flushed to 0 on
 * both sides. Measured against double precision over the whole domains
 * (tests/test_transcendental.c): cos and sin within 8.9e-8 (absolute); pow_unit's relative error at
 * most 1.4e-6 where the result is above 1e-3, 1.3e-5 above 1e-30 and 1.4e-5 down to the normal
 * range: it grows with |log2 of the result|, as the float y log2(x) carries it. angle_of
 * within 2.7e-7 (absolute) over every ratio and sign. */
#ifndef TRAZADOR_COMMON_TRANSCENDENTAL_H
#define TRAZADOR_COMMON_TRANSCENDENTAL_H

#include "dialect.h"

/* The smallest normal float. */
#define TZ_FLT_MIN 1.17549435e-38f

/* The angle of the point (x, y) from the +x axis for y >= 0, in [0, pi] (atan2(y, x) there);
 * NaN for (0, 0). The ratio t = y / |x| is reduced to |t| <= tan(pi / 8) around 0, pi / 4 or
 * pi / 2, and atan there is Cephes' atanf polynomial (S. Moshier). */
TZ_FN float angle_of(float y, float x) {
    TZ_PRECISE float t = y / TZ_ABS(x);
    TZ_BOOL big = t > 2.41421356f, mid = t > 0.414213562f;
    TZ_PRECISE float r = big ? -1.0f / t : mid ? (t - 1.0f) / (t + 1.0f) : t;
    float base = big ? 1.57079637f : mid ? 0.785398185f : 0.0f;
    TZ_PRECISE float z = r * r;
    TZ_PRECISE float p =
        ((((0.0805374449538f * z - 0.138776856032f) * z + 0.199777106478f) * z - 0.333329491539f) *
             z * r +
         r);
    TZ_PRECISE float a = base + p;
    TZ_PRECISE float flipped = 3.14159274f - a;
    return x < 0.0f ? flipped : a;
}

/* A cosine and a sine, of one angle. */
TZ_STRUCT(cos_sin) {
    float c;
    float s;
}
TZ_STRUCT_END(cos_sin)

/* cos and sin of 2 pi u for u in [0, 1) (u below the normal range counts as 0). */
TZ_FN cos_sin cos_sin_turn(float u) {
    /* 2 pi u = (pi / 4) (q + f): the octant q and the fraction f are exact, as is the angle's
     * distance to the octant's nearer axis, r pi / 4. */
    TZ_PRECISE float t = u * 8.0f;
    int q = TZ_INT(t);
    TZ_PRECISE float f = t - TZ_FLOAT(q);
    TZ_PRECISE float r = (q & 1) != 0 ? 1.0f - f : f;
    TZ_PRECISE float z = r * r;
    /* sin(r pi / 4) and cos(r pi / 4) for r in [0, 1]: odd and even, 1 and 0 exact at r = 0 */
    TZ_PRECISE float s =
        r * (0.785398185f + z * (-0.0807454363f + z * (0.00249000685f + z * -3.59542901e-05f)));
    /* where a driver flushes a denormal u, s is 0: so here, rather than u flushed before (gcc
     * then compiled a path of its own for u = 0, and the lane loops did not vectorize) */
    s = u < TZ_FLT_MIN ? 0.0f : s;
    TZ_PRECISE float c =
        1.0f +
        z * (-0.308425128f + z * (0.0158543382f + z * (-0.000325961388f + z * 3.54195276e-06f)));
    TZ_BOOL swap = ((q + 1) & 2) != 0;
    TZ_PRECISE float cos_r = swap ? s : c;
    TZ_PRECISE float sin_r = swap ? c : s;
    cos_sin a;
    a.c = ((q + 2) & 4) != 0 ? -cos_r : cos_r;
    a.s = (q & 4) != 0 ? -sin_r : sin_r;
    return a;
}

/* log2 of x for x in [TZ_FLT_MIN, 1]; exactly 0 at 1. */
TZ_FN float log2_normal(float x) {
    /* x = 2^e m with m in [sqrt(1/2), sqrt(2)), both exact; log2(m) = 2 atanh(s) / ln 2 with
     * s = (m - 1) / (m + 1), |s| <= 0.1716 */
    TZ_UINT bits = uint_bits(x);
    TZ_PRECISE float m = float_from_bits((bits & 0x007fffffu) | 0x3f800000u);
    TZ_PRECISE float e = TZ_FLOAT(bits >> 23u) - 127.0f;
    TZ_BOOL high = m >= 1.41421354f;
    m = high ? 0.5f * m : m;
    e = high ? e + 1.0f : e;
    TZ_PRECISE float s = (m - 1.0f) / (m + 1.0f);
    TZ_PRECISE float z = s * s;
    TZ_PRECISE float l =
        e + s * (2.88539004f + z * (0.961798847f + z * (0.576715171f + z * 0.431717694f)));
    return l;
}

/* 2^t for t <= 0 (minus infinity too), 0 where it is below the normal range; exactly 1 at 0. */
TZ_FN float exp2_nonpositive(float t) {
    /* t = n + f, n = t rounded toward 0 and f in (-1, 0], both exact; 2^n from its bits (0 for
     * n = -127, whose 2^n is not normal) */
    TZ_PRECISE float tc = TZ_MAX(t, -127.0f);
    int n = TZ_INT(tc);
    TZ_PRECISE float f = tc - TZ_FLOAT(n);
    TZ_PRECISE float p =
        1.0f + f * (0.693147182f +
                    f * (0.24022609f +
                         f * (0.0554992296f +
                              f * (0.00959703512f + f * (0.00129163684f + f * 0.000114919952f)))));
    float scale = float_from_bits(TZ_UINT_OF(n + 127) << 23u);
    TZ_PRECISE float r = p * scale;
    return r < TZ_FLT_MIN ? 0.0f : r;
}

/* x^y for x in [0, 1] and y >= 0 (Phong's lobe and its sample): exactly 1 for x = 1 and for
 * y = 0 (x > 0); 0 for x below the normal range (0 and NaN too), whatever y, and for results
 * below it; x above 1 (a cosine rounded up) counts as 1. */
TZ_FN float pow_unit(float x, float y) {
    TZ_BOOL normal = x >= TZ_FLT_MIN;
    TZ_PRECISE float xc = normal ? TZ_MIN(x, 1.0f) : 1.0f;
    TZ_PRECISE float t = y * log2_normal(xc);
    TZ_PRECISE float r = exp2_nonpositive(t);
    return normal ? r : 0.0f;
}

#endif
