/* decimal.h: short decimals to doubles without strtod (Clinger's fast path), for the parser. */
#ifndef TRAZADOR_DECIMAL_H
#define TRAZADOR_DECIMAL_H

#include <float.h>
#include <stdbool.h>
#include <stdint.h>

/* The powers of ten a double holds exactly. */
#define DECIMAL_EXACT_POWERS 22
/* Significant digits that always fit in a double's 53-bit mantissa. */
#define DECIMAL_EXACT_DIGITS 15

/* The double nearest to s[0, n), a decimal of the scene syntax ([+-]digits[.digits]
 * [(e|E)[+-]digits], checked before), when its significant digits fit in DECIMAL_EXACT_DIGITS
 * and its power of ten in DECIMAL_EXACT_POWERS: both numbers are then exact doubles, so one IEEE
 * product or quotient rounds correctly, to strtod's very result. False for any other decimal. */
static inline bool decimal_fast(const char *s, int n, double *out) {
    static const double powers[DECIMAL_EXACT_POWERS + 1] = {
        1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
        1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    int i = 0, digits = 0, power = 0;
    bool negative = false;
    if (i < n && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
    uint64_t mantissa = 0;
    bool fraction = false;
    for (; i < n && ((s[i] >= '0' && s[i] <= '9') || (s[i] == '.' && !fraction)); i++) {
        if (s[i] == '.') {
            fraction = true;
            continue;
        }
        power -= fraction;
        if (mantissa == 0 && s[i] == '0') continue; /* a leading zero */
        if (++digits > DECIMAL_EXACT_DIGITS) return false;
        mantissa = mantissa * 10u + (uint64_t)(s[i] - '0');
    }
    if (i < n) { /* the exponent */
        bool down = false;
        int exponent = 0;
        if (++i < n && (s[i] == '+' || s[i] == '-')) down = s[i++] == '-';
        for (; i < n; i++) {
            exponent = exponent * 10 + (s[i] - '0');
            if (exponent > 2 * DECIMAL_EXACT_POWERS + 2 * DECIMAL_EXACT_DIGITS) return false;
        }
        power += down ? -exponent : exponent;
    }
    double value = (double)mantissa;
#if FLT_EVAL_METHOD != 0
    if (mantissa != 0) return false; /* wider intermediates would round twice (32-bit x87) */
#endif
    if (mantissa != 0) {
        if (power < -DECIMAL_EXACT_POWERS || power > DECIMAL_EXACT_POWERS) return false;
        value = power >= 0 ? value * powers[power] : value / powers[-power];
    }
    *out = negative ? -value : value;
    return true;
}

#endif
