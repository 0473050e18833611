/* assimp_lib.c: opens assimp (TRAZADOR_ASSIMP_SONAME, the library the build's headers belong to)
 * and looks up the functions of assimp_lib.h. */
#include "scene/assimp_lib.h"

#include <dlfcn.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <string.h>

static assimp_lib lib;
static bool opened;
static char why[256];
static pthread_once_t once = PTHREAD_ONCE_INIT;

/* Looks function `name` up in the library into *slot; false (why set) when it lacks it. */
static bool find(void *handle, const char *name, void *slot) {
    void *f = dlsym(handle, name);
    if (!f) {
        snprintf(why, sizeof why, "%s has no %s", TRAZADOR_ASSIMP_SONAME, name);
        return false;
    }
    memcpy(slot, &f, sizeof f); /* a data pointer's bits as a function pointer's, as dlsym means */
    return true;
}

static void open_library(void) {
    void *handle = dlopen(TRAZADOR_ASSIMP_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
        const char *e = dlerror();
        snprintf(why, sizeof why, "cannot open assimp: %s", e ? e : TRAZADOR_ASSIMP_SONAME);
        return;
    }
    opened = find(handle, "aiImportFileEx", &lib.import_file_ex) &&
             find(handle, "aiApplyPostProcessing", &lib.apply_post_processing) &&
             find(handle, "aiReleaseImport", &lib.release_import) &&
             find(handle, "aiGetErrorString", &lib.get_error_string) &&
             find(handle, "aiIsExtensionSupported", &lib.is_extension_supported) &&
             find(handle, "aiGetMaterialColor", &lib.get_material_color) &&
             find(handle, "aiGetMaterialString", &lib.get_material_string) &&
             find(handle, "aiGetMaterialFloatArray", &lib.get_material_float_array) &&
             find(handle, "aiGetMaterialIntegerArray", &lib.get_material_integer_array) &&
             find(handle, "aiGetMaterialTextureCount", &lib.get_material_texture_count) &&
             find(handle, "aiGetImportFormatCount", &lib.get_import_format_count) &&
             find(handle, "aiGetImportFormatDescription", &lib.get_import_format_description);
}

const assimp_lib *assimp_lib_open(char *error, size_t error_size) {
    pthread_once(&once, open_library);
    if (!opened) snprintf(error, error_size, "%s", why);
    return opened ? &lib : NULL;
}
