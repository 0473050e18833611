/* output_flags.c: the output flags render and merge share that mean something for some formats
 * only (--tonemap, --exr-type): said once when given for an output that has no use for them,
 * rather than ignored silently. */
#include <string.h>

#include "cli/cli.h"
#include "util/log.h"

void cli_warn_unused(const char *format, bool part, int *tm, int *exr_type) {
    bool exr = format && !strcmp(format, "exr"),
         eight_bit = format && !exr && strcmp(format, "pfm");
    if (*tm >= 0 && !eight_bit)
        log_warn(
            "--tonemap does nothing for %s: it sets 8-bit encoding (PNG, PPM), and %s is "
            "linear",
            part  ? "a part"
            : exr ? "an exr output"
                  : "a pfm output",
            exr ? "EXR" : "PFM");
    if (*exr_type >= 0 && (!exr || part))
        log_warn("--exr-type does nothing for %s: it sets an EXR image's channels%s",
                 part ? "a part" : "an output that is no EXR",
                 part ? " (parts are always float)" : "");
    if (*tm < 0) *tm = 0;             /* TONEMAP_SRGB */
    if (*exr_type < 0) *exr_type = 0; /* half */
}
