/* array.c: device arrays split over several buffers where one cannot hold them (see array.h). */
#include "array.h"

#include <stdio.h>
#include <string.h>

/* bytes for a message: in bytes, MiB or GiB, whichever reads best. */
static const char *size_text(char *text, size_t size, double bytes)
{
    if (bytes < 1048576.0)
        snprintf(text, size, "%.0f bytes", bytes);
    else if (bytes < 1073741824.0)
        snprintf(text, size, "%.1f MiB", bytes / 1048576.0);
    else
        snprintf(text, size, "%.2f GiB", bytes / 1073741824.0);
    return text;
}

/* The log2 of the largest power of two of elements whose bytes fit limit; at least 1 (shift 0
 * means "one buffer" to the kernels), and *fits false when not even two elements fit. */
static uint32_t chunk_shift(size_t element_size, VkDeviceSize limit, bool *fits)
{
    uint32_t shift = 1;
    *fits = 2 * (VkDeviceSize)element_size <= limit;
    while (*fits && shift < 62 && ((VkDeviceSize)element_size << (shift + 1)) <= limit)
        ++shift;
    return shift;
}

uint32_t gpu_array_shift_for(const gpu_context *ctx, size_t element_size, size_t count)
{
    bool fits;
    if (count == 0 || element_size * count <= ctx->split_bytes)
        return 0;
    return chunk_shift(element_size, ctx->split_bytes, &fits);
}

bool gpu_array_create(gpu_context *ctx, gpu_array *a, size_t element_size, size_t count,
                      const char *what, vkrt_error *err)
{
    memset(a, 0, sizeof *a);
    a->element_size = element_size;
    a->count = count;
    a->chunk_count = 1;
    size_t bytes = element_size * count;
    if (count != 0 && bytes / count != element_size)
        return vkrt_error_set(err, "%s: %zu elements of %zu bytes overflow the address space", what,
                              count, element_size);
    if (bytes <= ctx->split_bytes)
        return gpu_buffer_create(ctx, &a->chunks[0], bytes, what, err);
    const char *device = ctx->properties.deviceName;
    const char *limit = gpu_buffer_limit_name(ctx, ctx->split_bytes);
    bool fits;
    uint32_t shift = chunk_shift(element_size, ctx->split_bytes, &fits);
    size_t per_chunk = (size_t)1 << shift;
    size_t chunks = fits ? (count + per_chunk - 1) / per_chunk : 0;
    char need[32], most[32], chunk[32];
    size_text(need, sizeof need, (double)bytes);
    size_text(most, sizeof most, (double)ctx->split_bytes);
    size_text(chunk, sizeof chunk, (double)per_chunk * (double)element_size);
    if (!ctx->device_addresses)
        return vkrt_error_set(err,
                              "the scene does not fit %s: its %s take %s (%zu x %zu bytes), more "
                              "than one buffer holds (%s: %s), and the device has no buffer "
                              "device addresses to reach several",
                              device, what, need, count, element_size, limit, most);
    if (!fits || chunks > GPU_ARRAY_MAX_CHUNKS)
        return vkrt_error_set(err,
                              "the scene does not fit %s: its %s take %s (%zu x %zu bytes), more "
                              "than %u buffers of %s hold (%s: %s)",
                              device, what, need, count, element_size, GPU_ARRAY_MAX_CHUNKS,
                              fits ? chunk : "two elements", limit, most);
    a->shift = shift;
    a->chunk_count = (uint32_t)chunks;
    for (uint32_t c = 0; c < a->chunk_count; ++c) {
        size_t first = (size_t)c << shift;
        size_t n = count - first < per_chunk ? count - first : per_chunk;
        char name[160];
        snprintf(name, sizeof name, "%s (part %u of %u)", what, c + 1, a->chunk_count);
        if (!gpu_buffer_create_addressed(ctx, &a->chunks[c], n * element_size, true, name, err)) {
            gpu_array_destroy(ctx, a);
            return false;
        }
    }
    return true;
}

/* gpu_buffer_write's writer for a chunk: bytes from the chunk's start, to elements. */
typedef struct chunk_writer {
    gpu_array_fill_fn *fill;
    void *user;
    size_t first; /* the chunk's first element */
    size_t element_size;
} chunk_writer;

static void write_chunk(void *user, size_t at, size_t size, void *dst)
{
    const chunk_writer *w = user;
    w->fill(w->user, w->first + at / w->element_size, size / w->element_size, dst);
}

bool gpu_array_fill(gpu_context *ctx, gpu_array *a, gpu_array_fill_fn *fill, void *user,
                    vkrt_error *err)
{
    if (a->count == 0)
        return true;
    /* Pieces of whole elements. */
    size_t piece = GPU_STAGING_BYTES / a->element_size * a->element_size;
    if (piece == 0)
        piece = a->element_size;
    for (uint32_t c = 0; c < a->chunk_count; ++c) {
        chunk_writer w = {fill, user, a->shift ? (size_t)c << a->shift : 0, a->element_size};
        size_t n = a->chunk_count == 1      ? a->count
                   : c + 1 < a->chunk_count ? (size_t)1 << a->shift
                                            : a->count - w.first;
        if (!gpu_buffer_write(ctx, &a->chunks[c], 0, n * a->element_size, piece, write_chunk, &w,
                              err))
            return false;
    }
    return true;
}

typedef struct copy_source {
    const unsigned char *data;
    size_t element_size;
} copy_source;

static void copy_elements(void *user, size_t first, size_t count, void *dst)
{
    const copy_source *s = user;
    memcpy(dst, s->data + first * s->element_size, count * s->element_size);
}

bool gpu_array_create_from(gpu_context *ctx, gpu_array *a, const void *data, size_t element_size,
                           size_t count, const char *what, vkrt_error *err)
{
    copy_source source = {data, element_size};
    if (!gpu_array_create(ctx, a, element_size, count, what, err))
        return false;
    if (gpu_array_fill(ctx, a, copy_elements, &source, err))
        return true;
    gpu_array_destroy(ctx, a);
    return false;
}

void gpu_array_destroy(gpu_context *ctx, gpu_array *a)
{
    for (uint32_t c = GPU_ARRAY_MAX_CHUNKS; c-- > 0;)
        gpu_buffer_destroy(ctx, &a->chunks[c]);
    memset(a, 0, sizeof *a);
}

VkDeviceSize gpu_array_device_bytes(const gpu_array *a)
{
    VkDeviceSize bytes = 0;
    for (uint32_t c = 0; c < GPU_ARRAY_MAX_CHUNKS; ++c)
        bytes += a->chunks[c].device_bytes;
    return bytes;
}
