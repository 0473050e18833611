/* cmd_gen.c: `trazador gen sphereflake|random`: the generators of scene/gen.h from the command
 * line, written to a file (all or nothing) or to standard output. */
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "scene/gen.h"
#include "util/atomic_file.h"

typedef struct gen_args {
    const char *output; /* NULL or "-": standard output */
    long long depth, count, seed;
    int force;
} gen_args;

#define ARG(field) offsetof(gen_args, field)
/* The options both generators take. */
#define COMMON_SPECS                                                                      \
    OPT_TEXT("--output", "-o", ARG(output), "FILE", "a file name",                        \
             "the scene file to write, all or nothing (default: standard output)"),       \
        OPT_WHOLE("--seed", NULL, ARG(seed), 0, 4294967295.0,                             \
                  "the random seed, 0 to 4294967295: same seed, same bytes (default 1)"), \
        OPT_SET("--force", NULL, ARG(force), 1,                                           \
                "replace a write-protected output (default: refuse it, as the shell's > does)")
static const opt_spec flake_specs[] = {
    OPT_WHOLE("--depth", NULL, ARG(depth), 0, GEN_MAX_DEPTH,
              "levels of children, 0 to " CLI_AS_TEXT(GEN_MAX_DEPTH) " (required)"),
    COMMON_SPECS,
};
static const opt_spec random_specs[] = {
    OPT_WHOLE("--count", NULL, ARG(count), 1, GEN_MAX_COUNT,
              "small spheres, 1 to " CLI_AS_TEXT(GEN_MAX_COUNT) " (required)"),
    COMMON_SPECS,
};
#undef COMMON_SPECS
#undef ARG

#define GENERATORS "sphereflake|random" /* in gen_kind order */
static const char synopsis[] =
    "usage: trazador gen sphereflake --depth N [-o FILE] [--seed N] [--force]\n"
    "       trazador gen random --count N [-o FILE] [--seed N] [--force]\n";
static const char about[] =
    "sphereflake: Eric Haines' SPD balls; random: the spheres of \"Ray Tracing in One "
    "Weekend\".\n";
static const opt_command commands[] = {
    {.name = "gen sphereflake",
     .synopsis = synopsis,
     .about = about,
     .specs = flake_specs,
     .spec_count = OPT_COUNT(flake_specs)},
    {.name = "gen random",
     .synopsis = synopsis,
     .about = about,
     .specs = random_specs,
     .spec_count = OPT_COUNT(random_specs)},
};
static const opt_command gen_command = {
    .name = "gen",
    .synopsis = synopsis,
    .about =
        "trazador gen sphereflake --help and trazador gen random --help describe their "
        "options.\n"};

int cmd_gen(int argc, char **argv) {
    if (argc < 2)
        return opt_usage_error(&gen_command, "expected a generator: sphereflake or random");
    const char *name = argv[1];
    if (!strcmp(name, "-h") || !strcmp(name, "--help")) {
        opt_print_help(&gen_command, stdout);
        return 0;
    }
    int kind = opt_choice_index(GENERATORS, name);
    if (kind < 0)
        return opt_usage_error(&gen_command,
                               "unknown generator '%s' (expected sphereflake or random)", name);
    const opt_command *cmd = &commands[kind];
    gen_args a = {.depth = -1, .count = -1, .seed = 1};
    const char *none[1];
    int count;
    opt_result rc = opt_parse(cmd, argc - 1, argv + 1, &a, none, &count);
    if (rc != OPT_OK) return rc == OPT_HELP ? 0 : rc;
    if (kind == GEN_SPHEREFLAKE && a.depth < 0)
        return opt_usage_error(cmd, "needs --depth N (0 to " CLI_AS_TEXT(GEN_MAX_DEPTH) ")");
    if (kind == GEN_RANDOM && a.count < 0)
        return opt_usage_error(cmd, "needs --count N (1 to " CLI_AS_TEXT(GEN_MAX_COUNT) ")");
    gen_desc desc = {.kind = (gen_kind)kind,
                     .depth = (int)a.depth,
                     .count = (long)a.count,
                     .seed = (uint32_t)a.seed};
    bool to_file = a.output && strcmp(a.output, "-");
    if (to_file && !atomic_file_check_force(a.output, a.force)) return 1;
    return gen_write_file(&desc, a.output) ? 0 : 1;
}
