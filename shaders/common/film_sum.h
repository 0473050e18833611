/* film_sum.h: compensated (Kahan) summation of a pixel's samples, one text for C and GLSL
 * (dialect.h), so that both back ends sum alike, operation for operation. A plain float sum
 * drifts as it grows; this one stays within rounding of the true mean at any sample count
 * (docs/DESIGN.md section 3.1). */
#ifndef TRAZADOR_COMMON_FILM_SUM_H
#define TRAZADOR_COMMON_FILM_SUM_H

#include "dialect.h"

/* isfinite() on the bits: immune to a compiler that assumes no NaN or infinity. */
TZ_FN TZ_BOOL finite_bits(float x) {
    return (uint_bits(x) & 0x7f800000u) != 0x7f800000u ? TZ_TRUE : TZ_FALSE;
}

/* Whether every component of a sample is finite: the others are dropped and counted. */
TZ_FN TZ_BOOL sample_finite(vec3 v) {
    return finite_bits(v.x) TZ_AND finite_bits(v.y) TZ_AND finite_bits(v.z);
}

/* The lost low-order part of a component whose new sum is t, or 0 past the float range (the
 * compensation would turn an infinite sum into NaN, so such a sum stays infinite). */
TZ_FN float film_sum_lost(float t, float lost) { return finite_bits(t) ? lost : 0.0f; }

/* Adds value to the sums whose lost low-order parts are comp; never fails. */
TZ_FN void film_sum_add(TZ_INOUT(vec3) sum, TZ_INOUT(vec3) comp, vec3 value) {
    TZ_PRECISE vec3 y = v3_sub(value, TZ_DEREF(comp));
    TZ_PRECISE vec3 t = v3_add(TZ_DEREF(sum), y);
    TZ_PRECISE vec3 lost = v3_sub(v3_sub(t, TZ_DEREF(sum)), y);
    TZ_DEREF(comp) =
        v3(film_sum_lost(t.x, lost.x), film_sum_lost(t.y, lost.y), film_sum_lost(t.z, lost.z));
    TZ_DEREF(sum) = t;
}

/* The value of a compensated sum; never fails. */
TZ_FN vec3 film_sum_value(vec3 sum, vec3 comp) {
    TZ_PRECISE vec3 v = v3_sub(sum, comp);
    return v;
}

#endif
