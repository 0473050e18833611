/* assimp_lib.h: the functions of assimp's C API that the mesh loader calls, from the library
 * opened on first use (assimp_lib.c): linked into the binary, assimp and the C++ libraries it
 * needs made every trazador process start 9 ms slower, scenes without meshes included. */
#ifndef TRAZADOR_ASSIMP_LIB_H
#define TRAZADOR_ASSIMP_LIB_H

#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/material.h>
#include <stddef.h>

/* Each member has the type of a pointer to the assimp function it is named after. */
typedef struct assimp_lib {
    __typeof__(&aiImportFileEx) import_file_ex;
    __typeof__(&aiApplyPostProcessing) apply_post_processing;
    __typeof__(&aiReleaseImport) release_import;
    __typeof__(&aiGetErrorString) get_error_string;
    __typeof__(&aiIsExtensionSupported) is_extension_supported;
    __typeof__(&aiGetMaterialColor) get_material_color;
    __typeof__(&aiGetMaterialString) get_material_string;
    __typeof__(&aiGetMaterialFloatArray) get_material_float_array;
    __typeof__(&aiGetMaterialIntegerArray) get_material_integer_array;
    __typeof__(&aiGetMaterialTextureCount) get_material_texture_count;
    __typeof__(&aiGetImportFormatCount) get_import_format_count;
    __typeof__(&aiGetImportFormatDescription) get_import_format_description;
} assimp_lib;

/* assimp's functions, the library opened once a process (thread-safe); NULL when it cannot be,
 * with why in error. */
const assimp_lib *assimp_lib_open(char *error, size_t error_size);

#endif
