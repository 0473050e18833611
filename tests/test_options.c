/* test_options.c: the option-table parser (src/cli/options.c) on a table of every type: values
 * stored where the table says, ranges, choices in any case, --flag=value, --, positional
 * arguments, and the exit results of usage errors and --help. */
#include <fcntl.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "check.h"
#include "cli/options.h"

typedef struct args {
    const char *name;
    long long count;
    double share;
    int mode, loud;
} args;

#define ARG(field) offsetof(args, field)
static const opt_spec specs[] = {
    OPT_TEXT("--name", "-n", ARG(name), "NAME", "a name", "a name (default none)"),
    OPT_WHOLE("--count", NULL, ARG(count), 1, 10, "how many, 1 to 10 (default 1)"),
    OPT_DECIMAL("--share", ARG(share), 0.0, 1.0, "F", "a share, 0 to 1 (default 0)"),
    OPT_ONE_OF("--mode", ARG(mode), "seed|path|debug", "the mode (default seed)"),
    OPT_SET("--loud", "-l", ARG(loud), 1, "louder (default off)"),
    OPT_SET("--soft", NULL, ARG(loud), 0, "softer (default)"),
};
#undef ARG

static const opt_command command = {.name = "test",
                                    .synopsis = "usage: test [options] [A] [B]\n",
                                    .specs = specs,
                                    .spec_count = OPT_COUNT(specs),
                                    .max_positional = 2};

static args parsed;
static const char *positional[2];
static int positional_count;

/* Parses a NULL-terminated list (argv[0] = "test" added) with stderr and stdout muted. */
static opt_result parse(const char *first, ...) {
    char *argv[16] = {"test"};
    int argc = 1;
    va_list ap;
    va_start(ap, first);
    for (const char *a = first; a && argc < 15; a = va_arg(ap, const char *))
        argv[argc++] = (char *)a;
    va_end(ap);
    parsed = (args){.count = 1};
    fflush(stdout);
    fflush(stderr);
    int saved_out = dup(1), saved_err = dup(2), null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    opt_result rc = opt_parse(&command, argc, argv, &parsed, positional, &positional_count);
    fflush(stdout);
    fflush(stderr);
    dup2(saved_out, 1);
    dup2(saved_err, 2);
    close(saved_out);
    close(saved_err);
    close(null);
    return rc;
}

static void test_values(void) {
    EXPECT(parse("--name", "x", "--count", "7", "--share", "0.25", "--mode", "path", "-l", NULL) ==
           OPT_OK);
    EXPECT(!strcmp(parsed.name, "x") && parsed.count == 7 && parsed.share == 0.25 &&
           parsed.mode == 1 && parsed.loud == 1);
    /* --flag=value, an alias, the last of two flags on one field wins */
    EXPECT(parse("--count=10", "-n", "y", "--share=inf", NULL) == OPT_USAGE); /* inf > 1 */
    EXPECT(parse("--count=10", "-n", "y", "--loud", "--soft", NULL) == OPT_OK);
    EXPECT(parsed.count == 10 && !strcmp(parsed.name, "y") && parsed.loud == 0);
    EXPECT(parse("--name=a=b", NULL) == OPT_OK && !strcmp(parsed.name, "a=b"));
    /* choices in any case, and only whole names */
    EXPECT(parse("--mode", "DEBUG", NULL) == OPT_OK && parsed.mode == 2);
    EXPECT(parse("--mode=Seed", NULL) == OPT_OK && parsed.mode == 0);
    EXPECT(parse("--mode", "pat", NULL) == OPT_USAGE);
    EXPECT(parse("--mode", "", NULL) == OPT_USAGE);
    EXPECT(opt_choice_index("seed|path|debug", "paths") == -1);
    EXPECT(opt_choice_index("seed|path|debug", "PATH") == 1);
}

static void test_ranges(void) {
    EXPECT(parse("--count", "0", NULL) == OPT_USAGE);
    EXPECT(parse("--count", "11", NULL) == OPT_USAGE);
    EXPECT(parse("--count", "1.5", NULL) == OPT_USAGE);
    EXPECT(parse("--count", " 3", NULL) == OPT_USAGE);
    EXPECT(parse("--share", "-0.1", NULL) == OPT_USAGE);
    EXPECT(parse("--share", "nan", NULL) == OPT_USAGE);
    EXPECT(parse("--share", "0x1p-1", NULL) == OPT_USAGE);
    EXPECT(parse("--share", "1", NULL) == OPT_OK && parsed.share == 1.0);
    EXPECT(parse("--count", NULL) == OPT_USAGE); /* no value */
    EXPECT(parse("--name", "", NULL) == OPT_USAGE);
    EXPECT(parse("--loud=1", NULL) == OPT_USAGE); /* a flag takes no value */
    EXPECT(parse("--bogus", NULL) == OPT_USAGE);
    EXPECT(parse("--coun", "3", NULL) == OPT_USAGE); /* no prefixes */
    EXPECT(parse("-n=x", NULL) == OPT_USAGE);        /* aliases take no '=' */
}

static void test_positional(void) {
    EXPECT(parse("a", "--count", "2", "b", NULL) == OPT_OK && positional_count == 2);
    EXPECT(!strcmp(positional[0], "a") && !strcmp(positional[1], "b"));
    EXPECT(parse("a", "b", "c", NULL) == OPT_USAGE);
    EXPECT(parse("-", NULL) == OPT_OK && positional_count == 1 && !strcmp(positional[0], "-"));
    /* -- ends the options: what follows is positional, --help included */
    EXPECT(parse("--count", "3", "--", "--loud", "--help", NULL) == OPT_OK);
    EXPECT(positional_count == 2 && !strcmp(positional[0], "--loud") && parsed.loud == 0);
    EXPECT(parse("--help", NULL) == OPT_HELP);
    EXPECT(parse("--count", "99", "--help", NULL) == OPT_USAGE); /* the first error stops */
}

static void test_help(void) {
    char *text = NULL;
    size_t length = 0;
    FILE *fp = open_memstream(&text, &length);
    opt_print_help(&command, fp);
    fclose(fp);
    EXPECT(text && strstr(text, "usage: test"));
    EXPECT(text && strstr(text, "  -n, --name NAME"));
    EXPECT(text && strstr(text, "  --mode seed|path|debug"));
    EXPECT(text && strstr(text, "  -l, --loud"));
    free(text);
}

int main(void) {
    CHECK_CASE(test_values);
    CHECK_CASE(test_ranges);
    CHECK_CASE(test_positional);
    CHECK_CASE(test_help);
    return check_summary("test_options");
}
