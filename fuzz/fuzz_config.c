/*
 * fuzz_config.c: libFuzzer target for the scene.cfg parser (vkrt_config_parse).
 *
 * Each input is taken as the whole text of a scene.cfg. The parser must either succeed or fail
 * with a message; AddressSanitizer/UBSan catch memory and undefined-behaviour bugs, and
 * LeakSanitizer (on by default under libFuzzer) catches anything a failed or successful parse
 * leaves allocated. Nothing touches the file system: relative paths are only joined, not opened.
 */
#include <stddef.h>
#include <stdint.h>

#include "scene/config.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    vkrt_config cfg;
    vkrt_error err;
    /* A fixed base_dir exercises the path joining without depending on the working folder. */
    vkrt_config_parse((const char *)data, size, "fuzz.cfg", "scenes/fuzz", &cfg, &err);
    /* After a failure *cfg is left empty (nothing to free), so one unconditional free is right in
     * both cases; anything still allocated afterwards is the parser's leak, reported by LSan. */
    vkrt_config_free(&cfg);
    return 0;
}
