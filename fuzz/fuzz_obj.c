/*
 * fuzz_obj.c: libFuzzer target for the OBJ loader (vkrt_obj_parse, tinyobjloader underneath).
 *
 * Each input is the whole text of an OBJ. base_dir is NULL so mtllib lines read no file: every
 * input is parsed from memory only, which keeps runs fast and reproducible. The model is freed
 * whatever the outcome, so LeakSanitizer flags anything the loader itself leaks.
 *
 * One thread, as vkrt_obj_parse_split allows: the default asks std::thread::hardware_concurrency
 * how many cores there are at every parallel step, which glibc answers by opening and reading
 * /sys/devices/system/cpu/online (five times an input, a large part of a short input's cost), and
 * a short input is one chunk, read on the calling thread either way.
 */
#include <stddef.h>
#include <stdint.h>

#include "scene/obj/obj_load.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vkrt_model model;
    vkrt_error err;
    vkrt_obj_parse_split((const char *)data, size, "fuzz.obj", NULL, 0, 1, &model, &err);
    vkrt_model_free(&model); /* also correct after a failure: the model is then zeroed */
    return 0;
}
