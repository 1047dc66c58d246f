/*
 * trace_api.c: tracing rays given by the caller (see trace_api.h).
 */
#include "trace_api.h"

#include "renderer_private.h"

bool vkrt_renderer_trace(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                         Hit *hits, uint32_t repeats, double *gpu_ms, vkrt_error *err)
{
    size_t capacity = r->capacity;
    if (count > capacity)
        return vkrt_error_set(err, "%u rays exceed the renderer's %zu", count, capacity);
    if (repeats == 0)
        repeats = 1;
    if (any_hit && !renderer_kernels_compile_occlusion(r, err))
        return false;
    FrameParams params = {0};
    params.counts = (uvec4){r->triangle_count, r->light_count, count, 0};
    params.wave = (uvec4){0, 0, 0, r->capacity};
    gpu_timer timer = {0};
    if (!gpu_buffer_upload(r->ctx, &r->rays, rays, count * sizeof *rays, err) ||
        (gpu_ms && !gpu_timer_create(r->ctx, &timer, repeats + 1, err)))
        return false;
    VkCommandBuffer cmd;
    bool ok = gpu_commands_begin(r->ctx, &cmd, err);
    if (ok) {
        /* Back to back in one submission, so the GPU never idles between repeats (its clocks
         * would fall, and each timing would measure the climb back). */
        if (gpu_ms) {
            gpu_timer_reset(cmd, &timer);
            gpu_timer_write(cmd, &timer, 0);
        }
        for (uint32_t i = 0; i < repeats; ++i) {
            renderer_record_trace(r, cmd, &params, any_hit, count, false);
            if (gpu_ms)
                gpu_timer_write(cmd, &timer, i + 1);
        }
        ok = gpu_commands_submit(r->ctx, err);
        for (uint32_t i = 0; ok && gpu_ms && i < repeats; ++i)
            ok = gpu_timer_ms(r->ctx, &timer, i, i + 1, &gpu_ms[i], err);
        ok = ok && gpu_buffer_download(r->ctx, &r->hits, hits, count * sizeof *hits, err);
    }
    gpu_timer_destroy(r->ctx, &timer);
    if (!ok)
        return false;
    if (!any_hit)
        for (uint32_t i = 0; i < count; ++i)
            if (hits[i].triangle != VKRT_NO_HIT)
                hits[i].triangle = (uint32_t)vkrt_accel_original_hit(&r->accel, hits[i].triangle);
    return true;
}

bool vkrt_renderer_trace_stats(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                               Hit *hits, vkrt_traversal_stats *stats, vkrt_error *err)
{
    Counters c;
    if (!gpu_buffer_zero(r->ctx, &r->counters, err) ||
        !vkrt_renderer_trace(r, rays, count, any_hit, hits, 1, NULL, err) ||
        !gpu_buffer_download(r->ctx, &r->counters, &c, sizeof c, err))
        return false;
    double rays_traced = c.trace_rays ? c.trace_rays : 1;
    double slots = (double)c.trace_widest * c.subgroup_size;
    *stats = (vkrt_traversal_stats){
        .rays = c.trace_rays,
        .steps_per_ray = c.trace_steps / rays_traced,
        .tests_per_ray = c.trace_tests / rays_traced,
        .simd_utilisation = slots > 0 ? c.trace_busy / slots : 0,
        .subgroup_size = c.subgroup_size,
    };
    return true;
}

bool vkrt_renderer_trace_kernel_statistics(vkrt_renderer *r, char *closest, size_t closest_size,
                                           char *any, size_t any_size, vkrt_error *err)
{
    return renderer_kernels_compile_occlusion(r, err) &&
           gpu_pipeline_statistics(r->ctx, &r->trace, closest, closest_size, err) &&
           gpu_pipeline_statistics(r->ctx, &r->occlusion, any, any_size, err);
}

bool vkrt_renderer_print_kernel_statistics(vkrt_renderer *r, FILE *out, vkrt_error *err)
{
    /* The frame's kernels in dispatch order. */
    const struct {
        const char *name;
        const gpu_pipeline *pipe;
    } kernels[] = {{"raygen", &r->raygen}, {"trace", &r->trace}, {"light", &r->light},
                   {"count", &r->count},   {"prepare", &r->prepare}, {"shade", &r->shade}};
    for (size_t i = 0; i < sizeof kernels / sizeof kernels[0]; ++i) {
        char text[2048];
        if (!gpu_pipeline_statistics(r->ctx, kernels[i].pipe, text, sizeof text, err))
            return false;
        fprintf(out, "vkrt: kernel %s: %s\n", kernels[i].name, text);
    }
    return true;
}
