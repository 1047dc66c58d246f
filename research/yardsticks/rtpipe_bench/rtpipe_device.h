/*
 * rtpipe_device.h: a vkrt gpu_context with what the driver's ray tracing pipeline needs:
 * VK_KHR_ray_tracing_pipeline, VK_KHR_acceleration_structure and the extensions they require,
 * with rayTracingPipeline, accelerationStructure and bufferDeviceAddress on; the extension
 * functions (which the Vulkan loader does not export) and the device's ray tracing limits.
 */
#ifndef RTPIPE_DEVICE_H
#define RTPIPE_DEVICE_H

#include <stdbool.h>
#include <vulkan/vulkan.h>

#include "error.h"
#include "gpu/context.h"

typedef struct rtpipe_functions {
    PFN_vkGetBufferDeviceAddressKHR get_buffer_address;
    PFN_vkCreateAccelerationStructureKHR create_accel;
    PFN_vkDestroyAccelerationStructureKHR destroy_accel;
    PFN_vkGetAccelerationStructureBuildSizesKHR build_sizes;
    PFN_vkGetAccelerationStructureDeviceAddressKHR accel_address;
    PFN_vkCmdBuildAccelerationStructuresKHR cmd_build_accel;
    PFN_vkCreateRayTracingPipelinesKHR create_pipelines;
    PFN_vkGetRayTracingShaderGroupHandlesKHR group_handles;
    PFN_vkCmdTraceRaysKHR cmd_trace_rays;
} rtpipe_functions;

typedef struct rtpipe_device {
    gpu_context ctx;
    rtpipe_functions vk;
    VkPhysicalDeviceRayTracingPipelinePropertiesKHR pipeline;
    VkPhysicalDeviceAccelerationStructurePropertiesKHR accel;
} rtpipe_device;

typedef enum rtpipe_device_status {
    RTPIPE_DEVICE_OK,
    RTPIPE_DEVICE_UNSUPPORTED, /* the device lacks an extension; err says which */
    RTPIPE_DEVICE_FAILED,
} rtpipe_device_status;

/* Creates the device: device_index as vkrt's --device (-1: the first discrete GPU, else the first
 * device), validation as vkrt's --validation. On anything but RTPIPE_DEVICE_OK err holds one line
 * (for UNSUPPORTED: "<device> has no <extension>") and nothing is left allocated. */
rtpipe_device_status rtpipe_device_create(rtpipe_device *dev, int device_index, bool validation,
                                          vkrt_error *err);

/* The device address of a buffer created with VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT. */
VkDeviceAddress rtpipe_buffer_address(const rtpipe_device *dev, VkBuffer buffer);

/* Destroys the device like gpu_context_finish: false with a message if validation reported
 * anything. Safe on a zeroed device. */
bool rtpipe_device_finish(rtpipe_device *dev, vkrt_error *err);

#endif
