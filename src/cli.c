/* cli.c: what the subcommands share to read their arguments. */
#include "cli.h"

#include <errno.h>
#include <stdlib.h>

bool cli_parse_int(const char *text, long long min, long long max, long long *out) {
    if (!text || !*text) return false;
    char *end;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (errno || *end || v < min || v > max) return false;
    *out = v;
    return true;
}
