/*
 * rtpipe_device.c: the ray tracing device (see rtpipe_device.h).
 *
 * vkrt's context asks for Vulkan 1.1, so every extension that Vulkan 1.2 took into core and the
 * ray tracing extensions require is enabled by name: VK_KHR_acceleration_structure requires
 * VK_EXT_descriptor_indexing, VK_KHR_buffer_device_address and VK_KHR_deferred_host_operations;
 * VK_KHR_ray_tracing_pipeline requires VK_KHR_spirv_1_4, which requires
 * VK_KHR_shader_float_controls. Drivers keep advertising promoted extensions, so this works on a
 * Vulkan 1.4 driver too.
 */
#include "rtpipe_device.h"

#include <string.h>

/* The ray tracing pipeline first: on a device without ray tracing it is the one named. */
static const char *const extensions[] = {
    VK_KHR_RAY_TRACING_PIPELINE_EXTENSION_NAME,
    VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME,
    VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME,
    VK_KHR_BUFFER_DEVICE_ADDRESS_EXTENSION_NAME,
    VK_EXT_DESCRIPTOR_INDEXING_EXTENSION_NAME,
    VK_KHR_SPIRV_1_4_EXTENSION_NAME,
    VK_KHR_SHADER_FLOAT_CONTROLS_EXTENSION_NAME,
};

static bool load_functions(rtpipe_device *dev, vkrt_error *err)
{
    VkDevice device = dev->ctx.device;
    rtpipe_functions *f = &dev->vk;
#define LOAD(field, name)                                                                     \
    do {                                                                                      \
        f->field = (PFN_##name)vkGetDeviceProcAddr(device, #name);                            \
        if (!f->field)                                                                        \
            return vkrt_error_set(err, "%s: vkGetDeviceProcAddr found no %s",                 \
                                  dev->ctx.properties.deviceName, #name);                     \
    } while (0)
    LOAD(get_buffer_address, vkGetBufferDeviceAddressKHR);
    LOAD(create_accel, vkCreateAccelerationStructureKHR);
    LOAD(destroy_accel, vkDestroyAccelerationStructureKHR);
    LOAD(build_sizes, vkGetAccelerationStructureBuildSizesKHR);
    LOAD(accel_address, vkGetAccelerationStructureDeviceAddressKHR);
    LOAD(cmd_build_accel, vkCmdBuildAccelerationStructuresKHR);
    LOAD(create_pipelines, vkCreateRayTracingPipelinesKHR);
    LOAD(group_handles, vkGetRayTracingShaderGroupHandlesKHR);
    LOAD(cmd_trace_rays, vkCmdTraceRaysKHR);
#undef LOAD
    return true;
}

rtpipe_device_status rtpipe_device_create(rtpipe_device *dev, int device_index, bool validation,
                                          vkrt_error *err)
{
    memset(dev, 0, sizeof *dev);
    VkPhysicalDeviceBufferDeviceAddressFeatures address = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_BUFFER_DEVICE_ADDRESS_FEATURES,
        .bufferDeviceAddress = VK_TRUE,
    };
    VkPhysicalDeviceAccelerationStructureFeaturesKHR accel = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR,
        .pNext = &address,
        .accelerationStructure = VK_TRUE,
    };
    VkPhysicalDeviceRayTracingPipelineFeaturesKHR pipeline = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_FEATURES_KHR,
        .pNext = &accel,
        .rayTracingPipeline = VK_TRUE,
    };
    gpu_context_desc desc = {
        .device_index = device_index,
        .validation = validation,
        .device_extensions = extensions,
        .device_extension_count = sizeof extensions / sizeof *extensions,
        .device_features = &pipeline,
    };
    if (!gpu_context_create(&dev->ctx, &desc, err))
        return RTPIPE_DEVICE_FAILED;
    if (dev->ctx.missing_extension) {
        vkrt_error_set(err, "%s has no %s", dev->ctx.properties.deviceName,
                       dev->ctx.missing_extension);
        gpu_context_destroy(&dev->ctx);
        return RTPIPE_DEVICE_UNSUPPORTED;
    }
    dev->accel = (VkPhysicalDeviceAccelerationStructurePropertiesKHR){
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR,
    };
    dev->pipeline = (VkPhysicalDeviceRayTracingPipelinePropertiesKHR){
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_TRACING_PIPELINE_PROPERTIES_KHR,
        .pNext = &dev->accel,
    };
    VkPhysicalDeviceProperties2 properties = {
        .sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2,
        .pNext = &dev->pipeline,
    };
    vkGetPhysicalDeviceProperties2(dev->ctx.physical, &properties);
    dev->pipeline.pNext = NULL;
    if (!load_functions(dev, err)) {
        gpu_context_destroy(&dev->ctx);
        memset(dev, 0, sizeof *dev);
        return RTPIPE_DEVICE_FAILED;
    }
    return RTPIPE_DEVICE_OK;
}

VkDeviceAddress rtpipe_buffer_address(const rtpipe_device *dev, VkBuffer buffer)
{
    VkBufferDeviceAddressInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO,
        .buffer = buffer,
    };
    return dev->vk.get_buffer_address(dev->ctx.device, &info);
}

bool rtpipe_device_finish(rtpipe_device *dev, vkrt_error *err)
{
    bool ok = gpu_context_finish(&dev->ctx, err);
    memset(&dev->vk, 0, sizeof dev->vk);
    return ok;
}
