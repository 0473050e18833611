/* assimp_lib.c: opens assimp (TRAZADOR_ASSIMP_SONAME, the library the build's headers belong to)
 * and looks up the functions of assimp_lib.h. */
#include "scene/assimp_lib.h"

#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>

#include "util/run_time_lib.h"

static assimp_lib lib;
static bool opened;
static char why[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void open_library(void) {
    const run_time_symbol symbols[] = {
        {"aiImportFileEx", &lib.import_file_ex},
        {"aiApplyPostProcessing", &lib.apply_post_processing},
        {"aiReleaseImport", &lib.release_import},
        {"aiGetErrorString", &lib.get_error_string},
        {"aiIsExtensionSupported", &lib.is_extension_supported},
        {"aiGetMaterialColor", &lib.get_material_color},
        {"aiGetMaterialString", &lib.get_material_string},
        {"aiGetMaterialFloatArray", &lib.get_material_float_array},
        {"aiGetMaterialIntegerArray", &lib.get_material_integer_array},
        {"aiGetMaterialTextureCount", &lib.get_material_texture_count},
        {"aiGetImportFormatCount", &lib.get_import_format_count},
        {"aiGetImportFormatDescription", &lib.get_import_format_description},
    };
    opened = run_time_lib_open(TRAZADOR_ASSIMP_SONAME, "assimp", symbols,
                               (int)(sizeof symbols / sizeof *symbols), why, sizeof why);
}

const assimp_lib *assimp_lib_open(char *error, size_t error_size) {
    pthread_once(&once, open_library);
    if (!opened) snprintf(error, error_size, "%s", why);
    return opened ? &lib : NULL;
}
