/*
 * rtpipe_accel.c: building the acceleration structures (see rtpipe_accel.h).
 *
 * Sizes come from vkGetAccelerationStructureBuildSizesKHR; one scratch buffer serves both builds
 * (the barrier between them orders its reuse), its address rounded up to
 * minAccelerationStructureScratchOffsetAlignment. Geometry and the instance are uploaded through
 * vkrt's staging path; the builds read them, so a barrier makes the transfers visible first.
 */
#include "rtpipe_accel.h"

#include <stdlib.h>
#include <string.h>

#include "gpu/timer.h"
#include "gpu/vk_check.h"

static VkDeviceAddress align_up(VkDeviceAddress value, VkDeviceSize alignment)
{
    return alignment > 1 ? (value + alignment - 1) / alignment * alignment : value;
}

static int compare_doubles(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, compare_doubles);
    return v[n / 2];
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

/* Creates a structure of the given type and size on a buffer of its own. */
static bool create_structure(rtpipe_device *dev, VkAccelerationStructureTypeKHR type,
                             VkDeviceSize size, gpu_buffer *buffer,
                             VkAccelerationStructureKHR *structure, const char *what,
                             vkrt_error *err)
{
    if (!gpu_buffer_create_usage(&dev->ctx, buffer, (size_t)size,
                                 VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR |
                                     VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                 what, err))
        return false;
    VkAccelerationStructureCreateInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR,
        .buffer = buffer->buffer,
        .offset = 0, /* must be a multiple of 256 */
        .size = size,
        .type = type,
    };
    GPU_CHECK(dev->vk.create_accel(dev->ctx.device, &info, NULL, structure));
    return true;
fail:
    gpu_buffer_destroy(&dev->ctx, buffer);
    return false;
}

bool rtpipe_accel_create(rtpipe_device *dev, const float *positions, uint32_t triangle_count,
                         rtpipe_accel *accel, vkrt_error *err)
{
    memset(accel, 0, sizeof *accel);
    if (triangle_count == 0)
        return vkrt_error_set(err, "the scene has no triangles");
    if (triangle_count > dev->accel.maxPrimitiveCount)
        return vkrt_error_set(err, "%u triangles exceed %s's maxPrimitiveCount (%llu)",
                              triangle_count, dev->ctx.properties.deviceName,
                              (unsigned long long)dev->accel.maxPrimitiveCount);
    VkDevice device = dev->ctx.device;
    gpu_buffer vertices = {0}, instances = {0}, scratch = {0};
    gpu_timer timer = {0};
    bool ok = false;

    /* The geometry: the mesh's positions as they are, three vertices per triangle. */
    size_t vertex_bytes = (size_t)triangle_count * 9 * sizeof(float);
    const VkBufferUsageFlags input_usage =
        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
        VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (!gpu_buffer_create_usage(&dev->ctx, &vertices, vertex_bytes, input_usage, "vertices",
                                 err) ||
        !gpu_buffer_upload(&dev->ctx, &vertices, positions, vertex_bytes, err))
        goto done;
    VkAccelerationStructureGeometryKHR triangles = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR,
        .geometry.triangles = {
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR,
            .vertexFormat = VK_FORMAT_R32G32B32_SFLOAT,
            .vertexData.deviceAddress = rtpipe_buffer_address(dev, vertices.buffer),
            .vertexStride = 3 * sizeof(float),
            .maxVertex = 3 * triangle_count - 1,
            .indexType = VK_INDEX_TYPE_NONE_KHR,
        },
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
    VkAccelerationStructureBuildGeometryInfoKHR blas_info = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
        .type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
        .flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR,
        .mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR,
        .geometryCount = 1,
        .pGeometries = &triangles,
    };
    VkAccelerationStructureBuildSizesInfoKHR blas_sizes = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR,
    };
    dev->vk.build_sizes(device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &blas_info,
                        &triangle_count, &blas_sizes);
    if (blas_sizes.accelerationStructureSize == 0) {
        vkrt_error_set(err, "the driver gave a bottom-level structure size of 0");
        goto done;
    }
    if (!create_structure(dev, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                          blas_sizes.accelerationStructureSize, &accel->blas_buffer, &accel->blas,
                          "bottom-level acceleration structure", err))
        goto done;

    /* The one instance: the identity transform, every ray's mask, hit group 0. */
    VkAccelerationStructureDeviceAddressInfoKHR blas_address = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR,
        .accelerationStructure = accel->blas,
    };
    VkAccelerationStructureInstanceKHR instance = {
        .transform.matrix = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}},
        .instanceCustomIndex = 0,
        .mask = 0xFF,
        .instanceShaderBindingTableRecordOffset = 0,
        .flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR |
                 VK_GEOMETRY_INSTANCE_FORCE_OPAQUE_BIT_KHR,
        .accelerationStructureReference = dev->vk.accel_address(device, &blas_address),
    };
    if (!gpu_buffer_create_usage(&dev->ctx, &instances, sizeof instance, input_usage, "instance",
                                 err) ||
        !gpu_buffer_upload(&dev->ctx, &instances, &instance, sizeof instance, err))
        goto done;
    VkAccelerationStructureGeometryKHR instance_geometry = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR,
        .geometry.instances = {
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR,
            .arrayOfPointers = VK_FALSE,
            .data.deviceAddress = rtpipe_buffer_address(dev, instances.buffer),
        },
        .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
    };
    VkAccelerationStructureBuildGeometryInfoKHR tlas_info = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
        .type = VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR,
        .flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR,
        .mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR,
        .geometryCount = 1,
        .pGeometries = &instance_geometry,
    };
    uint32_t instance_count = 1;
    VkAccelerationStructureBuildSizesInfoKHR tlas_sizes = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR,
    };
    dev->vk.build_sizes(device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &tlas_info,
                        &instance_count, &tlas_sizes);
    if (!create_structure(dev, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR,
                          tlas_sizes.accelerationStructureSize, &accel->tlas_buffer, &accel->tlas,
                          "top-level acceleration structure", err))
        goto done;

    /* One scratch buffer for both builds, with room to round its address up. */
    VkDeviceSize scratch_alignment = dev->accel.minAccelerationStructureScratchOffsetAlignment;
    VkDeviceSize scratch_size = blas_sizes.buildScratchSize > tlas_sizes.buildScratchSize
                                    ? blas_sizes.buildScratchSize
                                    : tlas_sizes.buildScratchSize;
    if (!gpu_buffer_create_usage(&dev->ctx, &scratch, (size_t)(scratch_size + scratch_alignment),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                 "acceleration structure scratch", err))
        goto done;
    VkDeviceAddress scratch_address =
        align_up(rtpipe_buffer_address(dev, scratch.buffer), scratch_alignment);
    blas_info.dstAccelerationStructure = accel->blas;
    blas_info.scratchData.deviceAddress = scratch_address;
    tlas_info.dstAccelerationStructure = accel->tlas;
    tlas_info.scratchData.deviceAddress = scratch_address;
    VkAccelerationStructureBuildRangeInfoKHR blas_range = {.primitiveCount = triangle_count};
    VkAccelerationStructureBuildRangeInfoKHR tlas_range = {.primitiveCount = 1};
    const VkAccelerationStructureBuildRangeInfoKHR *blas_ranges = &blas_range,
                                                   *tlas_ranges = &tlas_range;

    /* The builds back to back, timestamps between: 2k before the BLAS of build k, 2k+1 between
     * it and the TLAS, 2k+2 after. */
    const VkPipelineStageFlags build_stage = VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
    const VkAccessFlags structure_access = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                                           VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
    if (!gpu_timer_create(&dev->ctx, &timer, 2 * RTPIPE_BUILD_RUNS + 1, err))
        goto done;
    VkCommandBuffer cmd;
    if (!gpu_commands_begin(&dev->ctx, &cmd, err))
        goto done;
    memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, build_stage,
                   VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    gpu_timer_reset(cmd, &timer);
    gpu_timer_write(cmd, &timer, 0);
    for (uint32_t k = 0; k < RTPIPE_BUILD_RUNS; ++k) {
        dev->vk.cmd_build_accel(cmd, 1, &blas_info, &blas_ranges);
        /* The TLAS build reads the BLAS and reuses the scratch memory. */
        memory_barrier(cmd, build_stage, structure_access, build_stage, structure_access);
        gpu_timer_write(cmd, &timer, 2 * k + 1);
        dev->vk.cmd_build_accel(cmd, 1, &tlas_info, &tlas_ranges);
        /* The next build rewrites the BLAS and the scratch the TLAS build used. */
        memory_barrier(cmd, build_stage, structure_access, build_stage, structure_access);
        gpu_timer_write(cmd, &timer, 2 * k + 2);
    }
    /* Every later trace reads the structures. */
    memory_barrier(cmd, build_stage, VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                   VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR,
                   VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    if (!gpu_commands_submit(&dev->ctx, err))
        goto done;
    double total[RTPIPE_BUILD_RUNS], blas[RTPIPE_BUILD_RUNS], tlas[RTPIPE_BUILD_RUNS];
    for (uint32_t k = 0; k < RTPIPE_BUILD_RUNS; ++k)
        if (!gpu_timer_ms(&dev->ctx, &timer, 2 * k, 2 * k + 2, &total[k], err) ||
            !gpu_timer_ms(&dev->ctx, &timer, 2 * k, 2 * k + 1, &blas[k], err) ||
            !gpu_timer_ms(&dev->ctx, &timer, 2 * k + 1, 2 * k + 2, &tlas[k], err))
            goto done;
    accel->build_ms_first = total[0];
    accel->build_ms = median(total, RTPIPE_BUILD_RUNS);
    accel->blas_ms = median(blas, RTPIPE_BUILD_RUNS);
    accel->tlas_ms = median(tlas, RTPIPE_BUILD_RUNS);
    accel->blas_bytes = blas_sizes.accelerationStructureSize;
    accel->tlas_bytes = tlas_sizes.accelerationStructureSize;
    accel->scratch_bytes = scratch_size;
    ok = true;
done:
    gpu_timer_destroy(&dev->ctx, &timer);
    gpu_buffer_destroy(&dev->ctx, &scratch);
    gpu_buffer_destroy(&dev->ctx, &instances);
    gpu_buffer_destroy(&dev->ctx, &vertices);
    if (!ok)
        rtpipe_accel_destroy(dev, accel);
    return ok;
}

void rtpipe_accel_destroy(rtpipe_device *dev, rtpipe_accel *accel)
{
    /* After a lost device nothing may be freed (see gpu_context.lost). */
    if (!dev->ctx.lost) {
        if (accel->tlas)
            dev->vk.destroy_accel(dev->ctx.device, accel->tlas, NULL);
        if (accel->blas)
            dev->vk.destroy_accel(dev->ctx.device, accel->blas, NULL);
    }
    gpu_buffer_destroy(&dev->ctx, &accel->tlas_buffer);
    gpu_buffer_destroy(&dev->ctx, &accel->blas_buffer);
    memset(accel, 0, sizeof *accel);
}
