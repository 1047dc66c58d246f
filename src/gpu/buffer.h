/*
 * buffer.h: storage buffers on the device, with upload and download through staging buffers.
 */
#ifndef VKRT_GPU_BUFFER_H
#define VKRT_GPU_BUFFER_H

#include <stdbool.h>
#include <stddef.h>
#include <vulkan/vulkan.h>

#include "context.h"

typedef struct gpu_buffer {
    VkBuffer buffer;
    VkDeviceMemory memory;
    VkDeviceSize size;
    void *mapped;        /* non-NULL for host-visible buffers (staging) */
    VkDeviceSize device_bytes; /* device-local memory it holds (counted in ctx->memory_used) */
} gpu_buffer;

/* Staging buffers hold at most this many bytes: larger transfers go in pieces. */
#define GPU_STAGING_BYTES ((size_t)64 << 20)

/* Creates a device-local storage buffer of size bytes (at least 16, since Vulkan has no empty
 * buffers), usable as a transfer source and destination and as a uniform texel buffer
 * (gpu_buffer_view_create). what names the buffer in messages:
 * a buffer larger than ctx->max_buffer_bytes (maxStorageBufferRange, maxMemoryAllocationSize or
 * VKRT_TEST_MAX_BUFFER_BYTES), or than the device memory left (ctx->memory_limit less
 * ctx->memory_used), is refused with its size and the limit ("... does not fit ..."), before the
 * driver is asked. On failure nothing is left allocated. */
bool gpu_buffer_create(gpu_context *ctx, gpu_buffer *buf, size_t size, const char *what,
                       vkrt_error *err);

/* gpu_buffer_create; with addressed, the buffer also has a device address (gpu_buffer_address),
 * which needs ctx->device_addresses. */
bool gpu_buffer_create_addressed(gpu_context *ctx, gpu_buffer *buf, size_t size, bool addressed,
                                 const char *what, vkrt_error *err);

/* The name of the limit that limit (ctx->max_buffer_bytes or ctx->split_bytes) comes from, for
 * messages. */
const char *gpu_buffer_limit_name(const gpu_context *ctx, VkDeviceSize limit);

/* The device address of a buffer made with addressed set. */
VkDeviceAddress gpu_buffer_address(const gpu_context *ctx, const gpu_buffer *buf);

/* gpu_buffer_create, then gpu_buffer_upload of size bytes from data. On failure nothing is left
 * allocated. */
bool gpu_buffer_create_from(gpu_context *ctx, gpu_buffer *buf, const void *data, size_t size,
                            const char *what, vkrt_error *err);

/* Creates a device-local buffer of size bytes with exactly the given usage (add
 * VK_BUFFER_USAGE_TRANSFER_DST_BIT for gpu_buffer_upload). With
 * VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT its memory is allocated for device addresses, which
 * needs a device created with bufferDeviceAddress on. For acceleration structures, their inputs
 * and shader binding tables; what names it in messages. On failure nothing is left allocated. */
bool gpu_buffer_create_usage(gpu_context *ctx, gpu_buffer *buf, size_t size,
                             VkBufferUsageFlags usage, const char *what, vkrt_error *err);

/* A view of buf as 16-byte texels (RGBA32_UINT), for kernels to read it as a uniform texel
 * buffer: as many texels as the buffer holds and the device's maxTexelBufferElements allows.
 * *covered says whether that is all of the buffer. */
bool gpu_buffer_view_create(gpu_context *ctx, const gpu_buffer *buf, VkBufferView *view,
                            bool *covered, vkrt_error *err);

/* Frees the view and zeroes it. Safe on VK_NULL_HANDLE. */
void gpu_buffer_view_destroy(gpu_context *ctx, VkBufferView *view);

/* Creates a host-visible, coherent, persistently mapped buffer for transfers. */
bool gpu_staging_create(gpu_context *ctx, gpu_buffer *buf, size_t size, vkrt_error *err);

/* Frees the buffer and zeroes it. Safe on a zeroed buffer. */
void gpu_buffer_destroy(gpu_context *ctx, gpu_buffer *buf);

/* Copies size bytes from data into the start of buf and waits until done, through a staging
 * buffer of at most GPU_STAGING_BYTES. */
bool gpu_buffer_upload(gpu_context *ctx, gpu_buffer *buf, const void *data, size_t size,
                       vkrt_error *err);

/* The same into buf from byte offset on. */
bool gpu_buffer_upload_at(gpu_context *ctx, gpu_buffer *buf, size_t offset, const void *data,
                          size_t size, vkrt_error *err);

/* Writes size bytes at (from the start of the write) into dst. */
typedef void gpu_write_fn(void *user, size_t at, size_t size, void *dst);

/* Copies size bytes into buf from byte offset on, which write puts into a staging buffer piece by
 * piece, piece bytes at a time (at most; 0: all at once), and waits until done. */
bool gpu_buffer_write(gpu_context *ctx, gpu_buffer *buf, size_t offset, size_t size, size_t piece,
                      gpu_write_fn *write, void *user, vkrt_error *err);

/* Copies size bytes from the start of buf into data and waits until done. */
bool gpu_buffer_download(gpu_context *ctx, const gpu_buffer *buf, void *data, size_t size,
                         vkrt_error *err);

/* Fills the first size bytes of buf with zeros and waits until done. */
bool gpu_buffer_zero(gpu_context *ctx, gpu_buffer *buf, vkrt_error *err);

#endif
