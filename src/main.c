/*
 * main.c: the vkrt program. Parses the command line, loads the scene (all CPU, so bad input stops
 * before any GPU work), renders every frame and writes it, then prints a summary on stderr.
 * Only this file decides how the process exits.
 */
#define _POSIX_C_SOURCE 200809L
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench.h"
#include "cli.h"
#include "clock.h"
#include "error.h"
#include "gpu/context.h"
#include "gpu/spirv_cache.h"
#include "output/image_check.h"
#include "output/image_write.h"
#include "render/renderer.h"
#include "scene/scene.h"
#ifdef VKRT_VIEWER
#include "view/viewer.h"
#endif

#ifndef VKRT_VERSION
#define VKRT_VERSION "unknown"
#endif

/* The folder part of path must exist before any frame is rendered: failing after minutes of GPU
 * work for a typo in a folder name would waste them. */
static bool check_output_folder(const char *path, vkrt_error *err)
{
    const char *slash = strrchr(path, '/');
    if (!slash || slash == path)
        return true;
    char folder[4096];
    if ((size_t)(slash - path) >= sizeof folder)
        return vkrt_error_set(err, "%s: path too long", path);
    memcpy(folder, path, (size_t)(slash - path));
    folder[slash - path] = '\0';
    struct stat st;
    if (stat(folder, &st) != 0 || !S_ISDIR(st.st_mode))
        return vkrt_error_set(err, "%s: folder %s does not exist", path, folder);
    return true;
}

static bool check_output(const char *output, uint32_t frames, vkrt_error *err)
{
    if (!output)
        return vkrt_error_set(err, "no output file: give -o PATH or an `output` line");
    char first[4096];
    if (!vkrt_frame_path(first, sizeof first, output, 0, err))
        return false;
    if (vkrt_image_format_of(first) == VKRT_IMAGE_UNKNOWN)
        return vkrt_error_set(err, "%s: unknown image format (use .png or .exr)", output);
    if (frames > 1 && !vkrt_frame_pattern_has_number(output))
        return vkrt_error_set(err, "%s: the scene has %u cameras (frames) but the output has no "
                                   "frame number; use a pattern such as frame%%04d.png",
                              output, frames);
    return check_output_folder(first, err);
}

typedef struct render_totals {
    double seconds;
    uint64_t rays;
    uint32_t rendered, skipped;
    bool interrupted;
    vkrt_integrator integrator;   /* what the renderer computed, and why */
    char integrator_reason[256];
} render_totals;

/* Set by SIGINT or SIGTERM; frames are checked between, so the frame being written finishes (or
 * fails) cleanly and --resume can pick up after it. */
static volatile sig_atomic_t stop_requested;

static void request_stop(int signal_number)
{
    (void)signal_number;
    stop_requested = 1;
}

static void print_accel_stats(FILE *out, const vkrt_accel_stats *s)
{
    fprintf(out, "vkrt: accel %s: %s\n", vkrt_accel_name(s->kind), s->reason);
    if (s->kind == VKRT_ACCEL_BVH)
        fprintf(out,
                "vkrt: BVH: %u nodes, %u leaves, %.2f triangles per leaf, depth %u, SAH cost %.1f, "
                "%.2f MiB, built in %.1f ms\n",
                s->nodes, s->leaves, s->triangles_per_leaf, s->max_depth, s->sah_cost,
                s->bytes / 1048576.0, s->build_ms);
    else if (s->kind == VKRT_ACCEL_GRID)
        fprintf(out,
                "vkrt: grid: %ux%ux%u = %u cells, %u occupied, %.2f triangles per occupied cell, "
                "fullest cell %u, %.2f MiB, built in %.1f ms\n",
                s->grid_dims[0], s->grid_dims[1], s->grid_dims[2], s->nodes, s->leaves,
                s->triangles_per_leaf, s->max_cell_refs, s->bytes / 1048576.0, s->build_ms);
    if (s->choose_ms > 0)
        fprintf(out, "vkrt: choosing took %.1f ms\n", s->choose_ms);
}

/* Where the kernels came from: glslang, or the cache of earlier starts (gpu/spirv_cache.h). */
static void print_kernel_cache(FILE *out)
{
    uint32_t loaded, compiled;
    gpu_spirv_cache_counts(&loaded, &compiled);
    char dir[4096];
    if (gpu_spirv_cache_dir(dir, sizeof dir))
        fprintf(out, "vkrt: kernels: %u compiled, %u from the cache in %s\n", compiled, loaded,
                dir);
    else
        fprintf(out, "vkrt: kernels: %u compiled (no kernel cache: --no-cache, VKRT_CACHE_DIR is empty, or there is no HOME)\n",
                compiled);
}

/* A flythrough's progress after a frame: frames done of the run's, frames per second and the
 * time left at that rate. On a terminal one line, rewritten in place (the caller ends it); else a
 * line per frame, for logs. */
static void print_progress(FILE *out, uint32_t done, uint32_t total, uint32_t rendered,
                           double seconds, const char *path, bool terminal)
{
    double rate = seconds > 0 ? rendered / seconds : 0;
    char left[64] = "";
    if (rate > 0 && done < total)
        snprintf(left, sizeof left, ", about %.0f s left", (total - done) / rate);
    fprintf(out, "%svkrt: %u of %u frames done (%s), %.2f frames/s%s%s", terminal ? "\r" : "",
            done, total, path, rate, left, terminal ? "\033[K" : "\n");
    fflush(out);
}

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
    if (ok && !opts->common.quiet)
        fprintf(stderr,
                "vkrt: frame %u: target error %g: %.2f%% of pixels within it; estimate rms %.4f, "
                "99th percentile %.4f, max %.4f; samples per pixel %.1f mean (%u to %u of %u); "
                "%.3f s\n",
                f, (double)c.target, 100.0 * c.converged / c.pixels, c.rms_error,
                (double)c.p99_error, (double)c.max_error, c.mean_samples, c.min_samples,
                c.max_samples, desc->samples, stats->seconds);
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

static bool render_frames(const vkrt_render_options *opts, const vkrt_scene *scene,
                          const char *output, gpu_context *ctx, render_totals *totals,
                          vkrt_accel_stats *accel, vkrt_error *err)
{
    const vkrt_config *cfg = &scene->config;
    vkrt_render_desc desc = vkrt_render_desc_for(cfg, &opts->common, opts->samples);
    desc.profile = opts->profile;
    desc.profile_repeat = opts->profile_repeat;
    desc.seed = opts->seed;
    desc.shutter = cfg->shutter; /* render only: the viewer's camera has no next frame */
    vkrt_renderer *renderer;
    if (!vkrt_renderer_create(&renderer, ctx, scene, &desc, err))
        return false;
    *accel = *vkrt_renderer_accel_stats(renderer);
    const char *why;
    vkrt_integrator integrator = vkrt_renderer_integrator(renderer, &why);
    totals->integrator = integrator;
    snprintf(totals->integrator_reason, sizeof totals->integrator_reason, "%s", why);
    if (opts->common.verbose) {
        print_accel_stats(stderr, accel);
        fprintf(stderr, "vkrt: integrator %s: %s\n", vkrt_integrator_name(integrator), why);
        print_kernel_cache(stderr);
    }
    if (integrator == VKRT_INTEGRATOR_PATH && !opts->common.quiet)
        for (uint32_t i = 0; i < cfg->light_count; ++i)
            if (cfg->lights[i].kind == VKRT_LIGHT_AMBIENT) {
                fprintf(stderr, "vkrt: note: the path integrator computes indirect light and "
                                "ignores `light ambient`, Whitted's stand-in for it\n");
                break;
            }
    float *rgb = malloc((size_t)desc.width * desc.height * 3 * sizeof *rgb);
    bool ok = rgb != NULL;
    if (!ok)
        vkrt_error_set(err, "out of memory for a %ux%u image", desc.width, desc.height);
    uint32_t first = opts->frames_given ? opts->frame_first : 0;
    uint32_t last = opts->frames_given ? opts->frame_last : cfg->camera_count - 1;
    uint32_t step = opts->frames_given ? opts->frame_step : 1;
    uint32_t total = (last - first) / step + 1, done = 0;
    bool progress = !opts->common.quiet && total > 1;
    bool terminal = progress && isatty(fileno(stderr));
    double start_ms = vkrt_clock_ms();
    for (uint32_t f = first; ok && f <= last; f = f + step < f ? last + 1 : f + step) {
        if (stop_requested) {
            totals->interrupted = true;
            break;
        }
        vkrt_frame_stats stats;
        char path[4096];
        ok = vkrt_frame_path(path, sizeof path, output, f, err);
        if (ok && opts->resume && vkrt_image_is_complete(path, desc.width, desc.height)) {
            ++totals->skipped;
            ++done;
            continue;
        }
        if (ok)
            vkrt_image_remove_stale_temporaries(path);
        /* Motion blur towards the next frame's camera; the last frame has none and is sharp. */
        vkrt_renderer_set_next_camera(renderer, f + 1 < cfg->camera_count ? &cfg->cameras[f + 1]
                                                                          : NULL);
        ok = ok && vkrt_renderer_render(renderer, &cfg->cameras[f], f, rgb, &stats, err) &&
             vkrt_image_write(path, desc.width, desc.height, rgb, opts->exposure, err) &&
             (!desc.target_error || report_convergence(opts, renderer, &desc, f, &stats, err));
        if (ok) {
            totals->seconds += stats.seconds;
            totals->rays += stats.primary_rays + stats.shadow_rays + stats.secondary_rays;
            ++totals->rendered;
            if (terminal) /* the progress line makes way for this frame's messages */
                fputs("\r\033[K", stderr);
            if (stats.dropped_rays && !opts->common.quiet)
                fprintf(stderr, "vkrt: warning: frame %u: %llu rays did not fit the largest ray "
                                "buffers the device allows (%u rays) and were not traced\n",
                        f, (unsigned long long)stats.dropped_rays, stats.ray_capacity);
            if (stats.nonfinite && !opts->common.quiet)
                fprintf(stderr, "vkrt: warning: frame %u: %u shading results were NaN or "
                                "infinite and were dropped\n",
                        f, stats.nonfinite);
            if (stats.profile.profiled && !opts->common.quiet)
                vkrt_frame_profile_print(stderr, &stats.profile);
            if (opts->common.verbose && stats.attempts > 1)
                fprintf(stderr, "vkrt: frame %u: ray buffers grew to %u rays (%u attempts)\n", f,
                        stats.ray_capacity, stats.attempts);
            if (progress)
                print_progress(stderr, ++done, total, totals->rendered,
                               (vkrt_clock_ms() - start_ms) / 1e3, path, terminal);
        }
    }
    if (terminal && done > 0)
        fputc('\n', stderr);
    free(rgb);
    vkrt_renderer_destroy(renderer);
    return ok;
}

static int run_render(const vkrt_render_options *opts)
{
    vkrt_error err = {{0}};
    vkrt_scene scene;
    if (!vkrt_scene_load(opts->scene_path, &scene, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 1;
    }
    if (!opts->common.quiet)
        vkrt_mesh_print_warnings(&scene.mesh, "vkrt: ", opts->common.verbose, stderr);
    const char *output = opts->output ? opts->output : scene.config.output;
    uint32_t cameras = scene.config.camera_count;
    if (opts->frames_given && opts->frame_last >= cameras) {
        fprintf(stderr, "vkrt: --frames %u:%u: %s has %u camera%s (frames 0 to %u)\n",
                opts->frame_first, opts->frame_last, opts->scene_path, cameras,
                cameras == 1 ? "" : "s", cameras - 1);
        vkrt_scene_free(&scene);
        return 1;
    }
    /* The frames this run renders: all, or --frames's. */
    uint32_t frames = opts->frames_given
                          ? (opts->frame_last - opts->frame_first) / opts->frame_step + 1
                          : cameras;
    if (!check_output(output, scene.config.camera_count, &err) ||
        (opts->sample_count_image &&
         !check_output(opts->sample_count_image, scene.config.camera_count, &err))) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        vkrt_scene_free(&scene);
        return 1;
    }

    signal(SIGINT, request_stop);
    signal(SIGTERM, request_stop);
    gpu_context ctx;
    gpu_context_desc ctx_desc = {.device_index = opts->common.device,
                                 .validation = opts->common.validation};
    render_totals totals = {0};
    vkrt_accel_stats accel = {0};
    bool ok = gpu_context_create(&ctx, &ctx_desc, &err) &&
              render_frames(opts, &scene, output, &ctx, &totals, &accel, &err);
    char device[256];
    snprintf(device, sizeof device, "%s", ctx.properties.deviceName);
    if (!gpu_context_close(&ctx, ok, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        vkrt_scene_free(&scene);
        return 1;
    }
    if (totals.interrupted) {
        fprintf(stderr, "vkrt: interrupted after %u of %u frames; run again with --resume to "
                        "finish\n",
                totals.rendered + totals.skipped, frames);
        vkrt_scene_free(&scene);
        return 130;
    }
    if (!opts->common.quiet && totals.skipped)
        fprintf(stderr, "vkrt: resumed: %u of %u frames were already complete\n", totals.skipped,
                frames);
    if (!opts->common.quiet) {
        uint32_t rendered = totals.rendered;
        fprintf(stderr,
                "vkrt: %s | %u triangles | accel %s | %u frame%s | %.1f ms/frame | %.3g Mrays/s\n",
                device, scene.mesh.triangle_count, vkrt_accel_name(accel.kind), rendered,
                rendered == 1 ? "" : "s", rendered ? 1e3 * totals.seconds / rendered : 0.0,
                totals.seconds > 0 ? totals.rays / totals.seconds * 1e-6 : 0.0);
        if (!opts->common.verbose) {
            fprintf(stderr, "vkrt: accel %s: %s\n", vkrt_accel_name(accel.kind), accel.reason);
            fprintf(stderr, "vkrt: integrator %s: %s\n", vkrt_integrator_name(totals.integrator),
                    totals.integrator_reason);
        }
    }
    vkrt_scene_free(&scene);
    return 0;
}

int main(int argc, char **argv)
{
    vkrt_command_line cl;
    vkrt_error err = {{0}};
    if (!vkrt_command_line_parse(argc, argv, &cl, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 2;
    }
    const vkrt_common_options *common = cl.command == VKRT_COMMAND_RENDER ? &cl.render.common
                                        : cl.command == VKRT_COMMAND_VIEW ? &cl.view.common
                                        : cl.command == VKRT_COMMAND_BENCH ? &cl.bench.common
                                                                           : NULL;
    if (common && common->no_cache)
        gpu_spirv_cache_disable();
    switch (cl.command) {
    case VKRT_COMMAND_HELP:
        fputs(vkrt_usage(), stdout);
        return 0;
    case VKRT_COMMAND_VERSION:
        printf("vkrt %s\n", VKRT_VERSION);
        return 0;
    case VKRT_COMMAND_LIST_DEVICES:
        if (!gpu_list_devices(stdout, &err)) {
            fprintf(stderr, "vkrt: %s\n", err.msg);
            return 1;
        }
        return 0;
    case VKRT_COMMAND_RENDER:
        return run_render(&cl.render);
    case VKRT_COMMAND_BENCH:
        return vkrt_bench_run(&cl.bench);
    case VKRT_COMMAND_VIEW:
#ifdef VKRT_VIEWER
        return vkrt_view_run(&cl.view);
#else
        fprintf(stderr, "vkrt: this vkrt was built without the viewer: GLFW was not found "
                        "(Debian: apt-get install libglfw3-dev, then rebuild)\n");
        return 1;
#endif
    default:
        return 2;
    }
}
