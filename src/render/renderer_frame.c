/*
 * renderer_frame.c: one frame, recorded and run: per sample pass raygen, then per depth trace,
 * light, count, prepare and shade (renderer.h), all in one command buffer; the host waits once,
 * reads the counters, and renders again with larger ray buffers when a depth outgrew them.
 */
#include <stdlib.h>
#include <string.h>

#include "../clock.h"
#include "../../glsl/lib/ray_record.glsl"
#include "camera_frame.h"
#include "renderer_private.h"

/* A device's loop budget (the iterations a CPU device allows an invocation, tuning.c) also bounds the
 * light kernel, whose brute-force shadow rays each loop over every triangle: refuse rather than
 * render shadows that silently miss triangles. */
static bool check_loop_budget(const vkrt_renderer *r, vkrt_error *err)
{
    const uint32_t budget = r->tuning.loop_budget;
    if (r->accel.stats.kind != VKRT_ACCEL_BRUTE || budget == 0)
        return true;
    uint64_t shadow_lights = 0;
    for (uint32_t i = 0; i < r->light_count; ++i)
        shadow_lights += r->light_kinds[i] != VKRT_LIGHT_KIND_AMBIENT;
    shadow_lights += r->emitter_light;
    uint64_t iterations = (uint64_t)r->triangle_count * shadow_lights;
    if (iterations > budget - r->light_count)
        return vkrt_error_set(err,
                              "brute force with %u triangles and %u shadowing lights needs %llu "
                              "loop iterations per pixel; this device stops shaders after "
                              "%u: use accel grid or bvh",
                              r->triangle_count, (unsigned)shadow_lights,
                              (unsigned long long)iterations, budget);
    return true;
}

void renderer_record_trace(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams *params,
                           bool any_hit, uint32_t count, bool indirect)
{
    const gpu_pipeline *pipe = any_hit ? &r->occlusion : &r->trace;
    VkDeviceSize wave_offset = (VkDeviceSize)params->wave.y * sizeof(WaveState);
    uint32_t n = r->triangle_count;
    const uint32_t block = r->tuning.brute_force_block;
    for (uint32_t first = 0;; first += block) {
        bool brute = r->accel.stats.kind == VKRT_ACCEL_BRUTE;
        uint32_t end = !brute || n - first < block ? n : first + block;
        frame_set_brute_range(params, brute ? first : 0, end, first > 0);
        if (indirect)
            gpu_dispatch_indirect(cmd, pipe, &r->set, params, &r->waves, wave_offset);
        else
            gpu_dispatch(cmd, pipe, &r->set, params, count);
        if (end >= n)
            break;
    }
    frame_set_brute_range(params, 0, n, false);
}

/* Zeroes size bytes of buf from the start, between the compute work before (which may have read
 * or written them) and after it. */
static void record_zero(VkCommandBuffer cmd, const gpu_buffer *buf, VkDeviceSize size)
{
    VkMemoryBarrier before = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT,
                         0, 1, &before, 0, NULL, 0, NULL);
    vkCmdFillBuffer(cmd, buf->buffer, 0, size, 0);
    VkMemoryBarrier after = {
        .sType = VK_STRUCTURE_TYPE_MEMORY_BARRIER,
        .srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT,
        .dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT,
    };
    vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                         0, 1, &after, 0, NULL, 0, NULL);
}

/* Motion blur: the camera of the pass that starts at sample s of a moving frame. Each pass (one
 * sample a pixel: renderer.c) takes its own time in the open shutter, stratified: pass k of n at
 * shutter * (k + jitter) / n, the jitter hashed from the frame seed and k. */
static void moving_camera(const vkrt_renderer *r, uint32_t s, uint32_t frame_seed,
                          FrameParams *params)
{
    /* A Weyl sequence over the passes, offset per frame: jitters spread evenly in [0, 1). */
    uint32_t bits = (frame_seed + 1u) * 0x9E3779B9u + s * 0x6C8E9CF5u;
    float jitter = (float)(bits >> 8) * (1.0f / 16777216.0f);
    float t = r->shutter * ((float)s + jitter) / (float)r->samples;
    vkrt_config_camera at;
    vkrt_camera_between(&r->camera, &r->next_camera, t, &at);
    vkrt_camera_params(&at, r->width, r->height, params);
    params->eye.w = r->min_importance;
}

/* Records sample passes [first, end) of one frame. There are no transfer commands: raygen clears
 * the image (pass 0) and resets the wave table, so the passes are dispatches and
 * compute-to-compute barriers only. */
static void record_passes(vkrt_renderer *r, VkCommandBuffer cmd, FrameParams params,
                          uint32_t first, uint32_t end, profile_recorder *p)
{
    uint32_t pixels = r->width * r->height;
    bool adaptive = r->target_error > 0;
    /* Adaptive sampling: the frame starts with every pixel listed (renderer_adaptive.c). */
    if (adaptive && first == 0)
        renderer_adaptive_record_adapt(r, cmd, params, 0, r->batch);
    for (uint32_t s = first; s < end; s += r->batch) {
        /* Samples [s, s + batch) of every pixel (or of the listed ones) in one pass
         * (raygen.comp). */
        uint32_t taken = end - s < r->batch ? end - s : r->batch;
        params.image.z = s;
        if (r->has_next && r->shutter > 0)
            moving_camera(r, s, params.counts.w, &params);
        params.wave = (uvec4){0, 0, r->max_depth, r->capacity};
        if (adaptive) {
            renderer_adaptive_record_raygen(r, cmd, &params, taken);
        } else {
            params.counts.z = pixels * taken;
            gpu_dispatch(cmd, &r->raygen, &r->set, &params, pixels * taken);
        }
        profile_recorder_mark(cmd, p, 0, VKRT_KERNEL_RAYGEN);
        params.counts.z = VKRT_RAYS_OF_WAVE;
        for (uint32_t depth = 0; depth <= r->max_depth; ++depth) {
            params.wave.x = depth & 1;
            params.wave.y = depth;
            VkDeviceSize wave = (VkDeviceSize)depth * sizeof(WaveState);
            renderer_record_trace(r, cmd, &params, false, 0, true);
            profile_recorder_mark(cmd, p, depth, VKRT_KERNEL_TRACE);
            if (r->material_order && depth >= VKRT_ORDER_FIRST_DEPTH) {
                FrameParams order = params;
                frame_set_order_step(&order, VKRT_ORDER_COUNT);
                gpu_dispatch_indirect(cmd, &r->order, &r->set, &order, &r->waves, wave);
                frame_set_order_step(&order, VKRT_ORDER_PLACE);
                gpu_dispatch_indirect(cmd, &r->order, &r->set, &order, &r->waves, wave);
                profile_recorder_mark(cmd, p, depth, VKRT_KERNEL_ORDER);
            }
            gpu_dispatch_indirect(cmd, &r->light, &r->set, &params, &r->waves, wave);
            profile_recorder_mark(cmd, p, depth, VKRT_KERNEL_LIGHT);
            if (depth < r->max_depth) {
                gpu_dispatch_indirect(cmd, &r->count, &r->set, &params, &r->waves, wave);
                profile_recorder_mark(cmd, p, depth, VKRT_KERNEL_COUNT);
                gpu_dispatch(cmd, &r->prepare, &r->set, &params, 1);
                profile_recorder_mark(cmd, p, depth, VKRT_KERNEL_PREPARE);
            }
            gpu_dispatch_indirect(cmd, &r->shade, &r->set, &params, &r->waves, wave);
            profile_recorder_mark(cmd, p, depth, VKRT_KERNEL_SHADE);
        }
        if (adaptive)
            renderer_adaptive_record_adapt(r, cmd, params, s + taken, taken);
    }
}

/* Records and runs sample passes [first, end) into the image (cleared first when first is 0);
 * counters hold their statistics afterwards. With a profile (r->profile and stats), the frame is
 * recorded warmups + timed times back to back in one submission (only when first is 0: each
 * repetition then starts from a cleared image, so the picture is the same), with timestamps
 * around every dispatch of the timed ones; stats gets the medians. */
static bool run_passes(vkrt_renderer *r, FrameParams params, uint32_t first, uint32_t end,
                       uint32_t warmups, uint32_t timed, double *seconds, vkrt_frame_stats *stats,
                       vkrt_error *err)
{
    if (!r->profile || !stats || first != 0 || timed == 0) {
        warmups = 0;
        timed = 1;
    }
    profile_recorder profile, *p = NULL;
    if (r->profile && stats) {
        /* raygen's mark per pass, then one per kernel kind at each depth (record_passes). */
        uint32_t marks = timed * (end - first) * (1 + (VKRT_KERNEL_KINDS - 1) * (r->max_depth + 1));
        if (!profile_recorder_create(r->ctx, &profile, marks, timed, err))
            return false;
        p = &profile;
    }
    VkCommandBuffer cmd;
    bool ok = gpu_commands_begin(r->ctx, &cmd, err);
    if (ok) {
        /* Once per submission, before any timestamp: repetitions add to the counters, but the
         * host reads them only after a single frame. */
        record_zero(cmd, &r->counters, VK_WHOLE_SIZE);
        for (uint32_t i = 0; i < warmups; ++i)
            record_passes(r, cmd, params, first, end, NULL);
        if (p)
            profile_recorder_begin(cmd, p);
        for (uint32_t i = 0; i < timed; ++i) {
            record_passes(r, cmd, params, first, end, p);
            if (p)
                profile_recorder_end_frame(p);
        }
        double start = vkrt_clock_ms();
        ok = gpu_commands_submit(r->ctx, err);
        *seconds = (vkrt_clock_ms() - start) * 1e-3;
    }
    if (ok && p) {
        ok = profile_recorder_read(r->ctx, p, &stats->profile, err);
        stats->profile.warmups = warmups;
    }
    if (p)
        profile_recorder_destroy(r->ctx, p);
    return ok;
}

/* After a timeout or a lost device, the likeliest culprit is a material shader that never ends:
 * the message lists the scene's materials (the GPU cannot say which invocation hung). */
static void name_suspects(const vkrt_renderer *r, vkrt_error *err)
{
    char list[600] = "";
    size_t used = 0;
    for (uint32_t i = 0; i < r->material_count && used + 2 < sizeof list; ++i) {
        int n = snprintf(list + used, sizeof list - used, "%s%s", i ? ", " : "",
                         r->material_names[i]);
        if (n < 0 || (size_t)n >= sizeof list - used)
            break;
        used += (size_t)n;
    }
    size_t len = strlen(err->msg);
    snprintf(err->msg + len, sizeof err->msg - len, "; the scene's materials: %s", list);
}

bool vkrt_renderer_add_samples(vkrt_renderer *r, const vkrt_config_camera *camera,
                               uint32_t frame_index, uint32_t first, uint32_t count,
                               vkrt_frame_stats *stats, vkrt_error *err)
{
    uint32_t pixels = r->width * r->height;
    if (first >= r->samples || count > r->samples - first)
        return vkrt_error_set(err, "sample passes %u..%u are outside the %u of the renderer", first,
                              first + count, r->samples);
    if (!check_loop_budget(r, err))
        return false;
    FrameParams params = {0};
    r->camera = *camera;
    vkrt_camera_params(camera, r->width, r->height, &params);
    params.eye.w = r->min_importance;
    params.image = (uvec4){r->width, r->height, 0, r->samples};
    /* The frame seed: the frame's index, moved by the golden ratio's bits per seed so that seeds
     * do not share frames (every kernel hashes it before use). */
    params.counts = (uvec4){r->triangle_count, r->light_count, pixels,
                            frame_index + r->seed * 0x9E3779B9u};
    frame_set_brute_range(&params, 0, r->triangle_count, false);
    frame_set_light_words(&params, r->light_words);

    Counters counters;
    double seconds = 0;
    uint32_t attempts = 0, start = first;
    for (;;) {
        ++attempts;
        if (!run_passes(r, params, start, first + count, 0, 1, &seconds, stats, err) ||
            !gpu_buffer_download(r->ctx, &r->counters, &counters, sizeof counters, err)) {
            if (r->ctx->lost)
                name_suspects(r, err);
            return vkrt_error_prefix(err, "rendering frame %u", frame_index);
        }
        uint32_t m = counters.overcast_material - 1;
        const char *culprit = m < r->material_count ? r->material_names[m] : "?";
        if (counters.overcount)
            return vkrt_error_set(err,
                                  "material %s: count_rays asked for more than %u rays at %u hits; "
                                  "one hit may cast at most %u",
                                  culprit, VKRT_MAX_CAST, counters.overcount, VKRT_MAX_CAST);
        if (counters.overcast)
            return vkrt_error_set(err,
                                  "material %s cast more rays than its count_rays returned (%u "
                                  "rays not traced): shade may cast at most as many rays as "
                                  "count_rays returned for the same hit",
                                  culprit, counters.overcast);
        /* A wave asked for more rays than the buffers hold: those passes are incomplete. Grow
         * and render every pass of the image again from the first (earlier calls' passes are in
         * the image too, and cannot be taken out); the random streams make the new picture the
         * one large buffers would have given. */
        if (counters.max_wave <= r->capacity || r->capacity >= r->max_capacity)
            break;
        if (!renderer_grow_ray_buffers(r, counters.max_wave, err))
            return false;
        start = 0;
    }
    /* The profile of a cold GPU measures its clocks' climb: render the frame again, after
     * the device's warm-up back to back with it (tuning.h), and take the median of several.
     * The first render sizes the warm-up. */
    if (r->profile && stats && first == 0) {
        uint32_t warmups = vkrt_warmup_runs(r->tuning.warmup_ms, stats->profile.frame_ms, 1);
        double ignored;
        if (!run_passes(r, params, 0, count, warmups, r->profile_repeat, &ignored, stats, err)) {
            if (r->ctx->lost)
                name_suspects(r, err);
            return vkrt_error_prefix(err, "profiling frame %u", frame_index);
        }
    }
    if (stats) {
        stats->seconds = seconds;
        stats->primary_rays = r->target_error > 0 ? counters.primary_rays
                                                  : (uint64_t)pixels * (first + count - start);
        stats->active_pixels = counters.active_pixels;
        stats->shadow_rays = counters.shadow_rays;
        stats->secondary_rays = counters.secondary_rays;
        stats->attempts = attempts;
        stats->ray_capacity = r->capacity;
        stats->dropped_rays = counters.max_wave > r->capacity ? counters.max_wave - r->capacity : 0;
        stats->nonfinite = counters.nonfinite;
        stats->profile.profiled = r->profile;
    }
    return true;
}

bool vkrt_renderer_read_image(vkrt_renderer *r, uint32_t passes, float *rgb, vkrt_error *err)
{
    uint32_t pixels = r->width * r->height;
    vec4 *image = malloc((size_t)pixels * sizeof *image);
    if (!image)
        return vkrt_error_set(err, "out of memory reading back %u pixels", pixels);
    bool ok = gpu_buffer_download(r->ctx, &r->image, image, (size_t)pixels * sizeof *image, err);
    if (ok) {
        float scale = 1.0f / (float)(passes ? passes : 1);
        for (uint32_t i = 0; i < pixels; ++i) {
            /* Adaptive sampling: each pixel's own count, in w (adapt.comp). */
            if (r->target_error > 0)
                scale = image[i].w > 0 ? 1.0f / image[i].w : 0.0f;
            rgb[3 * (size_t)i + 0] = image[i].x * scale;
            rgb[3 * (size_t)i + 1] = image[i].y * scale;
            rgb[3 * (size_t)i + 2] = image[i].z * scale;
        }
    }
    free(image);
    return ok;
}

void vkrt_renderer_set_next_camera(vkrt_renderer *r, const vkrt_config_camera *next)
{
    r->has_next = next != NULL;
    if (next)
        r->next_camera = *next;
}

bool vkrt_renderer_render(vkrt_renderer *r, const vkrt_config_camera *camera, uint32_t frame_index,
                          float *rgb, vkrt_frame_stats *stats, vkrt_error *err)
{
    if (r->target_error > 0)
        return renderer_adaptive_render(r, camera, frame_index, stats, err) &&
               vkrt_renderer_read_image(r, r->samples, rgb, err);
    return vkrt_renderer_add_samples(r, camera, frame_index, 0, r->samples, stats, err) &&
           vkrt_renderer_read_image(r, r->samples, rgb, err);
}
