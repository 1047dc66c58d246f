/*
 * fuzz_obj.c: libFuzzer target for the OBJ loader (vkrt_obj_parse, tinyobjloader underneath).
 *
 * Each input is the whole text of an OBJ. base_dir is NULL so mtllib lines read no file: every
 * input is parsed from memory only, which keeps runs fast and reproducible. The model is freed
 * whatever the outcome, so LeakSanitizer flags anything the loader itself leaks.
 */
#include <stddef.h>
#include <stdint.h>

#include "scene/obj/obj_load.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vkrt_model model;
    vkrt_error err;
    vkrt_obj_parse((const char *)data, size, "fuzz.obj", NULL, &model, &err);
    vkrt_model_free(&model); /* also correct after a failure: the model is then zeroed */
    return 0;
}
