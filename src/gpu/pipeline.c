/*
 * pipeline.c: descriptor sets, pipeline layouts and compute pipelines (see pipeline.h).
 */
#include "pipeline.h"

#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "spirv_cache.h"
#include "vk_check.h"

static _Atomic uint32_t cache_loaded, cache_stored;

bool gpu_pipeline_cache_header_ok(const void *data, size_t size,
                                  const VkPhysicalDeviceProperties *props)
{
    VkPipelineCacheHeaderVersionOne h;
    if (!data || size < sizeof h)
        return false;
    memcpy(&h, data, sizeof h);
    return h.headerSize >= sizeof h && h.headerSize <= size &&
           h.headerVersion == VK_PIPELINE_CACHE_HEADER_VERSION_ONE &&
           h.vendorID == props->vendorID && h.deviceID == props->deviceID &&
           memcmp(h.pipelineCacheUUID, props->pipelineCacheUUID, VK_UUID_SIZE) == 0;
}

void gpu_pipeline_cache_counts(uint32_t *loaded, uint32_t *stored)
{
    *loaded = atomic_load(&cache_loaded);
    *stored = atomic_load(&cache_stored);
}

/* The key of a pipeline's cache data: everything the driver's compiled form depends on. */
static bool pipeline_key(const gpu_context *ctx, const uint32_t *spirv, size_t word_count,
                         const VkSpecializationInfo *spec, VkPipelineCreateFlags flags,
                         gpu_spirv_key *key)
{
    const VkPhysicalDeviceProperties *p = &ctx->properties;
    uint32_t device[4] = {p->vendorID, p->deviceID, p->driverVersion, (uint32_t)flags};
    size_t entries = spec->mapEntryCount * sizeof *spec->pMapEntries;
    size_t size = word_count * 4 + entries + spec->dataSize + sizeof device + VK_UUID_SIZE;
    unsigned char *bytes = malloc(size), *at = bytes;
    if (!bytes)
        return false;
    memcpy(at, spirv, word_count * 4);
    memcpy(at += word_count * 4, spec->pMapEntries, entries);
    memcpy(at += entries, spec->pData, spec->dataSize);
    memcpy(at += spec->dataSize, device, sizeof device);
    memcpy(at + sizeof device, p->pipelineCacheUUID, VK_UUID_SIZE);
    *key = gpu_spirv_key_of_bytes(bytes, size);
    free(bytes);
    return true;
}

/* A VkPipelineCache holding the data stored under key, when there is a whole entry for this
 * device (*hit), else an empty one. */
static bool open_pipeline_cache(gpu_context *ctx, const gpu_spirv_key *key, VkPipelineCache *cache,
                                bool *hit, vkrt_error *err)
{
    void *data = NULL;
    size_t size = 0;
    *hit = gpu_spirv_cache_load_bytes(key, &data, &size) &&
           gpu_pipeline_cache_header_ok(data, size, &ctx->properties);
    VkPipelineCacheCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_CACHE_CREATE_INFO,
        .initialDataSize = *hit ? size : 0,
        .pInitialData = *hit ? data : NULL,
    };
    VkResult result = vkCreatePipelineCache(ctx->device, &info, NULL, cache);
    free(data);
    if (result != VK_SUCCESS)
        return vkrt_error_set(err, "vkCreatePipelineCache failed: %s", gpu_result_name(result));
    if (*hit)
        atomic_fetch_add(&cache_loaded, 1u);
    return true;
}

/* Stores the driver's data of cache under key, best effort. */
static void store_pipeline_cache(gpu_context *ctx, const gpu_spirv_key *key, VkPipelineCache cache)
{
    size_t size = 0;
    if (vkGetPipelineCacheData(ctx->device, cache, &size, NULL) != VK_SUCCESS || size == 0)
        return;
    void *data = malloc(size);
    if (data && vkGetPipelineCacheData(ctx->device, cache, &size, data) == VK_SUCCESS &&
        gpu_pipeline_cache_header_ok(data, size, &ctx->properties) &&
        gpu_spirv_cache_store_bytes(key, data, size))
        atomic_fetch_add(&cache_stored, 1u); /* counted only when it is on disk */
    free(data);
}

bool gpu_storage_set_create(gpu_context *ctx, gpu_storage_set *set, uint32_t binding_count,
                            uint32_t push_size, vkrt_error *err)
{
    return gpu_storage_set_create_texels(ctx, set, binding_count, 0, push_size, err);
}

bool gpu_storage_set_create_texels(gpu_context *ctx, gpu_storage_set *set, uint32_t binding_count,
                                   uint32_t texel_count, uint32_t push_size, vkrt_error *err)
{
    memset(set, 0, sizeof *set);
    uint32_t total = binding_count + texel_count;
    if (push_size > ctx->properties.limits.maxPushConstantsSize)
        return vkrt_error_set(err, "%u bytes of push constants exceed the device's %u", push_size,
                              ctx->properties.limits.maxPushConstantsSize);
    VkDescriptorSetLayoutBinding *bindings = calloc(total, sizeof *bindings);
    if (!bindings)
        return vkrt_error_set(err, "out of memory");
    for (uint32_t i = 0; i < total; ++i)
        bindings[i] = (VkDescriptorSetLayoutBinding){
            .binding = i,
            .descriptorType = i < binding_count ? VK_DESCRIPTOR_TYPE_STORAGE_BUFFER
                                                : VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER,
            .descriptorCount = 1,
            .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
        };
    VkDescriptorSetLayoutCreateInfo layout_info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO,
        .bindingCount = total,
        .pBindings = bindings,
    };
    GPU_CHECK(vkCreateDescriptorSetLayout(ctx->device, &layout_info, NULL, &set->layout));
    VkDescriptorPoolSize pool_sizes[2] = {
        {.type = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, .descriptorCount = binding_count},
        {.type = VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER, .descriptorCount = texel_count},
    };
    VkDescriptorPoolCreateInfo pool_info = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO,
        .maxSets = 1,
        .poolSizeCount = texel_count ? 2 : 1,
        .pPoolSizes = pool_sizes,
    };
    GPU_CHECK(vkCreateDescriptorPool(ctx->device, &pool_info, NULL, &set->pool));
    VkDescriptorSetAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO,
        .descriptorPool = set->pool,
        .descriptorSetCount = 1,
        .pSetLayouts = &set->layout,
    };
    GPU_CHECK(vkAllocateDescriptorSets(ctx->device, &alloc, &set->set));
    VkPushConstantRange push = {
        .stageFlags = VK_SHADER_STAGE_COMPUTE_BIT,
        .size = push_size,
    };
    VkPipelineLayoutCreateInfo pipeline_layout_info = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO,
        .setLayoutCount = 1,
        .pSetLayouts = &set->layout,
        .pushConstantRangeCount = push_size ? 1 : 0,
        .pPushConstantRanges = &push,
    };
    GPU_CHECK(vkCreatePipelineLayout(ctx->device, &pipeline_layout_info, NULL,
                                     &set->pipeline_layout));
    set->binding_count = total;
    set->push_size = push_size;
    free(bindings);
    return true;
fail:
    free(bindings);
    gpu_storage_set_destroy(ctx, set);
    return false;
}

void gpu_storage_set_destroy(gpu_context *ctx, gpu_storage_set *set)
{
    /* After a lost device, work that uses the set may still be running (see gpu_context.lost):
     * the handles are dropped, not destroyed. */
    if (!ctx->lost) {
        if (set->pipeline_layout)
            vkDestroyPipelineLayout(ctx->device, set->pipeline_layout, NULL);
        if (set->pool)
            vkDestroyDescriptorPool(ctx->device, set->pool, NULL);
        if (set->layout)
            vkDestroyDescriptorSetLayout(ctx->device, set->layout, NULL);
    }
    memset(set, 0, sizeof *set);
}

/* Writes one descriptor of the set: a storage buffer (info) or a uniform texel buffer (view). */
static void write_descriptor(gpu_context *ctx, gpu_storage_set *set, uint32_t binding,
                             const VkDescriptorBufferInfo *info, const VkBufferView *view)
{
    VkWriteDescriptorSet write = {
        .sType = VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET,
        .dstSet = set->set,
        .dstBinding = binding,
        .descriptorCount = 1,
        .descriptorType = view ? VK_DESCRIPTOR_TYPE_UNIFORM_TEXEL_BUFFER
                               : VK_DESCRIPTOR_TYPE_STORAGE_BUFFER,
        .pBufferInfo = info,
        .pTexelBufferView = view,
    };
    vkUpdateDescriptorSets(ctx->device, 1, &write, 0, NULL);
}

void gpu_storage_set_bind(gpu_context *ctx, gpu_storage_set *set, uint32_t binding,
                          const gpu_buffer *buf)
{
    VkDescriptorBufferInfo info = {.buffer = buf->buffer, .range = VK_WHOLE_SIZE};
    write_descriptor(ctx, set, binding, &info, NULL);
}

void gpu_storage_set_bind_view(gpu_context *ctx, gpu_storage_set *set, uint32_t binding,
                               VkBufferView view)
{
    write_descriptor(ctx, set, binding, NULL, &view);
}

bool gpu_pipeline_create(gpu_context *ctx, gpu_pipeline *pipe, const gpu_storage_set *set,
                         const uint32_t *spirv, size_t word_count, uint32_t workgroup_size,
                         const gpu_spec_constant *spec, uint32_t spec_count, const char *name,
                         vkrt_error *err)
{
    memset(pipe, 0, sizeof *pipe);
    if (spec_count > GPU_MAX_SPEC_CONSTANTS)
        return vkrt_error_set(err, "pipeline %s: %u specialization constants, at most %u", name,
                              spec_count, GPU_MAX_SPEC_CONSTANTS);
    VkShaderModule module = VK_NULL_HANDLE;
    VkPipelineCache cache = VK_NULL_HANDLE;
    uint32_t count = spec_count + 1;
    VkSpecializationMapEntry *entries = calloc(count, sizeof *entries);
    uint32_t *values = calloc(count, sizeof *values);
    if (!entries || !values) {
        vkrt_error_set(err, "out of memory");
        goto fail;
    }
    entries[0] = (VkSpecializationMapEntry){.constantID = 0, .offset = 0, .size = 4};
    values[0] = workgroup_size;
    for (uint32_t i = 0; i < spec_count; ++i) {
        entries[i + 1] = (VkSpecializationMapEntry){
            .constantID = spec[i].id, .offset = 4 * (i + 1), .size = 4};
        values[i + 1] = spec[i].value;
    }
    VkSpecializationInfo specialization = {
        .mapEntryCount = count,
        .pMapEntries = entries,
        .dataSize = 4 * count,
        .pData = values,
    };
    VkShaderModuleCreateInfo module_info = {
        .sType = VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO,
        .codeSize = word_count * sizeof *spirv,
        .pCode = spirv,
    };
    GPU_CHECK(vkCreateShaderModule(ctx->device, &module_info, NULL, &module));
    VkPipelineCreateFlags flags =
        ctx->pipeline_statistics ? VK_PIPELINE_CREATE_CAPTURE_STATISTICS_BIT_KHR : 0;
    char dir[4096];
    gpu_spirv_key key;
    bool hit = false, cached = gpu_spirv_cache_dir(dir, sizeof dir) &&
                               pipeline_key(ctx, spirv, word_count, &specialization, flags, &key);
    if (cached && !open_pipeline_cache(ctx, &key, &cache, &hit, err))
        goto fail;
    VkComputePipelineCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO,
        .stage =
            {
                .sType = VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO,
                .stage = VK_SHADER_STAGE_COMPUTE_BIT,
                .module = module,
                .pName = "main",
                .pSpecializationInfo = &specialization,
            },
        .layout = set->pipeline_layout,
        .flags = flags,
    };
    GPU_CHECK(vkCreateComputePipelines(ctx->device, cache, 1, &info, NULL, &pipe->pipeline));
    pipe->workgroup_size = workgroup_size;
    if (spec_count > 0)
        memcpy(pipe->spec, spec, spec_count * sizeof *spec);
    pipe->spec_count = spec_count;
    if (cached && !hit)
        store_pipeline_cache(ctx, &key, cache);
    if (cache)
        vkDestroyPipelineCache(ctx->device, cache, NULL);
    vkDestroyShaderModule(ctx->device, module, NULL);
    free(entries);
    free(values);
    return true;
fail:
    if (cache)
        vkDestroyPipelineCache(ctx->device, cache, NULL);
    if (module)
        vkDestroyShaderModule(ctx->device, module, NULL);
    free(entries);
    free(values);
    return vkrt_error_prefix(err, "pipeline %s", name);
}

bool gpu_pipeline_create_alike(gpu_context *ctx, gpu_pipeline *pipe, const gpu_storage_set *set,
                               const uint32_t *spirv, size_t word_count, const gpu_pipeline *model,
                               const char *name, vkrt_error *err)
{
    gpu_pipeline like = *model;
    return gpu_pipeline_create(ctx, pipe, set, spirv, word_count, like.workgroup_size, like.spec,
                               like.spec_count, name, err);
}

void gpu_pipeline_destroy(gpu_context *ctx, gpu_pipeline *pipe)
{
    /* As gpu_storage_set_destroy: after a lost device the handle is dropped, not destroyed. */
    if (pipe->pipeline && !ctx->lost)
        vkDestroyPipeline(ctx->device, pipe->pipeline, NULL);
    memset(pipe, 0, sizeof *pipe);
}

bool gpu_pipeline_statistics(gpu_context *ctx, const gpu_pipeline *pipe, char *text, size_t size,
                             vkrt_error *err)
{
    if (size == 0)
        return vkrt_error_set(err, "pipeline statistics: no room");
    text[0] = '\0';
    if (!ctx->pipeline_statistics)
        return vkrt_error_set(err, "the device does not report its kernels' statistics "
                                   "(VK_KHR_pipeline_executable_properties)");
    PFN_vkGetPipelineExecutableStatisticsKHR get_statistics =
        (PFN_vkGetPipelineExecutableStatisticsKHR)vkGetDeviceProcAddr(
            ctx->device, "vkGetPipelineExecutableStatisticsKHR");
    if (!get_statistics)
        return vkrt_error_set(err, "vkGetPipelineExecutableStatisticsKHR is missing");
    VkPipelineExecutableInfoKHR executable = {
        .sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_INFO_KHR,
        .pipeline = pipe->pipeline,
        .executableIndex = 0, /* a compute pipeline's one shader */
    };
    enum { max_statistics = 32 };
    VkPipelineExecutableStatisticKHR stats[max_statistics];
    uint32_t count = max_statistics;
    for (uint32_t i = 0; i < count; ++i)
        stats[i] = (VkPipelineExecutableStatisticKHR){
            .sType = VK_STRUCTURE_TYPE_PIPELINE_EXECUTABLE_STATISTIC_KHR};
    VkResult result = get_statistics(ctx->device, &executable, &count, stats);
    if (result != VK_SUCCESS && result != VK_INCOMPLETE)
        return vkrt_error_set(err, "vkGetPipelineExecutableStatisticsKHR: %s",
                              gpu_result_name(result));
    size_t used = 0;
    for (uint32_t i = 0; i < count && used < size; ++i) {
        const VkPipelineExecutableStatisticKHR *st = &stats[i];
        char value[64];
        switch (st->format) {
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_BOOL32_KHR:
            snprintf(value, sizeof value, "%s", st->value.b32 ? "true" : "false");
            break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_INT64_KHR:
            snprintf(value, sizeof value, "%lld", (long long)st->value.i64);
            break;
        case VK_PIPELINE_EXECUTABLE_STATISTIC_FORMAT_UINT64_KHR:
            snprintf(value, sizeof value, "%llu", (unsigned long long)st->value.u64);
            break;
        default:
            snprintf(value, sizeof value, "%g", st->value.f64);
            break;
        }
        /* Names are the driver's words; quotes and backslashes would break the JSON. */
        char name[VK_MAX_DESCRIPTION_SIZE];
        size_t n = 0;
        for (const char *c = st->name; *c && n + 1 < sizeof name; ++c)
            name[n++] = (*c == '"' || *c == '\\') ? '\'' : *c;
        name[n] = '\0';
        int wrote = snprintf(text + used, size - used, "%s\"%s\": %s", used ? ", " : "", name,
                             value);
        used = wrote < 0 ? size : used + (size_t)wrote;
    }
    return true;
}

/* The pipeline, its set and the push constants, before a dispatch. */
static void bind_for_dispatch(VkCommandBuffer cmd, const gpu_pipeline *pipe,
                              const gpu_storage_set *set, const void *push)
{
    vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipe->pipeline);
    vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, set->pipeline_layout, 0, 1,
                            &set->set, 0, NULL);
    if (set->push_size)
        vkCmdPushConstants(cmd, set->pipeline_layout, VK_SHADER_STAGE_COMPUTE_BIT, 0,
                           set->push_size, push);
}

void gpu_dispatch(VkCommandBuffer cmd, const gpu_pipeline *pipe, const gpu_storage_set *set,
                  const void *push, uint32_t items)
{
    bind_for_dispatch(cmd, pipe, set, push);
    /* Past 65535 workgroups (the smallest maxComputeWorkGroupCount[0] Vulkan allows) the grid
     * folds into y; kernels flatten it back with invocation_index() in glsl/lib/bindings.glsl. */
    const uint32_t max_groups_x = 65535;
    uint32_t groups = (items + pipe->workgroup_size - 1) / pipe->workgroup_size;
    uint32_t groups_x = groups < max_groups_x ? groups : max_groups_x;
    uint32_t groups_y = groups_x ? (groups + groups_x - 1) / groups_x : 0;
    if (groups)
        vkCmdDispatch(cmd, groups_x, groups_y, 1);
    gpu_dispatch_barrier(cmd);
}

void gpu_dispatch_barrier(VkCommandBuffer cmd)
{
    /* Later dispatches may read what this one wrote as buffers, as indirect dispatch arguments,
     * or through transfers. */
    VkMemoryBarrier barrier = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT |
                         VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT |
                             VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT,
                         0, 1, &barrier, 0, NULL, 0, NULL);
}

void gpu_dispatch_indirect(VkCommandBuffer cmd, const gpu_pipeline *pipe,
                           const gpu_storage_set *set, const void *push, const gpu_buffer *args,
                           VkDeviceSize offset)
{
    bind_for_dispatch(cmd, pipe, set, push);
    vkCmdDispatchIndirect(cmd, args->buffer, offset);
    gpu_dispatch_barrier(cmd);
}
