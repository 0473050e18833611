/* cli.c: what the subcommands share to read their arguments. */
#include "cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

bool cli_parse_int(const char *text, long long min, long long max, long long *out) {
    if (!text || !*text || strspn(text, "+-0123456789") != strlen(text)) return false;
    char *end;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (errno || *end || v < min || v > max) return false;
    *out = v;
    return true;
}

bool cli_parse_number(const char *text, double *out) {
    if (text && !strcmp(text, "inf")) {
        *out = INFINITY;
        return true;
    }
    if (!text || !*text || strspn(text, "+-.0123456789eE") != strlen(text)) return false;
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end || !isfinite(v)) return false;
    *out = v;
    return true;
}
