/* cmd_formats.c: `trazador formats`, the model formats a scene's `mesh file` reads, as the assimp
 * trazador opens lists them (the README named `assimp listext`, a tool Debian does not install
 * with the library). */
#include <stdio.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "scene/model_formats.h"

int cmd_formats(int argc, char **argv) {
    static const opt_command command = {
        .name = "formats",
        .synopsis = "usage: trazador formats\n",
        .about = "Lists the model formats a scene's `mesh file PATH` reads, from assimp itself.\n",
    };
    const char *positional[1];
    int count;
    opt_result rc = opt_parse(&command, argc, argv, NULL, positional, &count);
    if (rc != OPT_OK) return rc == OPT_HELP ? 0 : rc;
    return model_formats_print(stdout) ? 0 : 1;
}
