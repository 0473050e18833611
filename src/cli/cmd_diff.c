/* cmd_diff.c: `trazador diff A B`: prints the metrics of diff.h and checks them against the
 * thresholds given. Exits as cmp does: 0 when identical (or, with thresholds, within every one),
 * 1 when they differ (past a threshold given), 2 when the images cannot be read or compared (or
 * on a usage error), so `diff a b && echo same` holds and a script tells a regression from a
 * broken file. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "image/diff.h"
#include "util/log.h"

typedef struct diff_args {
    double max_rmse, min_psnr, max_share; /* NAN: not given */
} diff_args;

#define ARG(field) offsetof(diff_args, field)
static const opt_spec diff_specs[] = {
    OPT_DECIMAL("--max-rmse", ARG(max_rmse), 0.0, INFINITY, "X",
                "fail past this RMSE of the linear values, 0 to inf (default: no limit)"),
    /* An 8-bit PSNR is never negative. */
    OPT_DECIMAL("--min-psnr", ARG(min_psnr), 0.0, INFINITY, "DB",
                "fail under this 8-bit sRGB PSNR in dB, 0 to inf (default: no limit)"),
    OPT_DECIMAL("--max-diff-share", ARG(max_share), 0.0, 1.0, "FRACTION",
                "fail past this share of differing pixels, 0 to 1: 0.01 is 1% (default: no "
                "limit)"),
};
#undef ARG

static const opt_command diff_command = {
    .name = "diff",
    .synopsis =
        "usage: trazador diff A B [--max-rmse X] [--min-psnr DB] [--max-diff-share FRACTION]\n",
    .about =
        "Exits 0 when A and B are identical, or with thresholds when they are within every\n"
        "one given; 1 when any value differs (past a threshold given); 2 when A and B\n"
        "cannot be read or compared (as cmp does).\n",
    .specs = diff_specs,
    .spec_count = OPT_COUNT(diff_specs),
    .max_positional = 2,
};

/* Exit code when the images cannot be read or compared. */
#define DIFF_CANNOT_COMPARE 2

int cmd_diff(int argc, char **argv) {
    diff_args limits = {NAN, NAN, NAN};
    const char *files[2];
    int nfiles;
    opt_result rc = opt_parse(&diff_command, argc, argv, &limits, files, &nfiles);
    if (rc != OPT_OK) return rc == OPT_HELP ? 0 : rc;
    if (nfiles != 2) return opt_usage_error(&diff_command, "expected two images A and B");

    image a, b;
    if (!image_read(files[0], &a, TONEMAP_SRGB)) return DIFF_CANNOT_COMPARE;
    if (!image_read(files[1], &b, TONEMAP_SRGB)) {
        image_free(&a);
        return DIFF_CANNOT_COMPARE;
    }
    if (a.width != b.width || a.height != b.height) {
        log_error("diff: %s is %dx%d but %s is %dx%d", files[0], a.width, a.height, files[1],
                  b.width, b.height);
        image_free(&a);
        image_free(&b);
        return DIFF_CANNOT_COMPARE;
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
    int result = 0;
    if (!isnan(limits.max_rmse) && !(s.rmse <= limits.max_rmse)) {
        printf("FAIL: rmse %.6g > %g\n", s.rmse, limits.max_rmse);
        result = 1;
    }
    if (!isnan(limits.min_psnr) && !(s.psnr >= limits.min_psnr)) {
        printf("FAIL: psnr %.2f dB < %g\n", s.psnr, limits.min_psnr);
        result = 1;
    }
    if (!isnan(limits.max_share) && !(s.differ_share <= limits.max_share)) {
        printf("FAIL: differ %.4f%% > %g%%\n", 100.0 * s.differ_share, 100.0 * limits.max_share);
        result = 1;
    }
    /* Without a tolerance any difference is one, as for cmp. */
    bool tolerant = !isnan(limits.max_rmse) || !isnan(limits.min_psnr) || !isnan(limits.max_share);
    if (!tolerant && !(s.max_diff == 0.0)) {
        printf("FAIL: the images differ (max_diff %.6g; give a threshold to allow some)\n",
               s.max_diff);
        result = 1;
    }
    fflush(stdout);
    return result;
}
