/* cmd_info.c: `trazador info MODEL`, what a model file given as the scene would be rendered
 * with: its faces, its cameras (for `render --camera`) and its lights, as trazador's space has
 * them. */
#include <stdio.h>

#include "cli/cli.h"
#include "cli/options.h"
#include "scene/model_scene.h"

int cmd_info(int argc, char **argv) {
    static const opt_command command = {
        .name = "info",
        .synopsis = "usage: trazador info MODEL\n",
        .about =
            "Lists a model file's faces, cameras (index, name, position, direction, up, "
            "horizontal fov, aspect) and lights, in trazador's space.\n",
        .max_positional = 1,
    };
    const char *path = NULL;
    int count;
    opt_result rc = opt_parse(&command, argc, argv, NULL, &path, &count);
    if (rc != OPT_OK) return rc == OPT_HELP ? 0 : rc;
    if (!path) {
        fputs("trazador: info needs a model file (trazador info model.glb)\n", stderr);
        return 2;
    }
    scene_error err;
    if (model_scene_list(path, stdout, &err)) return 0;
    scene_error_print(&err);
    return err.out_of_memory ? 1 : 2;
}
