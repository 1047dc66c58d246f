/*
 * array.h: a device array of fixed-size elements that may be larger than one buffer can hold
 * (a storage binding reaches maxStorageBufferRange bytes, often 4 GiB, and a scene of a hundred
 * million triangles has more). An array that fits one buffer is one buffer, bound and read as any
 * other (shift 0). A larger one is split into chunks of 2^shift elements, each a buffer of its
 * own with a device address, through which the kernels reach it (glsl/lib/bindings.glsl).
 */
#ifndef VKRT_GPU_ARRAY_H
#define VKRT_GPU_ARRAY_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "buffer.h"

/* The most chunks an array may have (glsl/shared.h VKRT_MAX_CHUNKS is the same number). */
#define GPU_ARRAY_MAX_CHUNKS 64u

typedef struct gpu_array {
    gpu_buffer chunks[GPU_ARRAY_MAX_CHUNKS]; /* chunk c holds elements c << shift on */
    uint32_t chunk_count;                    /* 1 for an array that fits one buffer */
    uint32_t shift;                          /* log2 of the elements per chunk; 0: one buffer */
    size_t element_size;
    size_t count;
} gpu_array;

/* Puts elements first .. first + count - 1 into dst. */
typedef void gpu_array_fill_fn(void *user, size_t first, size_t count, void *dst);

/* Creates an array of count elements of element_size bytes (count 0: a minimal buffer that keeps
 * a binding valid): one buffer where ctx->split_bytes allows, else chunks of the largest
 * power of two of elements that fits one buffer. An array that needs more than
 * GPU_ARRAY_MAX_CHUNKS chunks, or any chunks on a device without buffer device addresses, is
 * refused with its size and the limit ("the scene does not fit ..."); so is one the device's
 * memory cannot hold (gpu_buffer_create). what names it in messages. On failure nothing is left
 * allocated. */
bool gpu_array_create(gpu_context *ctx, gpu_array *a, size_t element_size, size_t count,
                      const char *what, vkrt_error *err);

/* The shift gpu_array_create gives an array of count elements of element_size bytes: 0 where one
 * buffer holds it, else log2 of the elements per chunk (what the kernels are compiled for, known
 * before the array is made). */
uint32_t gpu_array_shift_for(const gpu_context *ctx, size_t element_size, size_t count);

/* Fills the whole array from what fill writes, through staging buffers of at most
 * GPU_STAGING_BYTES, and waits until done. */
bool gpu_array_fill(gpu_context *ctx, gpu_array *a, gpu_array_fill_fn *fill, void *user,
                    vkrt_error *err);

/* gpu_array_create, then the count elements at data uploaded. */
bool gpu_array_create_from(gpu_context *ctx, gpu_array *a, const void *data, size_t element_size,
                           size_t count, const char *what, vkrt_error *err);

/* Frees the chunks and zeroes the array. Safe on a zeroed one. */
void gpu_array_destroy(gpu_context *ctx, gpu_array *a);

/* Device-local memory the array holds. */
VkDeviceSize gpu_array_device_bytes(const gpu_array *a);

#endif
