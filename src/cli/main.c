/* main.c: the command line's entry: dispatches to the subcommands (cli.h), the only place that
 * exits. Exit codes: 0 success, 1 runtime failure, 2 usage or scene error. */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "cli/cli.h"

static const char usage_text[] =
    "usage: trazador render [SCENE] [-o OUT] [--backend auto|vulkan|cpu] [--spp N] [--seed N]\n"
    "                       [--mode report|path] [--no-jitter] [--no-indirect] [--indirect]\n"
    "                       [--bounces N] [--sampler auto|random|sobol] [--light-samples N]\n"
    "                       [--camera N|NAME]\n"
    "                       [--threads N] [--device N] [--walk auto|compute|cooperative|rayquery]\n"
    "                       [--validate] [--quiet]\n"
    "                       [--verbose] [--tonemap srgb|linear] [--width N] [--no-bvh]\n"
    "                       [--format F] [--force] [--region X0,X1,Y0,Y1] [--samples A:B]\n"
    "                       [--part] [--checkpoint FILE] [--checkpoint-every S]\n"
    "                       [--keep-checkpoint] [--resume FILE] [--time-limit S]\n"
    "                       [--exr-type half|float]\n"
    "       trazador merge PARTS... -o OUT [--part] [--exr-type half|float] [--format F]\n"
    "       trazador diff A B [--max-rmse X] [--min-psnr DB] [--max-diff-share FRACTION]\n"
    "       trazador view [SCENE] [--backend auto|vulkan|cpu] [--spp N] [--width N] ...\n"
    "       trazador devices\n"
    "       trazador formats\n"
    "       trazador info MODEL\n"
    "       trazador bench [--backend auto|vulkan|cpu|both] [--spp N]\n"
    "       trazador gen sphereflake --depth N [-o FILE] [--seed N] [--force]\n"
    "       trazador gen random --count N [-o FILE] [--seed N] [--force]\n"
    "       trazador --help | --version\n"
    "SCENE defaults to the embedded scenes/cornell.scene ('-' reads standard input),\n"
    "OUT to render.png;\n"
    "the output format follows the extension: .png, .ppm, .pfm (linear float) or .exr\n"
    "(OpenEXR, linear half or float), or --format png|ppm|pfm|exr for any name\n"
    "(-o - --format ppm writes to standard output).\n"
    "trazador COMMAND --help describes every option of a command and its default;\n"
    "options take their value as --flag value or --flag=value, and -- ends them.\n";

typedef struct command {
    const char *name;
    int (*run)(int argc, char **argv);
} command;

static const command commands[] = {
    {"render", cmd_render},   {"merge", cmd_merge},     {"diff", cmd_diff},
    {"gen", cmd_gen},         {"devices", cmd_devices}, {"bench", cmd_bench},
    {"formats", cmd_formats}, {"view", cmd_view},       {"info", cmd_info},
};

/* Runs the subcommand argv[1]; its exit code. */
static int run_command(int argc, char **argv) {
    if (argc < 2) {
        fputs(usage_text, stderr);
        return 2;
    }
    const char *name = argv[1];
    if (!strcmp(name, "--help") || !strcmp(name, "-h") || !strcmp(name, "help")) {
        fputs(usage_text, stdout);
        return 0;
    }
    if (!strcmp(name, "--version")) {
        printf("trazador %s\n", TRAZADOR_VERSION);
        return 0;
    }
    for (size_t k = 0; k < sizeof commands / sizeof commands[0]; k++)
        if (!strcmp(name, commands[k].name)) return commands[k].run(argc - 1, argv + 1);
    fprintf(stderr, "trazador: unknown command '%s'\n%s", name, usage_text);
    return 2;
}

int main(int argc, char **argv) {
    int rc = run_command(argc, argv);
    /* What went to standard output is data (diff's metrics, a scene, a list): a failed write
     * there (a full disk, /dev/full) fails the run. */
    if ((fflush(stdout) != 0 || ferror(stdout)) && rc == 0) {
        fprintf(stderr, "trazador: cannot write to standard output: %s\n", strerror(errno));
        rc = 1;
    }
    return rc;
}
