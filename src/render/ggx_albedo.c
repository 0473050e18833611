/* ggx_albedo.c: the directional albedo E(mu, roughness) of a white GGX conductor with the
 * height-correlated Smith term, and its cosine-weighted mean E_avg, for Kulla and Conty's
 * multiple-scattering lobe (shaders/common/microfacet.h). E is the mean of G2 / G1 over the
 * visible normals, integrated by the midpoint rule over the unit square that the spherical-cap
 * sampling (Dupuy and Benyoub 2023) maps onto them: no random numbers, the same bits every run. */
#include "render/ggx_albedo.h"

#include <math.h>
#include <pthread.h>

#include "shared_layout.h"

/* Midpoints of the quadrature: cap heights, and azimuths over the half of the circle that
 * mirrors the other (the way back lies in the xz plane). */
#define HEIGHTS 512
#define AZIMUTHS 32
#define PI 3.14159265358979323846

float ggx_albedo_words[TZ_GGX_TABLE_WORDS];

/* Smith's Lambda of direction (x, z) (y 0 or folded into x) for GGX width alpha. */
static double smith_lambda(double x2y2, double z, double alpha) {
    return 0.5 * (sqrt(alpha * alpha * x2y2 + z * z) / fabs(z) - 1.0);
}

/* E at cosine mu for width alpha: the mean of G2 / G1 = (1 + Lo) / (1 + Lo + Li) over the
 * visible normals, 0 where the reflection goes below the surface. */
static double albedo_at(double mu, double alpha) {
    double ox = sqrt(1.0 - mu * mu), oz = mu;
    double lo = smith_lambda(ox * ox, oz, alpha);
    double vx = alpha * ox, vz = oz, vl = sqrt(vx * vx + vz * vz);
    vx /= vl;
    vz /= vl;
    double cosines[AZIMUTHS], sines[AZIMUTHS], sum = 0.0;
    for (int j = 0; j < AZIMUTHS; j++) {
        cosines[j] = cos(PI * (j + 0.5) / AZIMUTHS);
        sines[j] = sin(PI * (j + 0.5) / AZIMUTHS);
    }
    for (int i = 0; i < HEIGHTS; i++) {
        double u1 = (i + 0.5) / HEIGHTS;
        double z = (1.0 - u1) * (1.0 + vz) - vz, s = sqrt(fmax(1.0 - z * z, 0.0));
        for (int j = 0; j < AZIMUTHS; j++) {
            double hx = alpha * (s * cosines[j] + vx), hy = alpha * s * sines[j], hz = z + vz;
            double hl = sqrt(hx * hx + hy * hy + hz * hz);
            hx /= hl, hy /= hl, hz /= hl;
            double oh = ox * hx + oz * hz;
            double ix = 2.0 * oh * hx - ox, iy = 2.0 * oh * hy, iz = 2.0 * oh * hz - oz;
            if (!(iz > 0.0)) continue;
            double li = smith_lambda(ix * ix + iy * iy, iz, alpha);
            sum += (1.0 + lo) / (1.0 + lo + li);
        }
    }
    return sum / (HEIGHTS * AZIMUTHS);
}

/* 2 mu E(mu) integrated over the segment of the table between x = a and b (mu = x^2, E linear in
 * x from ea to eb): 4 x^3 E(x) dx, of degree 4, exactly by 3-point Gauss-Legendre. */
static double moment(double a, double b, double ea, double eb) {
    static const double nodes[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
    static const double weights[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    double sum = 0.0;
    for (int q = 0; q < 3; q++) {
        double t = 0.5 * (1.0 + nodes[q]), x = a + (b - a) * t;
        sum += weights[q] * 4.0 * x * x * x * (ea + (eb - ea) * t);
    }
    return 0.5 * (b - a) * sum;
}

/* Each row (a roughness k / (N - 1), the GGX width its square): E at the cosines mu = x^2 for x = k
 * / (N - 1), dense at grazing angles, where E dips and climbs back in a thin layer, clamped to [0,
 * 1]; then E_avg = 2 * integral of mu E(mu) over the E that the lookups interpolate, exactly, so
 * that the compensation lobe's albedo is 1 - E to the float. */
static void fill(void) {
    const int n = (int)TZ_GGX_TABLE_SIZE;
    for (int r = 0; r < n; r++) {
        double roughness = (double)r / (n - 1);
        double alpha = fmax(roughness * roughness, (double)TZ_GGX_MIN_ALPHA);
        float *e = ggx_albedo_words + r * n;
        for (int k = 0; k < n; k++) {
            double x = (double)k / (n - 1);
            e[k] = (float)fmin(fmax(albedo_at(fmax(x * x, 1e-6), alpha), 0.0), 1.0);
        }
        double avg = 0.0;
        for (int k = 1; k < n; k++)
            avg += moment((double)(k - 1) / (n - 1), (double)k / (n - 1), e[k - 1], e[k]);
        ggx_albedo_words[n * n + r] = (float)fmin(avg, 1.0);
    }
}

static pthread_once_t filled = PTHREAD_ONCE_INIT;

void ggx_albedo_prepare(void) { pthread_once(&filled, fill); }
