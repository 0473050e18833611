/* diff.c: image comparison metrics (RMSE, PSNR, max difference, share of differing pixels) and
   the `trazador diff` subcommand that checks them against thresholds. */
#include "image/diff.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
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

static const char usage[] =
    "usage: trazador diff A B [--max-rmse X] [--min-psnr DB] [--max-diff-share FRACTION]\n"
    "  --max-diff-share takes a fraction of the pixels, 0 to 1 (0.01 is 1%)\n";

static int usage_error(const char *what, const char *arg) {
    log_error("diff: %s%s", what, arg);
    fputs(usage, stderr);
    return 2;
}

typedef struct threshold {
    const char *flag;
    double min, max; /* the values that mean something */
    double value;
    bool given;
} threshold;

int diff_command(int argc, char **argv) {
    threshold limits[] = {{"--max-rmse", 0.0, INFINITY, 0, false},
                          {"--min-psnr", 0.0, INFINITY, 0, false}, /* 8-bit PSNR >= 0 */
                          {"--max-diff-share", 0.0, 1.0, 0, false}};
    const int nlimits = (int)(sizeof limits / sizeof limits[0]);
    const char *files[2];
    int nfiles = 0;
    for (int i = 1; i < argc; i++) {
        const char *arg = argv[i];
        if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
            fputs(usage, stdout);
            return 0;
        }
        if (arg[0] != '-' || arg[1] == '\0') {
            if (nfiles == 2) return usage_error("expected two images, got another: ", arg);
            files[nfiles++] = arg;
            continue;
        }
        int k = 0;
        while (k < nlimits && strcmp(arg, limits[k].flag) != 0) k++;
        if (k == nlimits) return usage_error("unknown option ", arg);
        if (i + 1 == argc) return usage_error("missing value after ", arg);
        double v;
        if (!cli_parse_number(argv[++i], &v)) {
            log_error("diff: %s expects a decimal number, not '%s'", arg, argv[i]);
            fputs(usage, stderr);
            return 2;
        }
        if (v < limits[k].min || v > limits[k].max) {
            log_error("diff: %s takes %g to %g, not '%s'", arg, limits[k].min, limits[k].max,
                      argv[i]);
            fputs(usage, stderr);
            return 2;
        }
        limits[k].value = v;
        limits[k].given = true;
    }
    if (nfiles != 2) return usage_error("expected two images A and B", "");

    image a, b;
    if (!image_read(files[0], &a, TONEMAP_SRGB)) return 1;
    if (!image_read(files[1], &b, TONEMAP_SRGB)) {
        image_free(&a);
        return 1;
    }
    if (a.width != b.width || a.height != b.height) {
        log_error("diff: %s is %dx%d but %s is %dx%d", files[0], a.width, a.height, files[1],
                  b.width, b.height);
        image_free(&a);
        image_free(&b);
        return 1;
    }
    diff_stats s;
    diff_images(&a, &b, &s);
    long pixels = (long)a.width * a.height;
    image_free(&a);
    image_free(&b);

    printf("rmse %.6g\n", s.rmse);
    printf("psnr %.2f dB\n", s.psnr);
    printf("max_diff %.6g\n", s.max_diff);
    printf("differ %.4f%% (%ld of %ld pixels)\n", 100.0 * s.differ_share, s.differ_count, pixels);
    /* written as !(within) so that a NaN metric fails */
    int rc = 0;
    if (limits[0].given && !(s.rmse <= limits[0].value)) {
        printf("FAIL: rmse %.6g > %g\n", s.rmse, limits[0].value);
        rc = 1;
    }
    if (limits[1].given && !(s.psnr >= limits[1].value)) {
        printf("FAIL: psnr %.2f dB < %g\n", s.psnr, limits[1].value);
        rc = 1;
    }
    if (limits[2].given && !(s.differ_share <= limits[2].value)) {
        printf("FAIL: differ %.4f%% > %g%%\n", 100.0 * s.differ_share, 100.0 * limits[2].value);
        rc = 1;
    }
    fflush(stdout);
    return rc;
}
