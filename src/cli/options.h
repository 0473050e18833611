/* options.h: the one table-driven parser behind every subcommand's flags. A command lists its
 * options once (name, type, range, destination, help line); parsing, `--flag=value`, `--`, the
 * usage errors and `--help` all come from that list. */
#ifndef TRAZADOR_OPTIONS_H
#define TRAZADOR_OPTIONS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef enum opt_type {
    OPT_FLAG,   /* no value: stores `set` in an int */
    OPT_INT,    /* a whole decimal number in [min, max], stored as a long long */
    OPT_NUMBER, /* a decimal number or "inf" in [min, max], stored as a double */
    OPT_STRING, /* any non-empty text, stored as a const char * */
    OPT_CHOICE, /* one of `choices` ("auto|vulkan|cpu"), any case, stored as its index in an int */
} opt_type;

typedef struct opt_spec {
    const char *name;  /* "--spp" */
    const char *alias; /* "-o", or NULL */
    opt_type type;
    size_t offset;       /* of the destination in the command's argument struct (offsetof) */
    double min, max;     /* OPT_INT and OPT_NUMBER: the values allowed */
    const char *choices; /* OPT_CHOICE: the names, '|' between them; else the value's name, "N" */
    const char *takes;   /* what the value is, for messages; NULL: said from type and range */
    const char *help;    /* one line for --help, default included */
    int set;             /* OPT_FLAG: the value stored */
} opt_spec;

typedef struct opt_command {
    const char *name;     /* "render", "gen random": the prefix of its messages */
    const char *synopsis; /* "usage: trazador render ..." lines, ending in '\n' */
    const char *about;    /* what --help says after the options (may be NULL) */
    const opt_spec *specs;
    int spec_count;
    int max_positional; /* arguments that are not options, at most */
} opt_command;

/* One table line per option; `field` is an offsetof into the command's argument struct. */
#define OPT_SET(name_, alias_, field, value, help_)                                      \
    {                                                                                    \
        .name = name_, .alias = alias_, .type = OPT_FLAG, .offset = field, .set = value, \
        .help = help_                                                                    \
    }
#define OPT_WHOLE(name_, alias_, field, min_, max_, help_)                             \
    {                                                                                  \
        .name = name_, .alias = alias_, .type = OPT_INT, .offset = field, .min = min_, \
        .max = max_, .choices = "N", .help = help_                                     \
    }
#define OPT_DECIMAL(name_, field, min_, max_, metavar, help_)                         \
    {                                                                                 \
        .name = name_, .type = OPT_NUMBER, .offset = field, .min = min_, .max = max_, \
        .choices = metavar, .help = help_                                             \
    }
#define OPT_TEXT(name_, alias_, field, metavar, takes_, help_)                                   \
    {                                                                                            \
        .name = name_, .alias = alias_, .type = OPT_STRING, .offset = field, .choices = metavar, \
        .takes = takes_, .help = help_                                                           \
    }
#define OPT_ONE_OF(name_, field, choices_, help_) \
    { .name = name_, .type = OPT_CHOICE, .offset = field, .choices = choices_, .help = help_ }

#define OPT_COUNT(table) ((int)(sizeof(table) / sizeof((table)[0])))

/* The parse ends in one of these. */
typedef enum opt_result { OPT_OK = 0, OPT_HELP = -1, OPT_USAGE = 2 } opt_result;

/* Parses argv[1..argc) into `dest` by the table, the other arguments into positional[] (their
 * count in *positional_count). OPT_HELP after printing --help on stdout; OPT_USAGE after
 * printing the error and the synopsis on stderr. */
opt_result opt_parse(const opt_command *cmd, int argc, char **argv, void *dest,
                     const char **positional, int *positional_count);
/* Prints "trazador: NAME: message" and the synopsis on stderr; returns OPT_USAGE. */
opt_result opt_usage_error(const opt_command *cmd, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
/* Prints the synopsis and one line per option on fp; never fails. */
void opt_print_help(const opt_command *cmd, FILE *fp);
/* The index of `text` among `choices` ("a|b|c"), any case; -1 when it is none of them. */
int opt_choice_index(const char *choices, const char *text);
/* Parses a whole decimal integer in [min, max]; false on anything else. */
bool opt_parse_int(const char *text, long long min, long long max, long long *out);
/* Parses a whole decimal number, or "inf" (no hex, nan or spaces); false on anything else. */
bool opt_parse_number(const char *text, double *out);

#endif
