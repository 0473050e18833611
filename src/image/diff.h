/* diff.h: image comparison metrics. */
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

#endif
