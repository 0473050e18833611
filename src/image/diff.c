/* diff.c: image comparison metrics (RMSE, PSNR, max difference, share of differing pixels); the
 * `trazador diff` subcommand that checks them against thresholds is src/cli/cmd_diff.c. */
#include "image/diff.h"

#include <math.h>

#include "util/log.h"

bool diff_images(const image *a, const image *b, diff_stats *out) {
    *out = (diff_stats){0};
    if (a->width != b->width || a->height != b->height) {
        log_error("cannot compare a %dx%d image with a %dx%d one", a->width, a->height, b->width,
                  b->height);
        return false;
    }
    size_t pixels = (size_t)a->width * (size_t)a->height;
    double sum_sq = 0.0, sum_sq8 = 0.0, max_diff = 0.0;
    long differ = 0;
    for (size_t p = 0; p < pixels; p++) {
        bool differs = false;
        for (int c = 0; c < 3; c++) {
            float x = a->rgb[3 * p + c], y = b->rgb[3 * p + c];
            /* equal infinities and two NaNs compare equal; a NaN against a number makes rmse and
             * max_diff NaN */
            double d = x == y || (isnan(x) && isnan(y)) ? 0.0 : fabs((double)x - (double)y);
            sum_sq += d * d;
            if (d > max_diff || isnan(d)) max_diff = d;
            double ex = tonemap_encode(x, TONEMAP_SRGB), ey = tonemap_encode(y, TONEMAP_SRGB);
            /* the same rounding as tonemap_channel, without encoding twice */
            double d8 = (double)(uint8_t)(ex * 255.0 + 0.5) - (double)(uint8_t)(ey * 255.0 + 0.5);
            /* A NaN or infinity that the other image does not have is a broken pixel, not the
             * black or white it would be written as: the largest 8-bit difference. */
            if (d != 0.0 && !(isfinite(x) && isfinite(y))) d8 = 255.0, ex = 0.0, ey = 1.0;
            sum_sq8 += d8 * d8;
            if (fabs(ex - ey) > 1.0 / 255.0) differs = true;
        }
        differ += differs;
    }
    double samples = 3.0 * (double)pixels;
    out->rmse = sqrt(sum_sq / samples);
    out->psnr = sum_sq8 == 0.0 ? INFINITY : 10.0 * log10(255.0 * 255.0 / (sum_sq8 / samples));
    out->max_diff = max_diff;
    out->differ_count = differ;
    out->differ_share = (double)differ / (double)pixels;
    return true;
}
