/* film_sum.h: compensated (Kahan) summation of a pixel's samples: the very operations of
 * film_sum_add() and of the last pass in shaders/trace.comp, so that both back ends sum alike,
 * operation for operation. A plain float sum drifts as it grows (1,048,576 samples of 0.9 summed
 * to a mean of 0.8913); this one stays within rounding of the true mean at any sample count. */
#ifndef TRAZADOR_FILM_SUM_H
#define TRAZADOR_FILM_SUM_H

#include <math.h>

/* Adds value to the sum whose lost low-order part is *comp; never fails. Past the float range
 * the compensation stops (it would turn an infinite sum into NaN), so such a sum stays infinite.
 */
static inline void film_sum_add(float *sum, float *comp, float value) {
    float y = value - *comp;
    float t = *sum + y;
    *comp = isfinite(t) ? (t - *sum) - y : 0.0f;
    *sum = t;
}

/* The value of a compensated sum; never fails. */
static inline float film_sum_value(float sum, float comp) { return sum - comp; }

#endif
