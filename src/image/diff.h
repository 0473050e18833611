/* diff.h: image comparison metrics and the `trazador diff` subcommand. */
#ifndef TRAZADOR_DIFF_H
#define TRAZADOR_DIFF_H

#include <stdbool.h>

#include "image/image.h"

typedef struct diff_stats {
    double rmse;         /* root mean square difference of the linear values, all channels */
    double psnr;         /* dB on 8-bit sRGB-encoded values; +infinity when those are identical */
    double max_diff;     /* largest absolute linear difference in any channel */
    double differ_share; /* share of pixels where a display-encoded channel differs by > 1/255 */
    long differ_count;   /* number of such pixels */
} diff_stats;

/* Compares two images of the same size; false (and a logged error) when the sizes differ. */
bool diff_images(const image *a, const image *b, diff_stats *out);
/* `trazador diff A B [--max-rmse X] [--min-psnr X] [--max-diff-share X]`, argv[0] = "diff":
   returns 0 within every threshold, 1 past one or on an unreadable image or a size mismatch,
   2 on a usage error. */
int diff_command(int argc, char **argv);

#endif
