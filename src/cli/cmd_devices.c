/* cmd_devices.c: `trazador devices`, the Vulkan devices and the default one. */
#include "cli/cli.h"
#include "cli/options.h"
#include "render/render.h"

int cmd_devices(int argc, char **argv) {
    static const opt_command command = {
        .name = "devices",
        .synopsis = "usage: trazador devices\n",
        .about = "Lists the Vulkan devices; * marks the default (--device picks another).\n",
    };
    const char *positional[1];
    int count;
    opt_result rc = opt_parse(&command, argc, argv, NULL, positional, &count);
    if (rc != OPT_OK) return rc == OPT_HELP ? 0 : rc;
    return render_backend_vulkan.describe() ? 0 : 1;
}
