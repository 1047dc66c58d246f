/*
 * frame_writer.c: one device rendering a scene's frames into their files (frame_writer.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "frame_writer.h"

#include <stdlib.h>

#include "../clock.h"
#include "../output/image_check.h"
#include "../output/image_write.h"
#include "../output/temporary.h"
#include "../render/trace_api.h"
#include "render_desc.h"
#include "report.h"

/* Sampling to a target error: what frame f reached (its estimates' spread, the samples it took,
 * its time), and with --sample-count-image each pixel's samples: EXR the counts, PNG grey
 * count / cap. */
static bool report_convergence(const vkrt_render_options *opts, vkrt_renderer *renderer,
                               const vkrt_render_desc *desc, uint32_t f,
                               const vkrt_frame_stats *stats, vkrt_error *err)
{
    size_t pixels = (size_t)desc->width * desc->height;
    uint32_t *samples = opts->sample_count_image ? malloc(pixels * sizeof *samples) : NULL;
    float *grey = opts->sample_count_image ? malloc(pixels * 3 * sizeof *grey) : NULL;
    if (opts->sample_count_image && (!samples || !grey)) {
        free(samples);
        free(grey);
        return vkrt_error_set(err, "out of memory for a %zu-pixel sample count image", pixels);
    }
    vkrt_convergence c;
    bool ok = vkrt_renderer_convergence(renderer, &c, NULL, samples, err);
    /* A pixel needs 2 samples for an estimate; those with fewer are said apart, not averaged. */
    char estimates[200];
    if (c.unestimated == c.pixels)
        snprintf(estimates, sizeof estimates,
                 "no error estimate (a pixel needs 2 samples for one; give --spp 2 or more)");
    else
        snprintf(estimates, sizeof estimates,
                 "estimate rms %.4f, 99th percentile %.4f, max %.4f%s", c.rms_error,
                 (double)c.p99_error, (double)c.max_error,
                 c.unestimated ? " (of the pixels with 2 samples or more)" : "");
    if (ok && !opts->common.quiet)
        fprintf(stderr,
                "vkrt: frame %u: target error %g: %.2f%% of pixels within it; %s; samples per "
                "pixel %.1f mean (%u to %u of %u); %.3f s\n",
                f, (double)c.target, 100.0 * c.converged / c.pixels, estimates, c.mean_samples,
                c.min_samples, c.max_samples, desc->samples, stats->seconds);
    char path[4096];
    if (ok && opts->sample_count_image) {
        bool exr = vkrt_image_format_of(opts->sample_count_image) == VKRT_IMAGE_EXR;
        for (size_t i = 0; i < 3 * pixels; ++i)
            grey[i] = exr ? (float)samples[i / 3] : (float)samples[i / 3] / (float)desc->samples;
        ok = vkrt_frame_path(path, sizeof path, opts->sample_count_image, f, err) &&
             vkrt_image_write(path, desc->width, desc->height, grey, 0, err);
    }
    free(samples);
    free(grey);
    return ok;
}

static void *early_context_thread(void *arg)
{
    early_context *e = arg;
    e->ok = gpu_context_create(&e->ctx, &e->desc, &e->err);
    return NULL;
}

void early_context_start(early_context *e, const vkrt_render_options *opts)
{
    *e = (early_context){.desc = {.device_index = opts->common.device,
                                  .validation = opts->common.validation,
                                  .pipeline_statistics = opts->profile}};
    /* A thread that cannot start costs the overlap only: the context is made at the join. */
    e->started = pthread_create(&e->thread, NULL, early_context_thread, e) == 0;
}

/* Waits for the context (making it here if no thread could); false with err where it failed. */
static bool early_context_join(early_context *e, gpu_context *out, vkrt_error *err)
{
    if (e->started)
        pthread_join(e->thread, NULL);
    else
        early_context_thread(e);
    e->started = false;
    e->joined = true;
    if (!e->ok) {
        *err = e->err;
        return false;
    }
    *out = e->ctx;
    return true;
}

void early_context_discard(early_context *e)
{
    if (e->joined)
        return;
    if (e->started)
        pthread_join(e->thread, NULL);
    if (e->started && e->ok)
        gpu_context_destroy(&e->ctx);
    e->joined = true;
}

bool frame_writer_start(frame_writer *w, int device, bool tell, vkrt_error *err)
{
    const vkrt_render_options *opts = &w->cl->render;
    const vkrt_config *cfg = &w->scene->config;
    w->desc = vkrt_render_desc_for(cfg, w->cl);
    gpu_context_desc ctx_desc = {.device_index = device,
                                 .validation = opts->common.validation,
                                 .pipeline_statistics = opts->profile};
    if (w->early ? !early_context_join(w->early, &w->ctx, err)
                 : !gpu_context_create(&w->ctx, &ctx_desc, err))
        return false;
    if (w->clock)
        w->clock->vulkan = vkrt_clock_ms();
    if (!vkrt_renderer_create(&w->renderer, &w->ctx, w->scene, &w->desc, err)) {
        gpu_context_destroy(&w->ctx);
        return false;
    }
    if (w->clock)
        w->clock->renderer = vkrt_clock_ms();
    const char *why;
    vkrt_integrator integrator = vkrt_renderer_integrator(w->renderer, &why);
    if (tell && opts->common.verbose) {
        report_accel_stats(stderr, vkrt_renderer_accel_stats(w->renderer));
        fprintf(stderr, "vkrt: integrator %s: %s\n", vkrt_integrator_name(integrator), why);
        report_kernel_cache(stderr);
        report_scene_cache(stderr, &w->scene->model_cache);
        report_memory(stderr, w->renderer, &w->ctx, w->scene);
    }
    /* A profile's times, then what the driver says of each kernel, where it says anything. */
    if (opts->profile && w->ctx.pipeline_statistics && !opts->common.quiet &&
        !vkrt_renderer_print_kernel_statistics(w->renderer, stderr, err)) {
        vkrt_renderer_destroy(w->renderer);
        gpu_context_destroy(&w->ctx);
        return false;
    }
    if (tell && integrator == VKRT_INTEGRATOR_PATH && !opts->common.quiet)
        for (uint32_t i = 0; i < w->scene->light_count; ++i)
            if (w->scene->lights[i].kind == VKRT_LIGHT_AMBIENT) {
                fprintf(stderr, "vkrt: note: the path integrator computes indirect light and "
                                "ignores `light ambient`, Whitted's stand-in for it\n");
                break;
            }
    /* Made here, after any fork of --devices: a worker's denoiser is its own. */
    if (vkrt_denoise_asked(w->cl, &w->scene->config) &&
        !vkrt_denoiser_create(&w->denoiser, &(vkrt_denoiser_desc){0}, err)) {
        vkrt_renderer_destroy(w->renderer);
        gpu_context_destroy(&w->ctx);
        return false;
    }
    if (w->denoiser && tell && opts->common.verbose)
        fprintf(stderr, "vkrt: denoise: %s\n", vkrt_denoiser_describe(w->denoiser));
    vkrt_write_pool_desc pool_desc = {.width = w->desc.width,
                                      .height = w->desc.height,
                                      .finish = {.exposure = opts->exposure,
                                                 .tonemap = w->scene->config.tonemap,
                                                 .denoiser = w->denoiser},
                                      .aovs = w->desc.aovs,
                                      .aovs_written = w->cl->render.aovs,
                                      .written = w->written,
                                      .failed = w->failed,
                                      .user = w->user};
    bool ok = vkrt_write_pool_threads(w->sharers, &pool_desc.threads, err);
    /* A single frame's file overlaps nothing: written on this thread, no buffers to spare. */
    if (w->frames <= 1)
        pool_desc.threads = 0;
    else if (pool_desc.threads > w->frames - 1)
        pool_desc.threads = w->frames - 1;
    if (!ok || !vkrt_write_pool_create(&w->pool, &pool_desc, err)) {
        vkrt_denoiser_destroy(w->denoiser);
        w->denoiser = NULL;
        vkrt_renderer_destroy(w->renderer);
        gpu_context_destroy(&w->ctx);
        return false;
    }
    return true;
}

bool frame_writer_write(frame_writer *w, uint32_t f, vkrt_frame_stats *stats, vkrt_error *err)
{
    const vkrt_render_options *opts = &w->cl->render;
    char path[4096];
    if (!vkrt_frame_path(path, sizeof path, w->output, f, err))
        return false;
    /* A --devices worker killed on this frame left its temporary; it is reaped by now. */
    vkrt_temporaries_remove_dead_beside(path);
    /* Motion blur towards the next frame's camera; the last frame has none and is sharp. */
    vkrt_renderer_set_next_camera(w->renderer,
                                  f + 1 < w->scene->camera_count ? &w->scene->cameras[f + 1] : NULL);
    float *rgb = vkrt_write_pool_buffer(w->pool, err);
    if (!rgb || !vkrt_renderer_render(w->renderer, &w->scene->cameras[f], f, rgb, stats, err))
        return false;
    /* --aov: the frame's AOVs into the buffers that travel with its beauty to the writer. */
    float *aovs[4];
    vkrt_write_pool_aovs(w->pool, aovs);
    if (w->desc.aovs &&
        !vkrt_renderer_read_aovs(w->renderer, 0, aovs[0], aovs[1], aovs[2], aovs[3], err))
        return false;
    if (w->clock && !w->clock->frame)
        w->clock->frame = vkrt_clock_ms();
    vkrt_written_frame written = {.frame = f,
                                  .path = path,
                                  .gpu_seconds = stats->seconds,
                                  .rays = stats->primary_rays + stats->shadow_rays +
                                          stats->secondary_rays};
    /* The progress line, printed by the writer threads, makes way for this frame's messages;
     * holding stderr keeps a progress line from coming between. */
    bool quiet = opts->common.quiet;
    bool tell = w->desc.target_error ||
                (!quiet && (stats->dropped_rays || stats->nonfinite || stats->profile.profiled)) ||
                (opts->common.verbose && stats->attempts > 1);
    if (tell)
        flockfile(stderr);
    if (tell && w->clear_line)
        fputs("\r\033[K", stderr);
    /* The convergence report reads the renderer's state of this frame: before the next one. */
    bool ok =
        !w->desc.target_error || report_convergence(opts, w->renderer, &w->desc, f, stats, err);
    if (ok && stats->dropped_rays && !quiet)
        fprintf(stderr,
                "vkrt: warning: frame %u: %llu rays did not fit the largest ray "
                "buffers the device allows (%u rays) and were not traced\n",
                f, (unsigned long long)stats->dropped_rays, stats->ray_capacity);
    if (ok && stats->nonfinite && !quiet)
        fprintf(stderr,
                "vkrt: warning: frame %u: %u shading results were NaN or "
                "infinite and were dropped\n",
                f, stats->nonfinite);
    if (ok && stats->profile.profiled && !quiet)
        vkrt_frame_profile_print(stderr, &stats->profile);
    if (ok && opts->common.verbose && stats->attempts > 1)
        fprintf(stderr, "vkrt: frame %u: ray buffers grew to %u rays (%u attempts)\n", f,
                stats->ray_capacity, stats->attempts);
    if (tell)
        funlockfile(stderr);
    return ok && vkrt_write_pool_submit(w->pool, &written, err);
}

bool frame_writer_finish(frame_writer *w, bool ok, vkrt_error *err)
{
    vkrt_error write_err = {{0}};
    if (!vkrt_write_pool_finish(w->pool, &write_err) && ok) {
        *err = write_err;
        ok = false;
    }
    vkrt_write_pool_destroy(w->pool);
    vkrt_denoiser_destroy(w->denoiser);
    w->denoiser = NULL;
    vkrt_renderer_destroy(w->renderer);
    return gpu_context_close(&w->ctx, ok, err);
}

bool frame_list_make(const vkrt_command_line *cl, const vkrt_scene *scene, const char *output,
                     frame_list *list, vkrt_error *err)
{
    const vkrt_render_options *opts = &cl->render;
    const vkrt_config *cfg = &scene->config;
    vkrt_render_desc desc = vkrt_render_desc_for(cfg, cl);
    uint32_t first = opts->frames_given ? opts->frame_first : 0;
    uint32_t last = opts->frames_given ? opts->frame_last : scene->camera_count - 1;
    uint32_t step = opts->frames_given ? opts->frame_step : 1;
    /* What interrupted runs left beside any frame of the pattern, those of live runs kept. */
    vkrt_temporaries_remove_dead(output);
    *list = (frame_list){.total = (last - first) / step + 1};
    list->frames = malloc(list->total * sizeof *list->frames);
    if (!list->frames)
        return vkrt_error_set(err, "out of memory");
    for (uint32_t i = 0; i < list->total; ++i) {
        uint32_t f = first + i * step;
        char path[4096];
        if (!vkrt_frame_path(path, sizeof path, output, f, err)) {
            free(list->frames);
            return false;
        }
        if (opts->resume && vkrt_image_is_complete(path, desc.width, desc.height))
            ++list->skipped;
        else
            list->frames[list->count++] = f;
    }
    return true;
}
