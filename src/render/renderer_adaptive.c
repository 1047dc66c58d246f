/*
 * renderer_adaptive.c: sampling to a target error (vkrt_render_desc.target_error, renderer.h).
 * Its buffers, its two kernels' place in a frame (glsl/adapt.comp, twice, after every sample pass,
 * then glsl/adapt_dispatch.comp, which writes raygen's indirect dispatch), and the error reached,
 * read back once a frame. Without a target none of it runs: the buffers are the minimal ones that keep
 * the bindings valid, and the kernels are neither compiled nor recorded.
 */
#include <math.h>
#include <stdlib.h>

#include "../../glsl/lib/ray_record.glsl"
#include "renderer_private.h"
/* After shared.h (renderer_private.h), whose uint it uses. */
#include "../../glsl/lib/adaptive.glsl"

bool renderer_adaptive_create_buffers(vkrt_renderer *r, vkrt_error *err)
{
    size_t pixels = (size_t)r->width * r->height;
    bool on = r->target_error > 0;
    return gpu_buffer_create(r->ctx, &r->pixel_stats, on ? pixels * sizeof(PixelStats) : 0,
                             "pixel statistics", err) &&
           gpu_buffer_create(r->ctx, &r->active_pixels,
                             on ? sizeof(ActivePixels) + pixels * sizeof(uint32_t) : 0,
                             "active pixel list", err) &&
           gpu_buffer_create(r->ctx, &r->sample_luminance,
                             on ? pixels * r->batch * sizeof(float) : 0, "sample luminance", err) &&
           /* The list's `appended` starts at 0; adapt_dispatch.comp sets it back to 0 after
            * every pass, so it is 0 whenever a frame starts. (Fresh memory is not zero: a CPU device's
            * comes from the host heap, garbage under the tests' MALLOC_PERTURB_.) adapt.comp resets the statistics and slots when a frame starts. */
           (!on || gpu_buffer_zero(r->ctx, &r->active_pixels, err));
}

void renderer_adaptive_destroy_buffers(vkrt_renderer *r)
{
    gpu_buffer_destroy(r->ctx, &r->sample_luminance);
    gpu_buffer_destroy(r->ctx, &r->active_pixels);
    gpu_buffer_destroy(r->ctx, &r->pixel_stats);
}

void renderer_adaptive_record_adapt(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams params,
                                    uint32_t done, uint32_t taken)
{
    params.image.z = done;
    params.counts.z = taken;
    /* Each pixel's samples folded and judged, then the list kept from the judgements of its
     * neighbours (glsl/adapt.comp): two dispatches, since a pixel reads its neighbours'. */
    frame_set_adapt_step(&params, VKRT_ADAPT_FOLD);
    gpu_dispatch(cmd, &r->adapt, &r->set, &params, r->width * r->height);
    frame_set_adapt_step(&params, VKRT_ADAPT_SELECT);
    gpu_dispatch(cmd, &r->adapt, &r->set, &params, r->width * r->height);
    params.counts.z = r->batch;
    gpu_dispatch(cmd, &r->adapt_dispatch, &r->set, &params, 1);
}

void renderer_adaptive_record_raygen(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams *params,
                                     uint32_t taken)
{
    params->counts.z = taken;
    gpu_dispatch_indirect(cmd, &r->raygen, &r->set, params, &r->active_pixels, 0);
}

/* A frame sampled to a target error: submissions of passes up to the cap, each as many samples
 * as the frame has so far (the first the fewest a pixel takes, VKRT_ADAPTIVE_MIN_SAMPLES), until no
 * pixel is listed: the host waits a few times a frame, never per pixel, and the passes past the
 * last pixel's (empty ones: no rays) are at most as many as it took. A profile times the frame in
 * one submission. */
bool renderer_adaptive_render(vkrt_renderer *r, const vkrt_config_camera *camera,
                              uint32_t frame_index, vkrt_frame_stats *stats, vkrt_error *err)
{
    vkrt_frame_stats total = {0}, part;
    uint32_t done = 0, chunk = r->profile ? r->samples : VKRT_ADAPTIVE_MIN_SAMPLES;
    while (done < r->samples) {
        uint32_t count = chunk < r->samples - done ? chunk : r->samples - done;
        if (!vkrt_renderer_add_samples(r, camera, frame_index, done, count, &part, err))
            return false;
        done += count;
        total.seconds += part.seconds;
        total.primary_rays += part.primary_rays;
        total.shadow_rays += part.shadow_rays;
        total.secondary_rays += part.secondary_rays;
        total.attempts = part.attempts > total.attempts ? part.attempts : total.attempts;
        total.dropped_rays += part.dropped_rays;
        total.nonfinite += part.nonfinite;
        total.ray_capacity = part.ray_capacity;
        total.active_pixels = part.active_pixels;
        total.profile = part.profile;
        if (part.active_pixels == 0)
            break;
        chunk = done;
    }
    if (stats)
        *stats = total;
    return true;
}

static int compare_floats(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

void vkrt_convergence_of(const PixelStats *stats, size_t pixels, float target,
                         vkrt_convergence *out, float *sorted, float *estimates,
                         uint32_t *samples)
{
    *out = (vkrt_convergence){.target = target, .pixels = (uint32_t)pixels};
    double squares = 0, total = 0;
    size_t estimated = 0;
    out->min_samples = UINT32_MAX;
    for (size_t i = 0; i < pixels; ++i) {
        const PixelStats *s = &stats[i];
        float e = adaptive_relative_error(s->mean, s->m2, s->samples);
        total += s->samples;
        out->converged += e <= target;
        out->min_samples = s->samples < out->min_samples ? s->samples : out->min_samples;
        out->max_samples = s->samples > out->max_samples ? s->samples : out->max_samples;
        if (estimates)
            estimates[i] = e;
        if (samples)
            samples[i] = s->samples;
        /* Fewer than 2 samples give adaptive.glsl's sentinel, not an estimate: counted apart,
         * so that it is never averaged into the figures or reported as one. */
        if (s->samples < 2) {
            out->unestimated++;
            continue;
        }
        sorted[estimated++] = e;
        squares += (double)e * e;
    }
    if (pixels == 0)
        out->min_samples = 0;
    out->mean_samples = pixels ? total / (double)pixels : 0.0;
    if (estimated) {
        out->rms_error = sqrt(squares / (double)estimated);
        qsort(sorted, estimated, sizeof *sorted, compare_floats);
        out->p99_error = sorted[(size_t)floor(0.99 * (double)(estimated - 1))];
        out->max_error = sorted[estimated - 1];
    }
}

bool vkrt_renderer_convergence(vkrt_renderer *r, vkrt_convergence *out, float *estimates,
                               uint32_t *samples, vkrt_error *err)
{
    *out = (vkrt_convergence){.target = r->target_error};
    if (r->target_error <= 0)
        return vkrt_error_set(err, "the renderer samples uniformly: no target error");
    size_t pixels = (size_t)r->width * r->height;
    PixelStats *stats = malloc(pixels * sizeof *stats);
    float *sorted = malloc(pixels * sizeof *sorted);
    bool ok = stats && sorted;
    if (!ok)
        vkrt_error_set(err, "out of memory reading back %zu pixels' statistics", pixels);
    ok = ok && gpu_buffer_download(r->ctx, &r->pixel_stats, stats, pixels * sizeof *stats, err);
    if (ok)
        vkrt_convergence_of(stats, pixels, r->target_error, out, sorted, estimates, samples);
    free(stats);
    free(sorted);
    return ok;
}
