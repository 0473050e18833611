/* chi_square.h: Pearson's chi-square of binned samples against the counts a pdf expects, as a
 * z score (Wilson and Hilferty's cube root), for the sampling tests. Bins expecting fewer than
 * CHI_SQUARE_MIN_EXPECTED join a pool with the samples that fell in no bin, which the mass the
 * kept bins leave expects. */
#ifndef TRAZADOR_CHI_SQUARE_H
#define TRAZADOR_CHI_SQUARE_H

#include <math.h>

#define CHI_SQUARE_MIN_EXPECTED 5.0

typedef struct chi_square {
    double chi2, pool_o, pool_e;
    int dof;
} chi_square;

/* A test of `samples` draws, `outside` of them in no bin. */
static inline chi_square chi_square_start(double samples, double outside) {
    return (chi_square){0.0, outside, samples, 0};
}

/* One bin: its observed count against the expected one (sparse ones pooled). */
static inline void chi_square_bin(chi_square *c, double observed, double expected) {
    c->pool_e -= expected;
    if (expected < CHI_SQUARE_MIN_EXPECTED) {
        c->pool_o += observed;
        c->pool_e += expected;
        return;
    }
    double diff = observed - expected;
    c->chi2 += diff * diff / expected;
    c->dof++;
}

/* The z score of chi2 over k degrees of freedom. */
static inline double chi_square_z_of(double chi2, double k) {
    return (cbrt(chi2 / k) - (1.0 - 2.0 / (9.0 * k))) / sqrt(2.0 / (9.0 * k));
}

/* The z score of the bins and the pool (the pool's bin is the one constraint). */
static inline double chi_square_result(chi_square c) {
    double pool_e = c.pool_e > CHI_SQUARE_MIN_EXPECTED ? c.pool_e : CHI_SQUARE_MIN_EXPECTED;
    double chi2 = c.chi2 + (c.pool_o - pool_e) * (c.pool_o - pool_e) / pool_e;
    return chi_square_z_of(chi2, c.dof > 0 ? c.dof : 1);
}

#endif
