/*
 * fuzz_obj.c: libFuzzer target for the OBJ loader (vkrt_obj_parse, tinyobjloader underneath).
 *
 * Each input is the whole text of an OBJ. base_dir is NULL so mtllib lines read no file: every
 * input is parsed from memory only, which keeps runs fast and reproducible. The mesh is freed
 * whatever the outcome, so LeakSanitizer flags anything the loader itself leaks.
 */
#include <stddef.h>
#include <stdint.h>

#include "scene/obj_load.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vkrt_mesh mesh;
    vkrt_error err;
    vkrt_obj_parse((const char *)data, size, "fuzz.obj", NULL, &mesh, &err);
    vkrt_mesh_free(&mesh); /* also correct after a failure: the mesh is then zeroed */
    return 0;
}
