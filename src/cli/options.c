/* options.c: the option-table parser of options.h: one loop for every subcommand, so that
 * `--flag=value`, `--`, the case rule of enum values and the wording of usage errors are the same
 * everywhere. */
#include "cli/options.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

bool opt_parse_int(const char *text, long long min, long long max, long long *out) {
    if (!text || !*text || strspn(text, "+-0123456789") != strlen(text)) return false;
    char *end;
    errno = 0;
    long long v = strtoll(text, &end, 10);
    if (errno || *end || v < min || v > max) return false;
    *out = v;
    return true;
}

bool opt_parse_number(const char *text, double *out) {
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

int opt_choice_index(const char *choices, const char *text) {
    size_t length = strlen(text);
    int index = 0;
    for (const char *c = choices; *c; index++) {
        size_t n = strcspn(c, "|");
        if (n == length && length > 0 && !strncasecmp(c, text, n)) return index;
        c += n + (c[n] == '|');
    }
    return -1;
}

/* What the option's value is, for messages: "a whole number from 1 to 65536", "png, ppm or
 * pfm". */
static void describe(const opt_spec *o, char *text, size_t size) {
    if (o->takes) {
        snprintf(text, size, "%s", o->takes);
    } else if (o->type == OPT_INT) {
        snprintf(text, size, "a whole number from %lld to %lld", (long long)o->min,
                 (long long)o->max);
    } else if (o->type == OPT_NUMBER) {
        snprintf(text, size, "a decimal number from %g to %g", o->min, o->max);
    } else if (o->type == OPT_CHOICE) {
        size_t used = 0, names = 1;
        for (const char *c = o->choices; *c; c++) names += *c == '|';
        text[0] = '\0';
        size_t k = 0;
        for (const char *c = o->choices; *c && used < size; k++) {
            size_t n = strcspn(c, "|");
            const char *sep = k == 0 ? "" : k + 1 == names ? " or " : ", ";
            used += (size_t)snprintf(text + used, size - used, "%s%.*s", sep, (int)n, c);
            c += n + (c[n] == '|');
        }
    } else {
        snprintf(text, size, "a value");
    }
}

opt_result opt_usage_error(const opt_command *cmd, const char *fmt, ...) {
    fprintf(stderr, "trazador: %s: ", cmd->name);
    va_list ap;
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n%s(trazador %s --help describes every option)\n", cmd->synopsis, cmd->name);
    return OPT_USAGE;
}

/* "trazador: CMD OPTION takes WHAT, got 'VALUE'" (or "needs WHAT" with no value) and the
 * synopsis; OPT_USAGE. */
static opt_result value_error(const opt_command *cmd, const opt_spec *o, const char *shown,
                              const char *value) {
    char what[160];
    describe(o, what, sizeof what);
    if (value)
        fprintf(stderr, "trazador: %s %s takes %s, got '%s'\n", cmd->name, shown, what, value);
    else
        fprintf(stderr, "trazador: %s %s needs %s\n", cmd->name, shown, what);
    fprintf(stderr, "%s(trazador %s --help describes every option)\n", cmd->synopsis, cmd->name);
    return OPT_USAGE;
}

/* Help lines: the flag in the first HELP_COLUMN columns, its text wrapped at HELP_WIDTH. */
#define HELP_COLUMN 31
#define HELP_WIDTH 100

/* Prints `left` padded to HELP_COLUMN, then `text` broken at spaces into lines of HELP_WIDTH,
 * each further line indented to HELP_COLUMN. */
static void print_wrapped(FILE *fp, const char *left, const char *text) {
    int column = fprintf(fp, "%-*s", HELP_COLUMN - 1, left);
    if (column >= HELP_COLUMN) { /* a long flag: its text starts on the next line */
        fprintf(fp, "\n%*s", HELP_COLUMN - 1, "");
        column = HELP_COLUMN - 1;
    }
    while (*text) {
        size_t word = strcspn(text, " ");
        if (column > HELP_COLUMN - 1 && column + 1 + (int)word > HELP_WIDTH) {
            fprintf(fp, "\n%*s", HELP_COLUMN - 1, "");
            column = HELP_COLUMN - 1;
        }
        column += fprintf(fp, " %.*s", (int)word, text);
        text += word;
        text += strspn(text, " ");
    }
    fputc('\n', fp);
}

void opt_print_help(const opt_command *cmd, FILE *fp) {
    fputs(cmd->synopsis, fp);
    if (cmd->spec_count) fputs("options:\n", fp);
    for (int k = 0; k < cmd->spec_count; k++) {
        const opt_spec *o = &cmd->specs[k];
        char left[96];
        int n = snprintf(left, sizeof left, "  %s%s%s", o->alias ? o->alias : "",
                         o->alias ? ", " : "", o->name);
        if (o->type != OPT_FLAG && n > 0 && (size_t)n < sizeof left)
            snprintf(left + n, sizeof left - (size_t)n, " %s", o->choices ? o->choices : "X");
        print_wrapped(fp, left, o->help);
    }
    if (cmd->about) fputs(cmd->about, fp);
}

/* Stores the value of o into dest; false (the error printed) when it is not one o takes. */
static bool store(const opt_command *cmd, const opt_spec *o, const char *shown, const char *value,
                  void *dest) {
    char *field = (char *)dest + o->offset;
    long long whole;
    double number;
    int index;
    switch (o->type) {
        case OPT_FLAG:
            *(int *)field = o->set;
            return true;
        case OPT_INT:
            if (!opt_parse_int(value, (long long)o->min, (long long)o->max, &whole)) break;
            *(long long *)field = whole;
            return true;
        case OPT_NUMBER:
            if (!opt_parse_number(value, &number) || !(number >= o->min && number <= o->max)) break;
            *(double *)field = number;
            return true;
        case OPT_STRING:
            if (!*value) break;
            *(const char **)field = value;
            return true;
        case OPT_CHOICE:
            index = opt_choice_index(o->choices, value);
            if (index < 0) break;
            *(int *)field = index;
            return true;
    }
    value_error(cmd, o, shown, value);
    return false;
}

opt_result opt_parse(const opt_command *cmd, int argc, char **argv, void *dest,
                     const char **positional, int *positional_count) {
    *positional_count = 0;
    bool options_ended = false;
    for (int k = 1; k < argc; k++) {
        const char *arg = argv[k];
        if (options_ended || arg[0] != '-' || !arg[1]) { /* "-" names standard input or output */
            if (*positional_count == cmd->max_positional)
                return opt_usage_error(cmd, "unexpected argument '%s'", arg);
            positional[(*positional_count)++] = arg;
            continue;
        }
        if (!strcmp(arg, "--")) {
            options_ended = true;
            continue;
        }
        if (!strcmp(arg, "-h") || !strcmp(arg, "--help")) {
            opt_print_help(cmd, stdout);
            return OPT_HELP;
        }
        /* --name=value: the name is what comes before the first '='. */
        const char *equals = !strncmp(arg, "--", 2) ? strchr(arg, '=') : NULL;
        size_t name_length = equals ? (size_t)(equals - arg) : strlen(arg);
        const opt_spec *o = NULL;
        for (int s = 0; s < cmd->spec_count && !o; s++) {
            const opt_spec *c = &cmd->specs[s];
            if ((strlen(c->name) == name_length && !strncmp(c->name, arg, name_length)) ||
                (c->alias && !equals && !strcmp(c->alias, arg)))
                o = c;
        }
        if (!o) return opt_usage_error(cmd, "unknown option '%.*s'", (int)name_length, arg);
        char shown[64];
        snprintf(shown, sizeof shown, "%.*s", (int)name_length, arg);
        const char *value = NULL;
        if (o->type == OPT_FLAG) {
            if (equals) return opt_usage_error(cmd, "%s takes no value", shown);
        } else if (equals) {
            value = equals + 1;
        } else if (k + 1 < argc) {
            value = argv[++k];
        } else {
            return value_error(cmd, o, shown, NULL);
        }
        if (!store(cmd, o, shown, value, dest)) return OPT_USAGE;
    }
    return OPT_OK;
}
