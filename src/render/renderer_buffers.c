/*
 * renderer_buffers.c: the buffers whose size follows the image and the rays of a depth: ray
 * buffers sized from counts (one ray per pixel to start, doubled when a depth needs more, within
 * the device's limits), and the one descriptor set that binds them all.
 */
#include <stdio.h>

#include "renderer_private.h"

/* The ray buffers may take at most this share of the device's largest memory heap. */
static const uint32_t ray_memory_share = 4;

/* The most rays a ray buffer may hold: each buffer within one buffer's limit, all the
 * per-ray buffers together within a share of the largest device-local heap. */
uint32_t renderer_max_ray_capacity(const vkrt_renderer *r)
{
    uint64_t by_range = r->ctx->max_buffer_bytes / sizeof(Ray);
    uint64_t words = r->light_words ? r->light_words : 1;
    uint64_t by_visibility = r->ctx->max_buffer_bytes / (4 * words);
    VkDeviceSize heap = 0;
    for (uint32_t i = 0; i < r->ctx->memory.memoryHeapCount; ++i)
        if ((r->ctx->memory.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) &&
            r->ctx->memory.memoryHeaps[i].size > heap)
            heap = r->ctx->memory.memoryHeaps[i].size;
    uint64_t per_ray = 2 * sizeof(Ray) + sizeof(Hit) + 4 * words + 2 * sizeof(uint32_t) +
                       (r->material_order ? sizeof(uint32_t) : 0);
    uint64_t by_memory = heap / ray_memory_share / per_ray;
    uint64_t cap = by_range < by_visibility ? by_range : by_visibility;
    cap = by_memory < cap ? by_memory : cap;
    return cap > UINT32_MAX / 2 ? UINT32_MAX / 2 : (uint32_t)cap;
}

void renderer_destroy_ray_buffers(vkrt_renderer *r)
{
    gpu_buffer *buffers[] = {&r->rays, &r->rays_b, &r->hits, &r->visibility, &r->slots,
                             &r->order_buffer};
    for (size_t i = 0; i < sizeof buffers / sizeof *buffers; ++i)
        gpu_buffer_destroy(r->ctx, buffers[i]);
}

/* The buffers with one entry per ray of a depth, for r->capacity rays. */
static bool create_ray_buffers(vkrt_renderer *r, vkrt_error *err)
{
    size_t n = r->capacity;
    size_t words = r->light_words ? r->light_words : 1;
    /* Two words per ray: the first slot and the number of the rays its material casts. */
    size_t slot_words = n * 2;
    /* order.comp's bins (totals and cursors) per depth, then a place per ray. */
    size_t order_words =
        r->material_order ? ((size_t)r->max_depth + 1) * 2 * VKRT_ORDER_BINS + n : 1;
    char what[64];
    snprintf(what, sizeof what, "ray buffer (%zu rays)", n);
    return gpu_buffer_create(r->ctx, &r->rays, n * sizeof(Ray), what, err) &&
           gpu_buffer_create(r->ctx, &r->rays_b, n * sizeof(Ray), what, err) &&
           gpu_buffer_create(r->ctx, &r->hits, n * sizeof(Hit), "hit buffer", err) &&
           gpu_buffer_create(r->ctx, &r->visibility, n * words * sizeof(uint32_t),
                             "light visibility buffer", err) &&
           gpu_buffer_create(r->ctx, &r->slots, slot_words * sizeof(uint32_t), "ray slot buffer",
                             err) &&
           gpu_buffer_create(r->ctx, &r->order_buffer, order_words * sizeof(uint32_t),
                             "material order buffer", err);
}

bool renderer_create_frame_buffers(vkrt_renderer *r, vkrt_error *err)
{
    size_t pixels = (size_t)r->width * r->height;
    return create_ray_buffers(r, err) &&
           gpu_buffer_create(r->ctx, &r->image, pixels * sizeof(vec4), "image", err) &&
           gpu_buffer_create(r->ctx, &r->counters, sizeof(Counters), "counters", err) &&
           gpu_buffer_create(r->ctx, &r->waves, (r->max_depth + 2) * sizeof(WaveState),
                             "wave buffer", err) &&
           renderer_adaptive_create_buffers(r, err) && renderer_aov_create_buffer(r, err);
}

void renderer_bind_all(vkrt_renderer *r)
{
    const gpu_buffer *bound[VKRT_STORAGE_BINDINGS] = {
        [VKRT_BINDING_RAYS] = &r->rays,
        [VKRT_BINDING_HITS] = &r->hits,
        /* A split array's first chunk: its binding stays valid, unread. */
        [VKRT_BINDING_TRIANGLES] = &r->triangles.chunks[0],
        [VKRT_BINDING_NORMALS] = &r->normals.chunks[0],
        [VKRT_BINDING_TRIANGLE_MATERIAL] = &r->triangle_material.chunks[0],
        [VKRT_BINDING_MATERIALS] = &r->materials,
        [VKRT_BINDING_LIGHTS] = &r->lights,
        [VKRT_BINDING_IMAGE] = &r->image,
        [VKRT_BINDING_COUNTERS] = &r->counters,
        [VKRT_BINDING_GRID_INFO] = &r->accel.info,
        [VKRT_BINDING_ACCEL_NODES] = &r->accel.nodes.chunks[0],
        [VKRT_BINDING_GRID_REFS] = &r->accel.refs.chunks[0],
        [VKRT_BINDING_RAYS_B] = &r->rays_b,
        [VKRT_BINDING_WAVES] = &r->waves,
        [VKRT_BINDING_VISIBILITY] = &r->visibility,
        [VKRT_BINDING_SLOTS] = &r->slots,
        [VKRT_BINDING_TEXCOORDS] = &r->texcoords.chunks[0],
        [VKRT_BINDING_TEXTURE_INFOS] = &r->texture_infos,
        [VKRT_BINDING_TEXELS] = &r->texels.chunks[0],
        [VKRT_BINDING_EMITTERS] = &r->emitters,
        [VKRT_BINDING_ENVIRONMENT] = &r->environment,
        [VKRT_BINDING_PIXEL_STATS] = &r->pixel_stats,
        [VKRT_BINDING_ACTIVE_PIXELS] = &r->active_pixels,
        [VKRT_BINDING_SAMPLE_LUMINANCE] = &r->sample_luminance,
        [VKRT_BINDING_SPLIT_ADDRESSES] = &r->split_addresses,
        [VKRT_BINDING_MATERIAL_ORDER] = &r->order_buffer,
        [VKRT_BINDING_PLASTIC_TABLES] = &r->plastic_tables,
        [VKRT_BINDING_AOVS] = &r->aov_planes,
    };
    for (uint32_t i = 0; i < VKRT_STORAGE_BINDINGS; ++i)
        gpu_storage_set_bind(r->ctx, &r->set, i, bound[i]);
    gpu_storage_set_bind_view(r->ctx, &r->set, VKRT_BINDING_TRIANGLE_TEXELS, r->triangle_view);
    gpu_storage_set_bind_view(r->ctx, &r->set, VKRT_BINDING_NODE_TEXELS, r->node_view);
}

bool renderer_grow_ray_buffers(vkrt_renderer *r, uint64_t needed, vkrt_error *err)
{
    uint64_t capacity = r->capacity;
    while (capacity < needed)
        capacity *= 2;
    if (capacity > r->max_capacity)
        capacity = r->max_capacity;
    renderer_destroy_ray_buffers(r);
    r->capacity = (uint32_t)capacity;
    if (!create_ray_buffers(r, err))
        return vkrt_error_prefix(err, "growing the ray buffers to %u rays", r->capacity);
    renderer_bind_all(r);
    return true;
}
