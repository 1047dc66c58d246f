/*
 * buffer.c: device buffers and staging transfers (see buffer.h).
 *
 * Every upload and download goes through a staging buffer (the context's, kept between transfers
 * of up to GPU_STAGING_BYTES) and a one-shot command buffer. That costs a wait per transfer,
 * which is fine: vkrt transfers when a scene loads and when a frame is read back, never per
 * bounce.
 */
#include "buffer.h"

#include <stdlib.h>
#include <string.h>

#include "../test_hooks.h"
#include "vk_check.h"

static const size_t min_buffer_size = 16;

static double mib(VkDeviceSize bytes)
{
    return (double)bytes / 1048576.0;
}

/* Refuses device-local memory the device cannot give (context.h), in words a user can act on. */
static bool check_device_memory(gpu_context *ctx, VkDeviceSize bytes, vkrt_error *err)
{
    const char *name = ctx->properties.deviceName;
    if (bytes > ctx->max_allocation)
        return vkrt_error_set(err,
                              "the scene does not fit %s: one allocation of %.1f MiB is more "
                              "than the device allows (maxMemoryAllocationSize %.1f MiB)",
                              name, mib(bytes), mib(ctx->max_allocation));
    if (bytes > ctx->memory_limit - ctx->memory_used)
        return vkrt_error_set(err,
                              "the scene does not fit %s: %.1f MiB more device memory with "
                              "%.1f MiB already in use makes %.1f MiB, and the device has "
                              "%.1f MiB%s",
                              name, mib(bytes), mib(ctx->memory_used),
                              mib(ctx->memory_used + bytes), mib(ctx->memory_limit),
                              vkrt_test_hooks_get()->device_memory_limit
                                  ? " (VKRT_TEST_DEVICE_MEMORY_LIMIT)"
                                  : "");
    return true;
}

static bool create_with_memory(gpu_context *ctx, gpu_buffer *buf, size_t size,
                               VkBufferUsageFlags usage, VkMemoryPropertyFlags wanted,
                               VkMemoryPropertyFlags fallback, vkrt_error *err)
{
    memset(buf, 0, sizeof *buf);
    if (size < min_buffer_size)
        size = min_buffer_size;
    VkBufferCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO,
        .size = size,
        .usage = usage,
        .sharingMode = VK_SHARING_MODE_EXCLUSIVE,
    };
    GPU_CHECK(vkCreateBuffer(ctx->device, &info, NULL, &buf->buffer));
    VkMemoryRequirements req;
    vkGetBufferMemoryRequirements(ctx->device, buf->buffer, &req);
    uint32_t type = gpu_memory_type(ctx, req.memoryTypeBits, wanted);
    if (type == UINT32_MAX)
        type = gpu_memory_type(ctx, req.memoryTypeBits, fallback);
    if (type == UINT32_MAX) {
        vkrt_error_set(err, "no suitable memory type for a buffer of %zu bytes", size);
        goto fail;
    }
    bool device_local = wanted & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    if (device_local && !check_device_memory(ctx, req.size, err))
        goto fail;
    /* Buffers whose address shaders or acceleration structure builds take need memory allocated
     * for it (bufferDeviceAddress); no other vkrt buffer asks for it. */
    VkMemoryAllocateFlagsInfo address_flags = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO,
        .flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT,
    };
    VkMemoryAllocateInfo alloc = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO,
        .pNext = usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT ? &address_flags : NULL,
        .allocationSize = req.size,
        .memoryTypeIndex = type,
    };
    GPU_CHECK(vkAllocateMemory(ctx->device, &alloc, NULL, &buf->memory));
    if (device_local) {
        buf->device_bytes = req.size;
        ctx->memory_used += req.size;
    }
    GPU_CHECK(vkBindBufferMemory(ctx->device, buf->buffer, buf->memory, 0));
    if (ctx->memory.memoryTypes[type].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT &&
        wanted & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT)
        GPU_CHECK(vkMapMemory(ctx->device, buf->memory, 0, VK_WHOLE_SIZE, 0, &buf->mapped));
    buf->size = size;
    return true;
fail:
    gpu_buffer_destroy(ctx, buf);
    return false;
}

bool gpu_buffer_create(gpu_context *ctx, gpu_buffer *buf, size_t size, const char *what,
                       vkrt_error *err)
{
    return gpu_buffer_create_addressed(ctx, buf, size, false, what, err);
}

bool gpu_buffer_create_addressed(gpu_context *ctx, gpu_buffer *buf, size_t size, bool addressed,
                                 const char *what, vkrt_error *err)
{
    if (size > ctx->max_buffer_bytes) {
        memset(buf, 0, sizeof *buf);
        return vkrt_error_set(err,
                              "%s needs %zu bytes (%.1f MiB), more than one buffer on %s "
                              "holds (%s %llu bytes)",
                              what, size, size / 1048576.0, ctx->properties.deviceName,
                              gpu_buffer_limit_name(ctx, ctx->max_buffer_bytes),
                              (unsigned long long)ctx->max_buffer_bytes);
    }
    if (addressed && !ctx->device_addresses) {
        memset(buf, 0, sizeof *buf);
        return vkrt_error_set(err, "%s: %s has no buffer device addresses", what,
                              ctx->properties.deviceName);
    }
    VkBufferUsageFlags usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                               VK_BUFFER_USAGE_UNIFORM_TEXEL_BUFFER_BIT |
                               VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
                               /* the wave buffer holds indirect dispatch arguments */
                               VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT |
                               (addressed ? VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT : 0);
    if (!create_with_memory(ctx, buf, size, usage, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, err))
        return vkrt_error_prefix(err, "%s (%zu bytes)", what, size);
    return true;
}

const char *gpu_buffer_limit_name(const gpu_context *ctx, VkDeviceSize limit)
{
    if (limit < ctx->max_buffer_bytes)
        return "VKRT_TEST_MAX_BUFFER_BYTES";
    return limit < ctx->properties.limits.maxStorageBufferRange ? "maxMemoryAllocationSize"
                                                                : "maxStorageBufferRange";
}

VkDeviceAddress gpu_buffer_address(const gpu_context *ctx, const gpu_buffer *buf)
{
    VkBufferDeviceAddressInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO,
        .buffer = buf->buffer,
    };
    return ctx->buffer_address(ctx->device, &info);
}

bool gpu_buffer_create_usage(gpu_context *ctx, gpu_buffer *buf, size_t size,
                             VkBufferUsageFlags usage, const char *what, vkrt_error *err)
{
    if (!create_with_memory(ctx, buf, size, usage, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, 0, err))
        return vkrt_error_prefix(err, "%s (%zu bytes)", what, size);
    return true;
}

bool gpu_buffer_view_create(gpu_context *ctx, const gpu_buffer *buf, VkBufferView *view,
                            bool *covered, vkrt_error *err)
{
    const VkDeviceSize texel = 16;
    VkDeviceSize texels = buf->size / texel, max = ctx->properties.limits.maxTexelBufferElements;
    *view = VK_NULL_HANDLE;
    *covered = texels <= max && texels * texel == buf->size;
    if (texels > max)
        texels = max;
    if (texels == 0)
        texels = 1;
    VkBufferViewCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_BUFFER_VIEW_CREATE_INFO,
        .buffer = buf->buffer,
        .format = VK_FORMAT_R32G32B32A32_UINT,
        .range = texels * texel,
    };
    GPU_CHECK(vkCreateBufferView(ctx->device, &info, NULL, view));
    return true;
fail:
    *covered = false;
    return false;
}

void gpu_buffer_view_destroy(gpu_context *ctx, VkBufferView *view)
{
    if (*view && !ctx->lost)
        vkDestroyBufferView(ctx->device, *view, NULL);
    *view = VK_NULL_HANDLE;
}

bool gpu_staging_create(gpu_context *ctx, gpu_buffer *buf, size_t size, vkrt_error *err)
{
    const VkMemoryPropertyFlags host =
        VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
    return create_with_memory(ctx, buf, size,
                              VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT,
                              host, host, err);
}

void gpu_buffer_destroy(gpu_context *ctx, gpu_buffer *buf)
{
    /* The device may still be running work that uses it (see gpu_context.lost). */
    if (ctx->lost) {
        memset(buf, 0, sizeof *buf);
        return;
    }
    if (buf->mapped)
        vkUnmapMemory(ctx->device, buf->memory);
    if (buf->buffer)
        vkDestroyBuffer(ctx->device, buf->buffer, NULL);
    if (buf->memory)
        vkFreeMemory(ctx->device, buf->memory, NULL);
    ctx->memory_used -= buf->device_bytes;
    memset(buf, 0, sizeof *buf);
}

/* The context's kept staging buffer, holding at least size bytes (size <= GPU_STAGING_BYTES),
 * into *staging; the context keeps owning it. */
static bool kept_staging(gpu_context *ctx, size_t size, gpu_buffer *staging, vkrt_error *err)
{
    if (ctx->staging_size < size) {
        gpu_buffer old = {.buffer = ctx->staging_buffer, .memory = ctx->staging_memory,
                          .mapped = ctx->staging_mapped};
        gpu_buffer_destroy(ctx, &old);
        ctx->staging_buffer = VK_NULL_HANDLE;
        ctx->staging_memory = VK_NULL_HANDLE;
        ctx->staging_mapped = NULL;
        ctx->staging_size = 0;
        /* Powers of two from 1 MiB: a few sizes, however the transfers come. */
        size_t grown = (size_t)1 << 20;
        while (grown < size)
            grown *= 2;
        gpu_buffer made;
        if (!gpu_staging_create(ctx, &made, grown, err))
            return false;
        ctx->staging_buffer = made.buffer;
        ctx->staging_memory = made.memory;
        ctx->staging_mapped = made.mapped;
        ctx->staging_size = made.size;
    }
    *staging = (gpu_buffer){.buffer = ctx->staging_buffer, .memory = ctx->staging_memory,
                            .size = ctx->staging_size, .mapped = ctx->staging_mapped};
    return true;
}

/* A staging buffer of size bytes: the context's kept one up to GPU_STAGING_BYTES (*kept), else
 * one of its own that the caller destroys. */
static bool staging_for(gpu_context *ctx, size_t size, gpu_buffer *staging, bool *kept,
                        vkrt_error *err)
{
    *kept = size <= GPU_STAGING_BYTES;
    return *kept ? kept_staging(ctx, size, staging, err)
                 : gpu_staging_create(ctx, staging, size, err);
}

static bool copy_buffer(gpu_context *ctx, VkBuffer src, size_t src_offset, VkBuffer dst,
                        size_t dst_offset, size_t size, vkrt_error *err)
{
    VkCommandBuffer cmd;
    if (!gpu_commands_begin(ctx, &cmd, err))
        return false;
    VkBufferCopy region = {.srcOffset = src_offset, .dstOffset = dst_offset, .size = size};
    vkCmdCopyBuffer(cmd, src, dst, 1, &region);
    return gpu_commands_submit(ctx, err);
}

bool gpu_buffer_create_from(gpu_context *ctx, gpu_buffer *buf, const void *data, size_t size,
                            const char *what, vkrt_error *err)
{
    if (!gpu_buffer_create(ctx, buf, size, what, err))
        return false;
    if (gpu_buffer_upload(ctx, buf, data, size, err))
        return true;
    gpu_buffer_destroy(ctx, buf);
    return false;
}

bool gpu_buffer_upload(gpu_context *ctx, gpu_buffer *buf, const void *data, size_t size,
                       vkrt_error *err)
{
    return gpu_buffer_upload_at(ctx, buf, 0, data, size, err);
}

static void copy_bytes(void *user, size_t at, size_t size, void *dst)
{
    memcpy(dst, (const unsigned char *)user + at, size);
}

bool gpu_buffer_upload_at(gpu_context *ctx, gpu_buffer *buf, size_t offset, const void *data,
                          size_t size, vkrt_error *err)
{
    return gpu_buffer_write(ctx, buf, offset, size, GPU_STAGING_BYTES, copy_bytes, (void *)data,
                            err);
}

bool gpu_buffer_write(gpu_context *ctx, gpu_buffer *buf, size_t offset, size_t size, size_t piece,
                      gpu_write_fn *write, void *user, vkrt_error *err)
{
    if (size == 0)
        return true;
    if (offset > buf->size || size > buf->size - offset)
        return vkrt_error_set(err, "upload of %zu bytes at %zu into a buffer of %zu", size, offset,
                              (size_t)buf->size);
    /* In pieces through one staging buffer: a scene's arrays take gigabytes, which would
     * otherwise be as much pinned host memory again. */
    if (piece == 0 || piece > size)
        piece = size;
    gpu_buffer staging;
    bool kept;
    if (!staging_for(ctx, piece, &staging, &kept, err))
        return false;
    bool ok = true;
    for (size_t done = 0; ok && done < size; done += piece) {
        size_t n = size - done < piece ? size - done : piece;
        write(user, done, n, staging.mapped);
        ok = copy_buffer(ctx, staging.buffer, 0, buf->buffer, offset + done, n, err);
    }
    if (!kept)
        gpu_buffer_destroy(ctx, &staging);
    return ok;
}

bool gpu_buffer_download(gpu_context *ctx, const gpu_buffer *buf, void *data, size_t size,
                         vkrt_error *err)
{
    if (size == 0)
        return true;
    if (size > buf->size)
        return vkrt_error_set(err, "download of %zu bytes from a buffer of %zu", size,
                              (size_t)buf->size);
    gpu_buffer staging;
    bool kept;
    if (!staging_for(ctx, size, &staging, &kept, err))
        return false;
    bool ok = copy_buffer(ctx, buf->buffer, 0, staging.buffer, 0, size, err);
    if (ok)
        memcpy(data, staging.mapped, size);
    if (!kept)
        gpu_buffer_destroy(ctx, &staging);
    return ok;
}

bool gpu_buffer_zero(gpu_context *ctx, gpu_buffer *buf, vkrt_error *err)
{
    VkCommandBuffer cmd;
    if (!gpu_commands_begin(ctx, &cmd, err))
        return false;
    vkCmdFillBuffer(cmd, buf->buffer, 0, VK_WHOLE_SIZE, 0);
    return gpu_commands_submit(ctx, err);
}
