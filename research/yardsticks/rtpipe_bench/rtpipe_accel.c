/*
 * rtpipe_accel.c: building the acceleration structures (see rtpipe_accel.h).
 *
 * Both forms go through one builder (build): the BLASes' vertices in one buffer, each mesh at its
 * own offset; the BLASes in one buffer, each at a multiple of 256 bytes; sizes from
 * vkGetAccelerationStructureBuildSizesKHR. One scratch buffer serves every build, its address
 * rounded up to minAccelerationStructureScratchOffsetAlignment: the BLASes, built in one call,
 * each take a slice of their own (builds in one call must not share scratch), and the TLAS build
 * reuses it from the start after a barrier. With one mesh and one instance this is the flat form
 * exactly as it was before the two-level one came: one BLAS at offset 0 of its buffer, scratch
 * max(BLAS, TLAS), the same two builds. Geometry and instances are uploaded through vkrt's staging
 * path; the builds read them, so a barrier makes the transfers visible first.
 *
 * Not run where this was written (its Vulkan, lavapipe, has no ray tracing): the two-level form
 * compiles and follows the specification (VkAccelerationStructureInstanceKHR's transform is the
 * 3x4 row-major matrix vkrt_instance holds; instance data at a 16-byte multiple; a BLAS's
 * reference its device address), and awaits its first run on a ray tracing GPU.
 */
#include "rtpipe_accel.h"

#include <math.h>
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

void rtpipe_plan_free(rtpipe_plan *p)
{
    free(p->positions);
    free(p->triangles);
    free(p->instances);
    free(p->instance_first);
    memset(p, 0, sizeof *p);
}

static bool plan_alloc(rtpipe_plan *p, uint32_t blas_count, uint32_t instance_count,
                             vkrt_error *err)
{
    memset(p, 0, sizeof *p);
    p->blas_count = blas_count;
    p->instance_count = instance_count;
    p->positions = calloc(blas_count ? blas_count : 1, sizeof *p->positions);
    p->triangles = calloc(blas_count ? blas_count : 1, sizeof *p->triangles);
    p->instances = calloc(instance_count ? instance_count : 1, sizeof *p->instances);
    p->instance_first = calloc(instance_count ? instance_count : 1, sizeof *p->instance_first);
    if (!p->positions || !p->triangles || !p->instances || !p->instance_first) {
        rtpipe_plan_free(p);
        return vkrt_error_set(err, "out of memory for %u structures and %u instances", blas_count,
                              instance_count);
    }
    return true;
}

/* An instance of BLAS blas: every ray's mask, hit group 0, both faces, opaque. */
static VkAccelerationStructureInstanceKHR instance_record(const float transform[12],
                                                          uint32_t custom_index, uint32_t blas)
{
    VkAccelerationStructureInstanceKHR r = {
        .instanceCustomIndex = custom_index,
        .mask = 0xFF,
        .instanceShaderBindingTableRecordOffset = 0,
        .flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR |
                 VK_GEOMETRY_INSTANCE_FORCE_OPAQUE_BIT_KHR,
        .accelerationStructureReference = blas,
    };
    memcpy(r.transform.matrix, transform, sizeof r.transform.matrix);
    return r;
}

/* The offset of a structure in a buffer must be a multiple of 256 (VkAccelerationStructureCreate-
 * InfoKHR). */
enum { STRUCTURE_OFFSET_ALIGNMENT = 256 };

/* Creates a structure of the given type and size at offset of buffer (made with
 * ACCELERATION_STRUCTURE_STORAGE usage). */
static bool create_structure(rtpipe_device *dev, VkAccelerationStructureTypeKHR type,
                             const gpu_buffer *buffer, VkDeviceSize offset, VkDeviceSize size,
                             VkAccelerationStructureKHR *structure, vkrt_error *err)
{
    VkAccelerationStructureCreateInfoKHR info = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR,
        .buffer = buffer->buffer,
        .offset = offset,
        .size = size,
        .type = type,
    };
    GPU_CHECK(dev->vk.create_accel(dev->ctx.device, &info, NULL, structure));
    return true;
fail:
    return false;
}

static bool create_storage(rtpipe_device *dev, VkDeviceSize size, gpu_buffer *buffer,
                           const char *what, vkrt_error *err)
{
    return gpu_buffer_create_usage(&dev->ctx, buffer, (size_t)size,
                                   VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR |
                                       VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                   what, err);
}

/* The build's inputs, scratch and timer; freed after it, whatever happened. */
typedef struct build_inputs {
    gpu_buffer vertices, instances, scratch;
    gpu_timer timer;
    VkAccelerationStructureGeometryKHR *geometries; /* per BLAS */
    VkAccelerationStructureBuildGeometryInfoKHR *infos;
    VkAccelerationStructureBuildRangeInfoKHR *ranges;
    const VkAccelerationStructureBuildRangeInfoKHR **range_pointers;
    VkAccelerationStructureBuildSizesInfoKHR *sizes;
    VkDeviceSize *blas_offsets, *scratch_offsets;
} build_inputs;

static void build_inputs_free(rtpipe_device *dev, build_inputs *in)
{
    gpu_timer_destroy(&dev->ctx, &in->timer);
    gpu_buffer_destroy(&dev->ctx, &in->scratch);
    gpu_buffer_destroy(&dev->ctx, &in->instances);
    gpu_buffer_destroy(&dev->ctx, &in->vertices);
    free(in->geometries);
    free(in->infos);
    free(in->ranges);
    free(in->range_pointers);
    free(in->sizes);
    free(in->blas_offsets);
    free(in->scratch_offsets);
    memset(in, 0, sizeof *in);
}

/* Uploads every BLAS's triangles into one vertex buffer, each at its own offset, and describes
 * the BLAS builds (sizes queried, offsets in the BLAS buffer and the scratch laid out). */
static bool describe_blases(rtpipe_device *dev, const rtpipe_plan *p, build_inputs *in,
                            VkDeviceSize *blas_total, VkDeviceSize *scratch_total,
                            vkrt_error *err)
{
    uint32_t n = p->blas_count;
    in->geometries = calloc(n, sizeof *in->geometries);
    in->infos = calloc(n, sizeof *in->infos);
    in->ranges = calloc(n, sizeof *in->ranges);
    in->range_pointers = calloc(n, sizeof *in->range_pointers);
    in->sizes = calloc(n, sizeof *in->sizes);
    in->blas_offsets = calloc(n, sizeof *in->blas_offsets);
    in->scratch_offsets = calloc(n, sizeof *in->scratch_offsets);
    if (!in->geometries || !in->infos || !in->ranges || !in->range_pointers || !in->sizes ||
        !in->blas_offsets || !in->scratch_offsets)
        return vkrt_error_set(err, "out of memory for %u structures", n);
    size_t vertex_bytes = 0;
    for (uint32_t b = 0; b < n; ++b)
        vertex_bytes += (size_t)p->triangles[b] * 9 * sizeof(float);
    const VkBufferUsageFlags input_usage =
        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
        VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    if (!gpu_buffer_create_usage(&dev->ctx, &in->vertices, vertex_bytes, input_usage, "vertices",
                                 err))
        return false;
    VkDeviceAddress vertex_address = rtpipe_buffer_address(dev, in->vertices.buffer);
    VkDeviceSize scratch_alignment = dev->accel.minAccelerationStructureScratchOffsetAlignment;
    size_t at = 0;
    *blas_total = 0;
    *scratch_total = 0;
    for (uint32_t b = 0; b < n; ++b) {
        uint32_t count = p->triangles[b];
        size_t bytes = (size_t)count * 9 * sizeof(float);
        if (count > dev->accel.maxPrimitiveCount)
            return vkrt_error_set(err, "a mesh's %u triangles exceed %s's maxPrimitiveCount "
                                       "(%llu)",
                                  count, dev->ctx.properties.deviceName,
                                  (unsigned long long)dev->accel.maxPrimitiveCount);
        if (!gpu_buffer_upload_at(&dev->ctx, &in->vertices, at, p->positions[b], bytes, err))
            return false;
        /* The vertices: a multiple of 4 bytes from the buffer's start, as R32G32B32_SFLOAT
         * needs (the size of its component). */
        in->geometries[b] = (VkAccelerationStructureGeometryKHR){
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
            .geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR,
            .geometry.triangles = {
                .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR,
                .vertexFormat = VK_FORMAT_R32G32B32_SFLOAT,
                .vertexData.deviceAddress = vertex_address + at,
                .vertexStride = 3 * sizeof(float),
                .maxVertex = 3 * count - 1,
                .indexType = VK_INDEX_TYPE_NONE_KHR,
            },
            .flags = VK_GEOMETRY_OPAQUE_BIT_KHR,
        };
        at += bytes;
        in->infos[b] = (VkAccelerationStructureBuildGeometryInfoKHR){
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR,
            .type = VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
            .flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR,
            .mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR,
            .geometryCount = 1,
            .pGeometries = &in->geometries[b],
        };
        in->sizes[b].sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR;
        dev->vk.build_sizes(dev->ctx.device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR,
                            &in->infos[b], &count, &in->sizes[b]);
        if (in->sizes[b].accelerationStructureSize == 0)
            return vkrt_error_set(err, "the driver gave a bottom-level structure size of 0");
        in->ranges[b] = (VkAccelerationStructureBuildRangeInfoKHR){.primitiveCount = count};
        in->range_pointers[b] = &in->ranges[b];
        /* Each BLAS at a multiple of 256 of one buffer; builds in one call must not share
         * scratch memory, so each has its own slice, at the device's scratch alignment. */
        in->blas_offsets[b] = align_up(*blas_total, STRUCTURE_OFFSET_ALIGNMENT);
        *blas_total = in->blas_offsets[b] + in->sizes[b].accelerationStructureSize;
        in->scratch_offsets[b] = align_up(*scratch_total, scratch_alignment);
        *scratch_total = in->scratch_offsets[b] + in->sizes[b].buildScratchSize;
    }
    return true;
}

/* The builds back to back RTPIPE_BUILD_RUNS times, timestamps between: 2k before the BLASes of
 * build k, 2k+1 between them and the TLAS, 2k+2 after; the medians into accel. */
static bool build_timed(rtpipe_device *dev, const rtpipe_plan *p, build_inputs *in,
                        const VkAccelerationStructureBuildGeometryInfoKHR *tlas_info,
                        rtpipe_accel *accel, vkrt_error *err)
{
    const VkAccelerationStructureBuildRangeInfoKHR tlas_range = {.primitiveCount =
                                                                     p->instance_count};
    const VkAccelerationStructureBuildRangeInfoKHR *tlas_ranges = &tlas_range;
    const VkPipelineStageFlags build_stage = VK_PIPELINE_STAGE_ACCELERATION_STRUCTURE_BUILD_BIT_KHR;
    const VkAccessFlags structure_access = VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR |
                                           VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR;
    if (!gpu_timer_create(&dev->ctx, &in->timer, 2 * RTPIPE_BUILD_RUNS + 1, err))
        return false;
    VkCommandBuffer cmd;
    if (!gpu_commands_begin(&dev->ctx, &cmd, err))
        return false;
    memory_barrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_ACCESS_TRANSFER_WRITE_BIT, build_stage,
                   VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    gpu_timer_reset(cmd, &in->timer);
    gpu_timer_write(cmd, &in->timer, 0);
    for (uint32_t k = 0; k < RTPIPE_BUILD_RUNS; ++k) {
        dev->vk.cmd_build_accel(cmd, p->blas_count, in->infos, in->range_pointers);
        /* The TLAS build reads the BLASes and reuses the scratch memory. */
        memory_barrier(cmd, build_stage, structure_access, build_stage, structure_access);
        gpu_timer_write(cmd, &in->timer, 2 * k + 1);
        dev->vk.cmd_build_accel(cmd, 1, tlas_info, &tlas_ranges);
        /* The next build rewrites the BLASes and the scratch the TLAS build used. */
        memory_barrier(cmd, build_stage, structure_access, build_stage, structure_access);
        gpu_timer_write(cmd, &in->timer, 2 * k + 2);
    }
    /* Every later trace reads the structures. */
    memory_barrier(cmd, build_stage, VK_ACCESS_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                   VK_PIPELINE_STAGE_RAY_TRACING_SHADER_BIT_KHR,
                   VK_ACCESS_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    if (!gpu_commands_submit(&dev->ctx, err))
        return false;
    double total[RTPIPE_BUILD_RUNS], blas[RTPIPE_BUILD_RUNS], tlas[RTPIPE_BUILD_RUNS];
    for (uint32_t k = 0; k < RTPIPE_BUILD_RUNS; ++k)
        if (!gpu_timer_ms(&dev->ctx, &in->timer, 2 * k, 2 * k + 2, &total[k], err) ||
            !gpu_timer_ms(&dev->ctx, &in->timer, 2 * k, 2 * k + 1, &blas[k], err) ||
            !gpu_timer_ms(&dev->ctx, &in->timer, 2 * k + 1, 2 * k + 2, &tlas[k], err))
            return false;
    accel->build_ms_first = total[0];
    accel->build_ms = median(total, RTPIPE_BUILD_RUNS);
    accel->blas_ms = median(blas, RTPIPE_BUILD_RUNS);
    accel->tlas_ms = median(tlas, RTPIPE_BUILD_RUNS);
    return true;
}

/* Builds what p describes into accel (zeroed first). */
static bool build(rtpipe_device *dev, rtpipe_plan *p, rtpipe_accel *accel, vkrt_error *err)
{
    memset(accel, 0, sizeof *accel);
    if (p->blas_count == 0 || p->instance_count == 0)
        return vkrt_error_set(err, "the scene has no triangles");
    if (p->instance_count > dev->accel.maxInstanceCount)
        return vkrt_error_set(err, "%u instances exceed %s's maxInstanceCount (%llu)",
                              p->instance_count, dev->ctx.properties.deviceName,
                              (unsigned long long)dev->accel.maxInstanceCount);
    VkDevice device = dev->ctx.device;
    build_inputs in = {0};
    bool ok = false;
    accel->blas = calloc(p->blas_count, sizeof *accel->blas);
    if (!accel->blas) {
        vkrt_error_set(err, "out of memory for %u structures", p->blas_count);
        goto done;
    }
    VkDeviceSize blas_total = 0, blas_scratch = 0;
    if (!describe_blases(dev, p, &in, &blas_total, &blas_scratch, err) ||
        !create_storage(dev, blas_total, &accel->blas_buffer, "bottom-level acceleration "
                                                              "structures", err))
        goto done;
    accel->blas_count = p->blas_count;
    for (uint32_t b = 0; b < p->blas_count; ++b) {
        if (!create_structure(dev, VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR,
                              &accel->blas_buffer, in.blas_offsets[b],
                              in.sizes[b].accelerationStructureSize, &accel->blas[b], err))
            goto done;
        accel->blas_bytes += in.sizes[b].accelerationStructureSize;
        accel->unique_triangles += p->triangles[b];
    }

    /* The instances, each referring to its BLAS by device address. Tightly packed records at a
     * device address that is a multiple of 16 (VkAccelerationStructureGeometryInstancesDataKHR
     * with arrayOfPointers false). */
    for (uint32_t i = 0; i < p->instance_count; ++i) {
        VkAccelerationStructureDeviceAddressInfoKHR address = {
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR,
            .accelerationStructure = accel->blas[p->instances[i].accelerationStructureReference],
        };
        p->instances[i].accelerationStructureReference = dev->vk.accel_address(device, &address);
    }
    const VkBufferUsageFlags input_usage =
        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR |
        VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    size_t instance_bytes = (size_t)p->instance_count * sizeof *p->instances;
    size_t first_bytes = (size_t)p->instance_count * sizeof *p->instance_first;
    if (!gpu_buffer_create_usage(&dev->ctx, &in.instances, instance_bytes, input_usage,
                                 "instances", err) ||
        !gpu_buffer_upload(&dev->ctx, &in.instances, p->instances, instance_bytes, err) ||
        !gpu_buffer_create(&dev->ctx, &accel->instance_first, first_bytes, "instance_first",
                           err) ||
        !gpu_buffer_upload(&dev->ctx, &accel->instance_first, p->instance_first, first_bytes,
                           err))
        goto done;
    VkDeviceAddress instance_address = rtpipe_buffer_address(dev, in.instances.buffer);
    if (instance_address % 16 != 0) {
        vkrt_error_set(err, "the instance buffer's device address is not a multiple of 16");
        goto done;
    }
    VkAccelerationStructureGeometryKHR instance_geometry = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR,
        .geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR,
        .geometry.instances = {
            .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR,
            .arrayOfPointers = VK_FALSE,
            .data.deviceAddress = instance_address,
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
    VkAccelerationStructureBuildSizesInfoKHR tlas_sizes = {
        .sType = VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR,
    };
    dev->vk.build_sizes(device, VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &tlas_info,
                        &p->instance_count, &tlas_sizes);
    if (!create_storage(dev, tlas_sizes.accelerationStructureSize, &accel->tlas_buffer,
                        "top-level acceleration structure", err) ||
        !create_structure(dev, VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, &accel->tlas_buffer,
                          0, tlas_sizes.accelerationStructureSize, &accel->tlas, err))
        goto done;

    /* One scratch buffer: the BLASes' slices side by side, then the TLAS from its start (the
     * barrier between the builds orders the reuse), with room to round its address up. */
    VkDeviceSize scratch_alignment = dev->accel.minAccelerationStructureScratchOffsetAlignment;
    VkDeviceSize scratch_size =
        blas_scratch > tlas_sizes.buildScratchSize ? blas_scratch : tlas_sizes.buildScratchSize;
    if (!gpu_buffer_create_usage(&dev->ctx, &in.scratch, (size_t)(scratch_size + scratch_alignment),
                                 VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                                     VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                                 "acceleration structure scratch", err))
        goto done;
    VkDeviceAddress scratch_address =
        align_up(rtpipe_buffer_address(dev, in.scratch.buffer), scratch_alignment);
    for (uint32_t b = 0; b < p->blas_count; ++b) {
        in.infos[b].dstAccelerationStructure = accel->blas[b];
        in.infos[b].scratchData.deviceAddress = scratch_address + in.scratch_offsets[b];
    }
    tlas_info.dstAccelerationStructure = accel->tlas;
    tlas_info.scratchData.deviceAddress = scratch_address;
    if (!build_timed(dev, p, &in, &tlas_info, accel, err))
        goto done;
    accel->tlas_bytes = tlas_sizes.accelerationStructureSize;
    accel->scratch_bytes = scratch_size;
    accel->instances = p->instance_count;
    accel->numbering = p->numbering;
    ok = true;
done:
    build_inputs_free(dev, &in);
    if (!ok)
        rtpipe_accel_destroy(dev, accel);
    return ok;
}

bool rtpipe_accel_create(rtpipe_device *dev, const float *positions, uint32_t triangle_count,
                         rtpipe_accel *accel, vkrt_error *err)
{
    memset(accel, 0, sizeof *accel);
    if (triangle_count == 0)
        return vkrt_error_set(err, "the scene has no triangles");
    rtpipe_plan p;
    if (!plan_alloc(&p, 1, 1, err))
        return false;
    p.positions[0] = positions;
    p.triangles[0] = triangle_count;
    p.instances[0] = instance_record(vkrt_identity_transform, 0, 0);
    p.numbering = RTPIPE_HIT_PRIMITIVE;
    bool ok = build(dev, &p, accel, err);
    rtpipe_plan_free(&p);
    return ok;
}

/* Whether t's 3x3 part is invertible and finite: vkrt's two-level BVH keeps such instances
 * only. */
static bool invertible(const float t[12])
{
    double cof[3][3];
    double det = vkrt_transform_cofactors(t, cof);
    return fabs(det) > 0 && isfinite(det);
}

bool rtpipe_plan_instanced(const vkrt_model *model, rtpipe_plan *p, vkrt_error *err)
{
    memset(p, 0, sizeof *p);
    /* Per mesh, its BLAS (UINT32_MAX: no kept instance uses it). */
    uint32_t *blas_of = malloc((model->mesh_count ? model->mesh_count : 1) * sizeof *blas_of);
    if (!blas_of)
        return vkrt_error_set(err, "out of memory for %u meshes", model->mesh_count);
    uint32_t blas_count = 0, kept = 0;
    for (uint32_t m = 0; m < model->mesh_count; ++m)
        blas_of[m] = UINT32_MAX;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        const vkrt_instance *inst = &model->instances[i];
        if (model->meshes[inst->mesh].triangle_count == 0 || !invertible(inst->transform))
            continue;
        ++kept;
        if (blas_of[inst->mesh] == UINT32_MAX)
            blas_of[inst->mesh] = blas_count++;
    }
    if (kept == 0) {
        free(blas_of);
        return vkrt_error_set(err, "no instance has triangles and an invertible transform");
    }
    if (!plan_alloc(p, blas_count, kept, err)) {
        free(blas_of);
        return false;
    }
    for (uint32_t m = 0; m < model->mesh_count; ++m)
        if (blas_of[m] != UINT32_MAX) {
            p->positions[blas_of[m]] = model->meshes[m].positions;
            p->triangles[blas_of[m]] = model->meshes[m].triangle_count;
        }
    /* The first triangles in vkrt_model_world's order count every instance, kept or not. */
    uint64_t first = 0, largest_first = 0;
    uint32_t k = 0;
    for (uint32_t i = 0; i < model->instance_count; ++i) {
        const vkrt_instance *inst = &model->instances[i];
        uint32_t count = model->meshes[inst->mesh].triangle_count;
        if (count != 0 && invertible(inst->transform)) {
            p->instance_first[k] = (uint32_t)first;
            largest_first = first;
            p->instances[k++] =
                instance_record(inst->transform, (uint32_t)first, blas_of[inst->mesh]);
        }
        first += count;
    }
    free(blas_of);
    /* instanceCustomIndex has 24 bits; larger numbers come from the instance_first buffer. */
    p->numbering =
        largest_first < (1u << 24) ? RTPIPE_HIT_CUSTOM_INDEX : RTPIPE_HIT_INSTANCE_BUFFER;
    if (p->numbering == RTPIPE_HIT_INSTANCE_BUFFER)
        for (uint32_t i = 0; i < kept; ++i)
            p->instances[i].instanceCustomIndex = 0;
    return true;
}

bool rtpipe_accel_create_instanced(rtpipe_device *dev, const vkrt_model *model,
                                   rtpipe_accel *accel, vkrt_error *err)
{
    memset(accel, 0, sizeof *accel);
    rtpipe_plan p;
    if (!rtpipe_plan_instanced(model, &p, err))
        return false;
    bool ok = build(dev, &p, accel, err);
    accel->two_level = ok;
    rtpipe_plan_free(&p);
    return ok;
}

void rtpipe_accel_destroy(rtpipe_device *dev, rtpipe_accel *accel)
{
    /* After a lost device nothing may be freed (see gpu_context.lost). */
    if (!dev->ctx.lost) {
        if (accel->tlas)
            dev->vk.destroy_accel(dev->ctx.device, accel->tlas, NULL);
        for (uint32_t b = 0; accel->blas && b < accel->blas_count; ++b)
            if (accel->blas[b])
                dev->vk.destroy_accel(dev->ctx.device, accel->blas[b], NULL);
    }
    free(accel->blas);
    gpu_buffer_destroy(&dev->ctx, &accel->instance_first);
    gpu_buffer_destroy(&dev->ctx, &accel->tlas_buffer);
    gpu_buffer_destroy(&dev->ctx, &accel->blas_buffer);
    memset(accel, 0, sizeof *accel);
}
