/*
 * vk_check.h: the one way vkrt checks a Vulkan result.
 *
 * GPU_CHECK(call) runs call; on anything but VK_SUCCESS it fills the vkrt_error *err in scope with
 * the source file, line, the call's text and the result's name (VK_ERROR_OUT_OF_DEVICE_MEMORY,
 * not -2), then jumps to the function's `fail:` label, which frees what the function took.
 */
#ifndef VKRT_VK_CHECK_H
#define VKRT_VK_CHECK_H

#include <vulkan/vulkan.h>

#include "../error.h"

/* The enumerator's name for a VkResult, e.g. "VK_ERROR_DEVICE_LOST". */
const char *gpu_result_name(VkResult result);

#define GPU_CHECK(call)                                                                     \
    do {                                                                                    \
        VkResult gpu_check_result_ = (call);                                                \
        if (gpu_check_result_ != VK_SUCCESS) {                                              \
            vkrt_error_set(err, "%s:%d: %s failed: %s", __FILE__, __LINE__, #call,          \
                           gpu_result_name(gpu_check_result_));                             \
            goto fail;                                                                      \
        }                                                                                   \
    } while (0)

#endif
