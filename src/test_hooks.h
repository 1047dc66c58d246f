/*
 * test_hooks.h: the switches tests and benchmarks set from the environment, in one place.
 *
 * Each hook is a VKRT_TEST_* variable that makes a capable device behave like a lesser one, or
 * points vkrt at something other than what it ships, so that a test can reach a code path the
 * machine would not take by itself. test_hooks.c's table names every hook, what it does and which
 * test or tool sets it. The environment is read once, on the first call; a product run that sets
 * none behaves as if this module did not exist. User-facing settings (VKRT_CACHE_DIR,
 * VKRT_SCENE_CACHE_DIR, VKRT_WRITE_THREADS, VKRT_VALIDATION) are not hooks and are read where they
 * are used.
 */
#ifndef VKRT_TEST_HOOKS_H
#define VKRT_TEST_HOOKS_H

#include <stdbool.h>
#include <stdint.h>

typedef struct vkrt_test_hooks {
    bool no_float_atomics;        /* VKRT_TEST_NO_FLOAT_ATOMICS: add to pixels by compare-and-swap */
    bool no_device_addresses;     /* VKRT_TEST_NO_DEVICE_ADDRESSES: leave device addresses off */
    bool no_subgroups;            /* VKRT_TEST_NO_SUBGROUPS: kernels without subgroup operations */
    bool sync_validation;         /* VKRT_TEST_SYNC_VALIDATION: the layer's hazard checks too */
    uint64_t device_memory_limit; /* VKRT_TEST_DEVICE_MEMORY_LIMIT: bytes of device memory to
                                     pretend to have; 0: the device's own */
    uint64_t max_buffer_bytes;    /* VKRT_TEST_MAX_BUFFER_BYTES: split arrays past this many bytes
                                     (at least 128); 0: where the device needs it */
    double gpu_timeout_s;         /* VKRT_TEST_GPU_TIMEOUT: seconds before a submission counts as
                                     hung; 0: the default */
    int material_order;           /* VKRT_TEST_MATERIAL_ORDER: 0 or 1 forces hits grouped by
                                     shader off or on; -1: the tuning's choice */
    const char *glsl_dir;         /* VKRT_TEST_GLSL_DIR: read kernels from this folder instead of
                                     the embedded ones; NULL: the embedded ones */
} vkrt_test_hooks;

/* The hooks as the environment set them when this was first called (thread-safe); a malformed
 * value counts as unset. */
const vkrt_test_hooks *vkrt_test_hooks_get(void);

#endif
