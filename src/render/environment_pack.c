/* environment_pack.c: the environment map as the shaders read it (TZ_BINDING_ENVIRONMENT,
 * common/emitter.h): each texel's radiance and its pdf over the map's unit square, then the
 * tables that sample it by importance, built once here in double so that every back end reads
 * the same floats: a texel's weight is its luminance times the sine of its row's polar angle
 * (the solid angle it spans), the rows' marginal cdf and each row's conditional cdf, then each
 * table's guide (environment_table_pick reads it: where to start looking for u). */
#include <math.h>
#include <stdlib.h>

#include "render/scene_pack.h"
#include "util/big_memory.h"
#include "util/log.h"

#define PI 3.14159265358979323846

/* The luminance of linear Rec. 709 RGB. */
static double luminance(const float *rgb) {
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2];
}

/* cdf[0..count] of the weights w[0..count-1] summing to total: running sums over total, the last
 * exactly 1 (uniform steps where total is 0, a row never picked). */
static void put_cdf(float *cdf, const double *w, int count, double total) {
    double running = 0.0;
    cdf[0] = 0.0f;
    for (int k = 0; k < count; k++) {
        running += w[k];
        cdf[k + 1] = total > 0.0 ? (float)(running / total) : (float)(k + 1) / (float)count;
    }
    cdf[count] = 1.0f;
}

/* guide[j] for j in [0, count): the first entry k of cdf[0..count] whose next one exceeds
 * j / count, as a float, so that a search for u from guide[u count] takes a step or two. */
static void put_guide(float *guide, const float *cdf, int count) {
    int k = 0;
    for (int j = 0; j < count; j++) {
        float u = (float)j / (float)count;
        while (k < count - 1 && !(u < cdf[k + 1])) k++;
        guide[j] = (float)k;
    }
}

bool environment_pack(const environment_map *m, packed_scene *out, double *mean) {
    *mean = 0.0;
    size_t w = m->rgb ? (size_t)m->width : 0, h = m->rgb ? (size_t)m->height : 0;
    size_t floats = w ? (h + 1) + h * (w + 1) + h + h * w : 0;
    size_t texels = w * h + (floats + 3) / 4;
    out->environment = big_calloc(texels ? texels : 1, sizeof *out->environment);
    double *weight = calloc(w * h + 1, sizeof *weight), *row_sum = calloc(h + 1, sizeof *row_sum);
    if (!out->environment || !weight || !row_sum) {
        free(weight);
        free(row_sum);
        log_error("out of memory packing the %zu x %zu environment map", w, h);
        return false;
    }
    out->environment_texels = (uint32_t)texels;
    double total = 0.0, radiance = 0.0;
    for (size_t r = 0; r < h; r++) {
        double sine = sin(PI * ((double)r + 0.5) / (double)h);
        for (size_t c = 0; c < w; c++) {
            const float *rgb = m->rgb + 3 * (r * w + c);
            weight[r * w + c] = luminance(rgb) * sine;
            row_sum[r] += weight[r * w + c];
            radiance += ((double)rgb[0] + rgb[1] + rgb[2]) / 3.0 * sine;
        }
        total += row_sum[r];
    }
    /* the mean over the sphere: each texel spans (2 pi / w) (pi / h) sin(theta) sr of 4 pi */
    if (w) *mean = radiance * (2.0 * PI / (double)w) * (PI / (double)h) / (4.0 * PI);
    for (size_t k = 0; k < w * h; k++) {
        const float *rgb = m->rgb + 3 * k;
        double pdf = total > 0.0 ? weight[k] * (double)(w * h) / total : 0.0;
        out->environment[k] = (tz_vec4){rgb[0], rgb[1], rgb[2], (float)pdf};
    }
    float *tables = (float *)(out->environment + w * h);
    float *guides = tables + (h + 1) + h * (w + 1);
    if (w) put_cdf(tables, row_sum, (int)h, total);
    if (w) put_guide(guides, tables, (int)h);
    for (size_t r = 0; r < h; r++) {
        float *cdf = tables + (h + 1) + r * (w + 1);
        put_cdf(cdf, weight + r * w, (int)w, row_sum[r]);
        put_guide(guides + h + r * w, cdf, (int)w);
    }
    free(weight);
    free(row_sum);
    if (!(total > 0.0)) *mean = 0.0; /* a black map lights nothing: no emitter */
    return true;
}
