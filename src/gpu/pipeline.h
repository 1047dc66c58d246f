/*
 * pipeline.h: compute pipelines over one descriptor set of storage buffers.
 *
 * Every vkrt kernel sees the same kind of interface: set 0 holds storage buffers at bindings
 * 0..binding_count-1, and push constants carry per-dispatch parameters. Choices fixed at pipeline
 * creation (workgroup size, whether a buffer is present) are specialization constants.
 */
#ifndef VKRT_GPU_PIPELINE_H
#define VKRT_GPU_PIPELINE_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "buffer.h"
#include "context.h"

/* The set layout, pool and set shared by the pipelines of one renderer. */
typedef struct gpu_storage_set {
    VkDescriptorSetLayout layout;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkPipelineLayout pipeline_layout;
    uint32_t binding_count;
    uint32_t push_size;
} gpu_storage_set;

/* Creates a set of binding_count storage buffers and a pipeline layout with push_size bytes of
 * push constants (at most the device's limit). */
bool gpu_storage_set_create(gpu_context *ctx, gpu_storage_set *set, uint32_t binding_count,
                            uint32_t push_size, vkrt_error *err);

/* The same with texel_count uniform texel buffers after the storage buffers, at bindings
 * binding_count .. binding_count + texel_count - 1 (gpu_storage_set_bind_view). */
bool gpu_storage_set_create_texels(gpu_context *ctx, gpu_storage_set *set, uint32_t binding_count,
                                   uint32_t texel_count, uint32_t push_size, vkrt_error *err);

/* Frees the set. Safe on a zeroed one. */
void gpu_storage_set_destroy(gpu_context *ctx, gpu_storage_set *set);

/* Points binding at the whole of buf. Call before recording dispatches that use it. */
void gpu_storage_set_bind(gpu_context *ctx, gpu_storage_set *set, uint32_t binding,
                          const gpu_buffer *buf);

/* Points the uniform texel buffer at binding at view. */
void gpu_storage_set_bind_view(gpu_context *ctx, gpu_storage_set *set, uint32_t binding,
                               VkBufferView view);

/* A specialization constant: constant_id and its 32-bit value (bool: 0 or 1). */
typedef struct gpu_spec_constant {
    uint32_t id;
    uint32_t value;
} gpu_spec_constant;

/* The most specialization constants a pipeline takes besides its workgroup size. */
#define GPU_MAX_SPEC_CONSTANTS 32u

typedef struct gpu_pipeline {
    VkPipeline pipeline;
    uint32_t workgroup_size;
    /* What it was specialized with, so that a kernel compiled later can be made alike
     * (gpu_pipeline_create_alike). */
    gpu_spec_constant spec[GPU_MAX_SPEC_CONSTANTS];
    uint32_t spec_count;
} gpu_pipeline;

/* Creates a compute pipeline from SPIR-V. Constant id 0 is the workgroup size
 * (local_size_x_id = 0) and is set to workgroup_size; more constants (at most
 * GPU_MAX_SPEC_CONSTANTS) come in spec. The driver's
 * compiled form is kept in the kernel cache (spirv_cache.h) under a key of the SPIR-V,
 * the specialization and the driver (pipelineCacheUUID, vendor and device id, driver version),
 * so a later start hands it back to the driver through a VkPipelineCache; an entry that is not
 * whole or whose Vulkan header names another device is not used, and is written anew. */
bool gpu_pipeline_create(gpu_context *ctx, gpu_pipeline *pipe, const gpu_storage_set *set,
                         const uint32_t *spirv, size_t word_count, uint32_t workgroup_size,
                         const gpu_spec_constant *spec, uint32_t spec_count, const char *name,
                         vkrt_error *err);

/* Creates a pipeline from SPIR-V with the workgroup size and specialization constants `model`
 * was made with: a kernel that is compiled only when first needed, for the same plan as those
 * compiled up front. */
bool gpu_pipeline_create_alike(gpu_context *ctx, gpu_pipeline *pipe, const gpu_storage_set *set,
                               const uint32_t *spirv, size_t word_count, const gpu_pipeline *model,
                               const char *name, vkrt_error *err);

/* Whether data (size bytes) starts with the header Vulkan specifies for pipeline cache data
 * (VkPipelineCacheHeaderVersionOne) for the device of props: a header of at least 32 bytes,
 * version one, props's vendor and device id and pipelineCacheUUID. */
bool gpu_pipeline_cache_header_ok(const void *data, size_t size,
                                  const VkPhysicalDeviceProperties *props);

/* How many pipelines this process made with the driver's data from the cache, and how many it
 * stored there, for --verbose. */
void gpu_pipeline_cache_counts(uint32_t *loaded, uint32_t *stored);

/* The driver's statistics of the pipeline's compiled kernel (registers and the like, as
 * `"name": value` pairs joined by ", ", cut to size), for a context created with
 * pipeline_statistics. False with err set when the device does not report them. */
bool gpu_pipeline_statistics(gpu_context *ctx, const gpu_pipeline *pipe, char *text, size_t size,
                             vkrt_error *err);

/* Frees the pipeline. Safe on a zeroed one. */
void gpu_pipeline_destroy(gpu_context *ctx, gpu_pipeline *pipe);

/* Records a dispatch of enough workgroups to cover `items` invocations in x, with push constants,
 * followed by a barrier that makes its buffer writes visible to the next dispatch and transfer. */
void gpu_dispatch(VkCommandBuffer cmd, const gpu_pipeline *pipe, const gpu_storage_set *set,
                  const void *push, uint32_t items);

/* Records a dispatch whose workgroup counts (3 uints) the GPU wrote into args at offset, with
 * push constants and the same barrier as gpu_dispatch. The kernel must stop invocations past its
 * item count itself. */
void gpu_dispatch_indirect(VkCommandBuffer cmd, const gpu_pipeline *pipe,
                           const gpu_storage_set *set, const void *push, const gpu_buffer *args,
                           VkDeviceSize offset);

/* The barrier every dispatch ends with: shader writes become visible to later shader reads and
 * writes, transfers and indirect argument reads. */
void gpu_dispatch_barrier(VkCommandBuffer cmd);

#endif
