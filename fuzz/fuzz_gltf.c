/*
 * fuzz_gltf.c: libFuzzer target for the glTF loader (vkrt_gltf_parse, tinygltf underneath).
 *
 * Each input is a whole .gltf or .glb (told apart by its first bytes). base_dir is NULL, so an
 * external buffer is an error and external images are not looked for: every input is parsed from
 * memory only. The model is freed whatever the outcome, so LeakSanitizer flags anything the
 * loader leaks. tinygltf itself is Debian's shared library, not instrumented: the coverage is
 * the loader's own checks, which stand between tinygltf's parse and every read of a buffer.
 */
#include <stddef.h>
#include <stdint.h>

#include "scene/gltf/gltf_load.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vkrt_model model;
    vkrt_error err;
    vkrt_gltf_parse(data, size, "fuzz.gltf", NULL, NULL, &model, &err);
    vkrt_model_free(&model); /* also correct after a failure: the model is then zeroed */
    return 0;
}
