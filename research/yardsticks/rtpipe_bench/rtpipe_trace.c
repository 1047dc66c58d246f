/*
 * rtpipe_trace.c: the ray tracing pipeline and its shader binding table (see rtpipe_trace.h).
 *
 * Shader groups, in the SBT's order: 0 raygen, 1 miss (closest-hit rays), 2 miss (shadow rays),
 * 3 the triangle hit group (closest.rchit). Each SBT record is a bare handle; records are
 * shaderGroupHandleSize rounded up to shaderGroupHandleAlignment apart, and each region starts
 * at a multiple of shaderGroupBaseAlignment (the buffer's address itself is rounded up to it).
 * The raygen region's size must equal its stride.
 * closest.rchit is specialized for the structures' hit numbering (rtpipe_accel.h), and reads
 * their instance_first buffer (always bound, whatever the numbering).
 */
#include "rtpipe_trace.h"

#include <stdlib.h>
#include <string.h>

#include "../../../glsl/shared.h"
#include "gpu/timer.h"
#include "gpu/vk_check.h"

/* BINDING_INSTANCE_FIRST: rtpipe_accel.instance_first, read by closest.rchit alone. */
enum { BINDING_SCENE, BINDING_RAYS, BINDING_HITS, BINDING_INSTANCE_FIRST, BINDING_COUNT };

/* The raygen shader's push constants. */
typedef struct trace_push {
    uint32_t count;
    uint32_t any_hit;
} trace_push;

static VkDeviceSize align_up(VkDeviceSize value, VkDeviceSize alignment)
{
    return alignment > 1 ? (value + alignment - 1) / alignment * alignment : value;
}

static bool create_layout(rtpipe_device *dev, rtpipe_tracer *t, vkrt_error *err)
{
    VkDevice device = dev->ctx.device;
    const VkShaderStageFlags raygen = VK_SHADER_STAGE_RAYGEN_BIT_KHR;
    VkDescriptorSetLayoutBinding bindings[BINDING_COUNT] = {
        {BINDING_SCENE, VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, 1, raygen, NULL},
        {BINDING_RAYS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, raygen, NULL},
        {BINDING_HITS, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, raygen, NULL},
        {BINDING_INSTANCE_FIRST, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1,
         VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR, NULL},
    };
    VkDescriptorSetLayoutCreateInfo set_info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = BINDING_COUNT,
        .pBindings = bindings,
    };
    GPU_CHECK(vkCreateDescriptorSetLayout(device, &set_info, NULL, &t->set_layout));
    VkPushConstantRange push = {.stageFlags = raygen, .size = sizeof(trace_push)};
    VkPipelineLayoutCreateInfo layout_info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 1,
        .pSetLayouts = &t->set_layout,
        .pushConstantRangeCount = 1,
        .pPushConstantRanges = &push,
    };
    GPU_CHECK(vkCreatePipelineLayout(device, &layout_info, NULL, &t->layout));
    VkDescriptorPoolSize sizes[] = {
        {VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR, 1},
        {VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 3},
    };
    VkDescriptorPoolCreateInfo pool_info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = 1,
        .poolSizeCount = 2,
        .pPoolSizes = sizes,
    };
    GPU_CHECK(vkCreateDescriptorPool(device, &pool_info, NULL, &t->pool));
    VkDescriptorSetAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorPool = t->pool,
        .descriptorSetCount = 1,
        .pSetLayouts = &t->set_layout,
    };
    GPU_CHECK(vkAllocateDescriptorSets(device, &alloc, &t->set));
    return true;
fail:
    return false;
}

static bool create_pipeline(rtpipe_device *dev, const rtpipe_shaders *shaders,
                            rtpipe_hit_numbering numbering, rtpipe_tracer *t, vkrt_error *err)
{
    /* closest.rchit's HIT_NUMBERING (constant_id 0). */
    uint32_t numbering_value = (uint32_t)numbering;
    VkSpecializationMapEntry numbering_entry = {0, 0, sizeof numbering_value};
    VkSpecializationInfo numbering_info = {1, &numbering_entry, sizeof numbering_value,
                                           &numbering_value};
    static const VkShaderStageFlagBits vk_stages[RTPIPE_STAGES] = {
        [RTPIPE_RAYGEN] = VK_SHADER_STAGE_RAYGEN_BIT_KHR,
        [RTPIPE_MISS] = VK_SHADER_STAGE_MISS_BIT_KHR,
        [RTPIPE_SHADOW_MISS] = VK_SHADER_STAGE_MISS_BIT_KHR,
        [RTPIPE_CLOSEST_HIT] = VK_SHADER_STAGE_CLOSEST_HIT_BIT_KHR,
    };
    VkDevice device = dev->ctx.device;
    VkShaderModule modules[RTPIPE_STAGES] = {0};
    VkPipelineShaderStageCreateInfo stages[RTPIPE_STAGES];
    VkRayTracingShaderGroupCreateInfoKHR groups[RTPIPE_STAGES];
    bool ok = false;
    for (int i = 0; i < RTPIPE_STAGES; ++i) {
        VkShaderModuleCreateInfo module_info = {
            .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
            .codeSize = shaders->words[i] * sizeof(uint32_t),
            .pCode = shaders->spirv[i],
        };
        GPU_CHECK(vkCreateShaderModule(device, &module_info, NULL, &modules[i]));
        stages[i] = (VkPipelineShaderStageCreateInfo){
            .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
            .stage = vk_stages[i],
            .module = modules[i],
            .pName = "main",
        };
        bool hit = i == RTPIPE_CLOSEST_HIT;
        if (hit)
            stages[i].pSpecializationInfo = &numbering_info;
        groups[i] = (VkRayTracingShaderGroupCreateInfoKHR){
            .sType = VK_STRUCTURE_TYPE_RAY_TRACING_SHADER_GROUP_CREATE_INFO_KHR,
            .type = hit ? VK_RAY_TRACING_SHADER_GROUP_TYPE_TRIANGLES_HIT_GROUP_KHR
                        : VK_RAY_TRACING_SHADER_GROUP_TYPE_GENERAL_KHR,
            .generalShader = hit ? VK_SHADER_UNUSED_KHR : (uint32_t)i,
            .closestHitShader = hit ? (uint32_t)i : VK_SHADER_UNUSED_KHR,
            .anyHitShader = VK_SHADER_UNUSED_KHR,
            .intersectionShader = VK_SHADER_UNUSED_KHR,
        };
    }
    VkRayTracingPipelineCreateInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_RAY_TRACING_PIPELINE_CREATE_INFO_KHR,
        .stageCount = RTPIPE_STAGES,
        .pStages = stages,
        .groupCount = RTPIPE_STAGES,
        .pGroups = groups,
        /* raygen traces; nothing traces from a hit or a miss */
        .maxPipelineRayRecursionDepth = 1,
        .layout = t->layout,
    };
    GPU_CHECK(dev->vk.create_pipelines(device, VK_NULL_HANDLE, VK_NULL_HANDLE, 1, &info, NULL,
                                       &t->pipeline));
    ok = true;
fail:
    for (int i = 0; i < RTPIPE_STAGES; ++i)
        if (modules[i])
            vkDestroyShaderModule(device, modules[i], NULL);
    return ok;
}

static bool create_sbt(rtpipe_device *dev, rtpipe_tracer *t, vkrt_error *err)
{
    const VkPhysicalDeviceRayTracingPipelinePropertiesKHR *p = &dev->pipeline;
    VkDeviceSize handle_size = p->shaderGroupHandleSize;
    VkDeviceSize base = p->shaderGroupBaseAlignment ? p->shaderGroupBaseAlignment : 1;
    VkDeviceSize stride = align_up(handle_size, p->shaderGroupHandleAlignment);
    if (handle_size == 0 || stride > p->maxShaderGroupStride)
        return vkrt_error_set(err, "%s: shader group handles of %llu bytes (stride %llu, at most "
                                   "%u) cannot make a shader binding table",
                              dev->ctx.properties.deviceName, (unsigned long long)handle_size,
                              (unsigned long long)stride, p->maxShaderGroupStride);
    VkDeviceSize raygen_size = align_up(stride, base);
    VkDeviceSize miss_size = align_up(2 * stride, base);
    VkDeviceSize hit_size = align_up(stride, base);
    VkDeviceSize miss_offset = raygen_size, hit_offset = raygen_size + miss_size;
    VkDeviceSize total = hit_offset + hit_size;

    uint8_t *handles = malloc(RTPIPE_STAGES * handle_size);
    uint8_t *table = calloc(1, total + base);
    bool ok = false;
    if (!handles || !table) {
        vkrt_error_set(err, "out of memory for the shader binding table");
        goto fail;
    }
    GPU_CHECK(dev->vk.group_handles(dev->ctx.device, t->pipeline, 0, RTPIPE_STAGES,
                                    RTPIPE_STAGES * handle_size, handles));
    if (!gpu_buffer_create_usage(&dev->ctx, &t->sbt, total + base,
                                 VK_BUFFER_USAGE_SHADER_BINDING_TABLE_BIT_KHR |
                                     VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
                                     VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                                 "shader binding table", err))
        goto fail;
    VkDeviceAddress address = rtpipe_buffer_address(dev, t->sbt.buffer);
    VkDeviceAddress start = align_up(address, base);
    uint8_t *at = table + (start - address);
    memcpy(at, handles + RTPIPE_RAYGEN * handle_size, handle_size);
    memcpy(at + miss_offset, handles + RTPIPE_MISS * handle_size, handle_size);
    memcpy(at + miss_offset + stride, handles + RTPIPE_SHADOW_MISS * handle_size, handle_size);
    memcpy(at + hit_offset, handles + RTPIPE_CLOSEST_HIT * handle_size, handle_size);
    if (!gpu_buffer_upload(&dev->ctx, &t->sbt, table, total + base, err))
        goto fail;
    t->raygen_region = (VkStridedDeviceAddressRegionKHR){start, raygen_size, raygen_size};
    t->miss_region = (VkStridedDeviceAddressRegionKHR){start + miss_offset, stride, miss_size};
    t->hit_region = (VkStridedDeviceAddressRegionKHR){start + hit_offset, stride, hit_size};
    t->callable_region = (VkStridedDeviceAddressRegionKHR){0, 0, 0};
    ok = true;
fail:
    free(handles);
    free(table);
    return ok;
}

bool rtpipe_tracer_create(rtpipe_device *dev, const rtpipe_shaders *shaders,
                          const rtpipe_accel *accel, uint32_t capacity, rtpipe_tracer *t,
                          vkrt_error *err)
{
    memset(t, 0, sizeof *t);
    const VkPhysicalDeviceLimits *limits = &dev->ctx.properties.limits;
    uint64_t max_width =
        (uint64_t)limits->maxComputeWorkGroupCount[0] * limits->maxComputeWorkGroupSize[0];
    uint64_t max_height =
        (uint64_t)limits->maxComputeWorkGroupCount[1] * limits->maxComputeWorkGroupSize[1];
    if (max_width > dev->pipeline.maxRayDispatchInvocationCount)
        max_width = dev->pipeline.maxRayDispatchInvocationCount;
    t->max_width = max_width > UINT32_MAX ? UINT32_MAX : (uint32_t)max_width;
    t->max_height = max_height > UINT32_MAX ? UINT32_MAX : (uint32_t)max_height;
    t->capacity = capacity ? capacity : 1;
    if (dev->pipeline.maxRayRecursionDepth < 1) {
        vkrt_error_set(err, "%s: maxRayRecursionDepth is 0", dev->ctx.properties.deviceName);
        return false;
    }
    if (!create_layout(dev, t, err) || !create_pipeline(dev, shaders, accel->numbering, t, err) ||
        !create_sbt(dev, t, err) ||
        !gpu_buffer_create(&dev->ctx, &t->rays, (size_t)t->capacity * sizeof(Ray), "rays", err) ||
        !gpu_buffer_create(&dev->ctx, &t->hits, (size_t)t->capacity * sizeof(Hit), "hits", err)) {
        rtpipe_tracer_destroy(dev, t);
        return false;
    }
    VkWriteDescriptorSetAccelerationStructureKHR scene = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET_ACCELERATION_STRUCTURE_KHR,
        .accelerationStructureCount = 1,
        .pAccelerationStructures = &accel->tlas,
    };
    VkDescriptorBufferInfo rays = {t->rays.buffer, 0, VK_WHOLE_SIZE};
    VkDescriptorBufferInfo hits = {t->hits.buffer, 0, VK_WHOLE_SIZE};
    VkDescriptorBufferInfo instance_first = {accel->instance_first.buffer, 0, VK_WHOLE_SIZE};
    VkWriteDescriptorSet writes[BINDING_COUNT] = {
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .pNext = &scene, .dstSet = t->set,
         .dstBinding = BINDING_SCENE, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_ACCELERATION_STRUCTURE_KHR},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = t->set,
         .dstBinding = BINDING_RAYS, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &rays},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = t->set,
         .dstBinding = BINDING_HITS, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &hits},
        {.sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET, .dstSet = t->set,
         .dstBinding = BINDING_INSTANCE_FIRST, .descriptorCount = 1,
         .descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .pBufferInfo = &instance_first},
    };
    vkUpdateDescriptorSets(dev->ctx.device, BINDING_COUNT, writes, 0, NULL);
    return true;
}

static void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags src_stage,
                           VkAccessFlags src_access, VkPipelineStageFlags dst_stage,
                           VkAccessFlags dst_access)
{
    VkMemoryBarrier barrier = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = src_access,
        .dstAccessMask = dst_access,
    };
    vkCmdPipelineBarrier(cmd, src_stage, dst_stage, 0, 1, &barrier, 0, NULL, 0, NULL);
}

bool rtpipe_tracer_trace(rtpipe_device *dev, rtpipe_tracer *t, const Ray *rays, uint32_t count,
                         bool any_hit, Hit *hits, uint32_t repeats, double *gpu_ms,
                         vkrt_error *err)
{
    if (count > t->capacity)
        return vkrt_error_set(err, "%u rays exceed the tracer's %u", count, t->capacity);
    if (count == 0)
        return true;
    if (repeats == 0)
        repeats = 1;
    /* A 1D launch of count rays, or rows of the widest launch the device allows. */
    uint32_t width = count < t->max_width ? count : t->max_width;
    uint32_t height = (uint32_t)(((uint64_t)count + width - 1) / width);
    if (height > t->max_height ||
        (uint64_t)width * height > dev->pipeline.maxRayDispatchInvocationCount)
        return vkrt_error_set(err, "%u rays need a launch of %u x %u, more than %s allows "
                                   "(maxRayDispatchInvocationCount %u)",
                              count, width, height, dev->ctx.properties.deviceName,
                              dev->pipeline.maxRayDispatchInvocationCount);
    trace_push push = {count, any_hit ? 1u : 0u};
    gpu_timer timer = {0};
    if (!gpu_buffer_upload(&dev->ctx, &t->rays, rays, (size_t)count * sizeof *rays, err) ||
        (gpu_ms && !gpu_timer_create(&dev->ctx, &timer, repeats + 1, err)))
        return false;
    const VkPipelineStageFlags rt_stage = VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR;
    VkCommandBuffer cmd;
    bool ok = gpu_commands_begin(&dev->ctx, &cmd, err);
    if (ok) {
        /* The upload's rays, and the last trace's reads of the hits (a download), come first. */
        memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT,
                       rt_stage, VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT);
        vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, t->pipeline);
        vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_RAY_TRACING_KHR, t->layout, 0, 1,
                                &t->set, 0, NULL);
        vkCmdPushConstants(cmd, t->layout, VK_SHADER_STAGE_RAYGEN_BIT_KHR, 0, sizeof push,
                           &push);
        /* Back to back in one submission, as vkrt_renderer_trace does, so the GPU never idles
         * between repeats. */
        if (gpu_ms) {
            gpu_timer_reset(cmd, &timer);
            gpu_timer_write(cmd, &timer, 0);
        }
        for (uint32_t i = 0; i < repeats; ++i) {
            dev->vk.cmd_trace_rays(cmd, &t->raygen_region, &t->miss_region, &t->hit_region,
                                   &t->callable_region, width, height, 1);
            /* Each run rewrites the hits: runs do not overlap, as vkrt's dispatches do not. */
            memory_barrier(cmd, rt_stage, VK_ACCESS_SHADER_WRITE_BIT,
                           rt_stage | VK_PIPELINE_STAGE_TRANSFER_BIT,
                           VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                               VK_ACCESS_TRANSFER_READ_BIT);
            if (gpu_ms)
                gpu_timer_write(cmd, &timer, i + 1);
        }
        ok = gpu_commands_submit(&dev->ctx, err);
        for (uint32_t i = 0; ok && gpu_ms && i < repeats; ++i)
            ok = gpu_timer_ms(&dev->ctx, &timer, i, i + 1, &gpu_ms[i], err);
        ok = ok && gpu_buffer_download(&dev->ctx, &t->hits, hits, (size_t)count * sizeof *hits,
                                       err);
    }
    gpu_timer_destroy(&dev->ctx, &timer);
    return ok;
}

void rtpipe_tracer_destroy(rtpipe_device *dev, rtpipe_tracer *t)
{
    gpu_buffer_destroy(&dev->ctx, &t->hits);
    gpu_buffer_destroy(&dev->ctx, &t->rays);
    gpu_buffer_destroy(&dev->ctx, &t->sbt);
    if (!dev->ctx.lost && dev->ctx.device) {
        if (t->pipeline)
            vkDestroyPipeline(dev->ctx.device, t->pipeline, NULL);
        if (t->pool)
            vkDestroyDescriptorPool(dev->ctx.device, t->pool, NULL);
        if (t->layout)
            vkDestroyPipelineLayout(dev->ctx.device, t->layout, NULL);
        if (t->set_layout)
            vkDestroyDescriptorSetLayout(dev->ctx.device, t->set_layout, NULL);
    }
    memset(t, 0, sizeof *t);
}
