/* test_hooks.c: the VKRT_TEST_* switches, read once (see test_hooks.h). */
#include "test_hooks.h"

#include <pthread.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

typedef enum hook_kind { HOOK_FLAG, HOOK_BYTES, HOOK_SECONDS, HOOK_CHOICE, HOOK_PATH } hook_kind;

/* Every hook: its variable, how its value reads, where it lands, what it does, who sets it. */
typedef struct hook {
    const char *name;
    hook_kind kind;
    size_t offset;
    const char *what;
    const char *users;
} hook;

#define AT(field) offsetof(vkrt_test_hooks, field)
static const hook hooks[] = {
    {"VKRT_TEST_NO_FLOAT_ATOMICS", HOOK_FLAG, AT(no_float_atomics),
     "pixels add by compare-and-swap, as on devices without float atomics",
     "by hand, to try the fallback on a device that has them"},
    {"VKRT_TEST_NO_DEVICE_ADDRESSES", HOOK_FLAG, AT(no_device_addresses),
     "buffer device addresses stay off: a split scene gets the message such devices give",
     "tests/test_split.sh"},
    {"VKRT_TEST_NO_SUBGROUPS", HOOK_FLAG, AT(no_subgroups),
     "kernels built without subgroup operations, as on devices without them",
     "by hand, to try the fallback on a device that has them"},
    {"VKRT_TEST_SYNC_VALIDATION", HOOK_FLAG, AT(sync_validation),
     "with validation on, the layer's synchronization checks too (slow)", "tests/meson.build"},
    {"VKRT_TEST_DEVICE_MEMORY_LIMIT", HOOK_BYTES, AT(device_memory_limit),
     "pretend the device has at most this many bytes (a small device)",
     "tests/test_cli.sh, tests/test_split.sh"},
    {"VKRT_TEST_MAX_BUFFER_BYTES", HOOK_BYTES, AT(max_buffer_bytes),
     "split arrays larger than this many bytes (at least 128), so small scenes split",
     "tests/test_split.sh, tests/test_scene_cache.sh, research/gpu-run"},
    {"VKRT_TEST_GPU_TIMEOUT", HOOK_SECONDS, AT(gpu_timeout_s),
     "seconds a submission may run before it counts as hung", "tests/test_cli.sh"},
    {"VKRT_TEST_MATERIAL_ORDER", HOOK_CHOICE, AT(material_order),
     "0 or 1: hits grouped by shader off or on, whatever the device",
     "tests/test_order.sh, research/gpu-run"},
    {"VKRT_TEST_GLSL_DIR", HOOK_PATH, AT(glsl_dir),
     "kernels read from this folder instead of the embedded ones (edit without rebuilding)",
     "research/gpu-run and research/cpu-run (kernel variants)"},
};
#undef AT

static vkrt_test_hooks values;
static pthread_once_t once = PTHREAD_ONCE_INIT;

/* Sets the field of h from text; a value that does not read as h's kind leaves it unset. */
static void read_hook(const hook *h, const char *text, vkrt_test_hooks *out)
{
    char *field = (char *)out + h->offset;
    char *end = NULL;
    switch (h->kind) {
    case HOOK_FLAG:
        *(bool *)field = strcmp(text, "0") != 0;
        break;
    case HOOK_BYTES: {
        unsigned long long bytes = strtoull(text, &end, 10);
        if (*end == '\0')
            *(uint64_t *)field = bytes;
        break;
    }
    case HOOK_SECONDS: {
        double seconds = strtod(text, &end);
        if (end != text && seconds > 0)
            *(double *)field = seconds;
        break;
    }
    case HOOK_CHOICE:
        if ((text[0] == '0' || text[0] == '1') && text[1] == '\0')
            *(int *)field = text[0] - '0';
        break;
    case HOOK_PATH:
        *(const char **)field = text;
        break;
    }
}

static void read_all(void)
{
    values.material_order = -1;
    for (size_t i = 0; i < sizeof hooks / sizeof *hooks; ++i) {
        const char *text = getenv(hooks[i].name);
        if (text && *text)
            read_hook(&hooks[i], text, &values);
    }
}

const vkrt_test_hooks *vkrt_test_hooks_get(void)
{
    pthread_once(&once, read_all);
    return &values;
}
