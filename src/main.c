/*
 * main.c: the vkrt program. Parses the command line, loads the scene (all CPU, so bad input stops
 * before any GPU work), renders every frame and writes it (on one device, or with --devices on
 * several, a worker process each: device_pool.h), then prints a summary on stderr.
 * Only this file decides how the process exits.
 */
#define _POSIX_C_SOURCE 200809L
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include "bench.h"
#include "cli.h"
#include "clock.h"
#include "device_pool.h"
#include "error.h"
#include "gpu/context.h"
#include "gpu/pipeline.h"
#include "gpu/spirv_cache.h"
#include "output/image_check.h"
#include "output/image_write.h"
#include "output/write_pool.h"
#include "render/renderer.h"
#include "render/trace_api.h"
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
    /* A structure from the cache (render/accel_cache.h) was read, not built, in build_ms. */
    const char *built = s->from_cache ? "read from the structure cache in" : "built in";
    fprintf(out, "vkrt: accel %s: %s\n", vkrt_accel_name(s->kind), s->reason);
    if (s->kind == VKRT_ACCEL_BVH)
        fprintf(out,
                "vkrt: BVH: %u nodes, %u leaves, %u references, %.2f per leaf, depth %u, SAH cost "
                "%.1f, %.2f MiB, %s %.1f ms\n",
                s->nodes, s->leaves, s->references, s->triangles_per_leaf, s->max_depth,
                s->sah_cost, s->bytes / 1048576.0, built, s->build_ms);
    else if (s->kind == VKRT_ACCEL_KDTREE)
        fprintf(out,
                "vkrt: kd-tree: %u nodes, %u leaves (%u empty), %.2f triangles per non-empty "
                "leaf, %u references, depth %u, SAH cost %.1f, %.2f MiB, %s %.1f ms\n",
                s->nodes, s->leaves, s->empty_leaves, s->triangles_per_leaf, s->references,
                s->max_depth, s->sah_cost, s->bytes / 1048576.0, built, s->build_ms);
    else if (s->kind == VKRT_ACCEL_GRID)
        fprintf(out,
                "vkrt: grid: %ux%ux%u = %u cells, %u occupied, %.2f triangles per occupied cell, "
                "fullest cell %u, %.2f MiB, %s %.1f ms\n",
                s->grid_dims[0], s->grid_dims[1], s->grid_dims[2], s->nodes, s->leaves,
                s->triangles_per_leaf, s->max_cell_refs, s->bytes / 1048576.0, built, s->build_ms);
    if (s->choose_ms > 0)
        fprintf(out, "vkrt: choosing took %.1f ms\n", s->choose_ms);
}

/* Where the kernels came from: glslang, or the cache of earlier starts (gpu/spirv_cache.h). */
static void print_kernel_cache(FILE *out)
{
    uint32_t loaded, compiled;
    gpu_spirv_cache_counts(&loaded, &compiled);
    char dir[4096];
    uint32_t pipelines_loaded, pipelines_stored;
    gpu_pipeline_cache_counts(&pipelines_loaded, &pipelines_stored);
    if (gpu_spirv_cache_dir(dir, sizeof dir))
        fprintf(out,
                "vkrt: kernels: %u compiled, %u from the cache in %s; pipelines: %u from the "
                "driver's data there, %u stored\n",
                compiled, loaded, dir, pipelines_loaded, pipelines_stored);
    else
        fprintf(out, "vkrt: kernels: %u compiled (no kernel cache: --no-cache, VKRT_CACHE_DIR is empty, or there is no HOME)\n",
                compiled);
}

/* Where the model came from: the scene file parsed, or the scene cache (scene/scene_cache.h). */
static void print_scene_cache(FILE *out, const vkrt_scene_cache_report *c)
{
    if (c->outcome == VKRT_SCENE_CACHE_OFF)
        return;
    fprintf(out, "vkrt: scene cache: ");
    if (c->rejected[0])
        fprintf(out, "the entry found was not used (%s); ", c->rejected);
    if (c->outcome == VKRT_SCENE_CACHE_HIT)
        fprintf(out, "model read in %.0f ms", c->read_ms);
    else if (c->outcome == VKRT_SCENE_CACHE_STORED)
        fprintf(out, "scene file parsed, model stored in %.0f ms", c->store_ms);
    else if (c->outcome == VKRT_SCENE_CACHE_STORING)
        fprintf(out, "scene file parsed, model being stored on a thread");
    else
        fprintf(out, "scene file parsed, not stored: %s", c->why);
    fprintf(out, "; the scene file's key hashed in %.0f ms\n", c->hash_ms);
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

/* Device memory by what it is for, against what the device has, and host memory: the mesh's
 * arrays and the process's peak (--verbose, issue 20). */
static void print_memory(FILE *out, const vkrt_renderer *renderer, const gpu_context *ctx,
                         const vkrt_scene *scene)
{
    vkrt_renderer_memory m = vkrt_renderer_memory_use(renderer);
    const double MiB = 1048576.0;
    fprintf(out,
            "vkrt: device memory: triangles %.1f MiB, nodes %.1f MiB, textures %.1f MiB, rays "
            "%.1f MiB, image %.1f MiB, other %.1f MiB: %.1f MiB of the device's %.1f MiB\n",
            m.triangles / MiB, m.nodes / MiB, m.textures / MiB, m.rays / MiB, m.image / MiB,
            m.other / MiB, m.total / MiB, ctx->memory_limit / MiB);
    char split[256];
    vkrt_renderer_split_text(renderer, split, sizeof split);
    fprintf(out, "vkrt: arrays split past %llu bytes (%s): %s\n",
            (unsigned long long)ctx->split_bytes, gpu_buffer_limit_name(ctx, ctx->split_bytes),
            *split ? split : "none");
    struct rusage usage;
    double peak = getrusage(RUSAGE_SELF, &usage) == 0 ? usage.ru_maxrss / 1024.0 : 0.0;
    fprintf(out,
            "vkrt: host memory: mesh %.1f MiB (positions, normals, texture coordinates, "
            "materials), peak resident %.1f MiB\n",
            vkrt_model_host_bytes(&scene->model) / MiB, peak);
}

/* Wall-clock ms of the stages of a render's start (issue 20), printed with --verbose: the
 * clock read when main began, when the scene was loaded, the Vulkan device opened, the renderer
 * made (BVH, upload, kernels), the first frame traced and its image written. */
typedef struct startup_clock {
    double main, scene, vulkan, renderer, frame, image;
} startup_clock;

static void print_startup(FILE *out, const startup_clock *t, const vkrt_scene *scene,
                          const vkrt_accel_stats *accel, const vkrt_renderer_startup *steps)
{
    fprintf(out,
            "vkrt: start-up: scene %.0f ms (scene file %.0f ms), Vulkan %.0f ms, renderer %.0f ms "
            "(structure %.0f ms, of which %s %.0f; triangles' upload %.0f, materials %.0f, "
            "lights %.0f, buffers %.0f, %s %.0f), first frame %.0f ms, its image written %.0f "
            "ms; %.0f ms since main\n",
            t->scene - t->main, scene->model_ms, t->vulkan - t->scene, t->renderer - t->vulkan,
            steps->structure_ms, accel->from_cache ? "reading it from the cache" : "building",
            accel->build_ms + accel->choose_ms, steps->geometry_ms,
            steps->materials_ms, steps->lights_ms, steps->buffers_ms,
            steps->kernels_recompiled ? "kernels compiled after them"
                                      : "waiting for the kernels compiled alongside",
            steps->kernels_ms,
            t->frame - t->renderer, t->image - t->frame, t->image - t->main);
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

/* The single device's Vulkan context, made on a thread of its own while the scene loads: creating
 * the instance and the device took 150 ms of the bunny's 0.44 s from start to PNG on the H200
 * (research/results/coldstart-h200/first-try-log.txt), the OBJ 107 ms beside it. */
typedef struct early_context {
    gpu_context_desc desc;
    gpu_context ctx;
    vkrt_error err;
    bool ok;
    bool started;  /* the thread runs, to be joined */
    bool joined;
    pthread_t thread;
} early_context;

static void *early_context_thread(void *arg)
{
    early_context *e = arg;
    e->ok = gpu_context_create(&e->ctx, &e->desc, &e->err);
    return NULL;
}

static void early_context_start(early_context *e, const vkrt_render_options *opts)
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

/* For the ways out before the context is taken: joins the thread and frees what it made. */
static void early_context_discard(early_context *e)
{
    if (e->joined)
        return;
    if (e->started)
        pthread_join(e->thread, NULL);
    if (e->started && e->ok)
        gpu_context_destroy(&e->ctx);
    e->joined = true;
}

/* One device rendering a scene's frames into their files: the single-device loop and each
 * worker of --devices (device_pool.h) use it. Files are written by a pool of threads while the
 * next frame renders (output/write_pool.h); the callbacks hear of each file written. */
typedef struct frame_writer {
    const vkrt_render_options *opts;
    const vkrt_scene *scene;
    const char *output;
    bool clear_line;      /* a progress line is on the terminal: messages clear it first */
    startup_clock *clock; /* the single-device run's start-up stages, or NULL */
    uint32_t sharers;     /* processes rendering on this machine: they share its cores */
    uint32_t frames;      /* at most this many frames to render: a writer thread a frame */
    void (*written)(void *user, const vkrt_written_frame *frame);
    void (*failed)(void *user, const vkrt_error *err);
    void *user;
    early_context *early; /* the single device's context, being made since start, or NULL */
    gpu_context ctx;
    vkrt_renderer *renderer;
    vkrt_render_desc desc;
    vkrt_write_pool *pool;
} frame_writer;

/* Creates the device's context and the renderer; tell says whether to print the choices
 * (--verbose) and notes about the scene. On failure err says why and nothing is left. */
static bool frame_writer_start(frame_writer *w, int device, bool tell, vkrt_error *err)
{
    const vkrt_render_options *opts = w->opts;
    const vkrt_config *cfg = &w->scene->config;
    w->desc = vkrt_render_desc_for(cfg, &opts->common, opts->samples);
    w->desc.profile = opts->profile;
    w->desc.profile_repeat = opts->profile_repeat;
    w->desc.seed = opts->seed;
    w->desc.shutter = cfg->shutter; /* render only: the viewer's camera has no next frame */
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
        print_accel_stats(stderr, vkrt_renderer_accel_stats(w->renderer));
        fprintf(stderr, "vkrt: integrator %s: %s\n", vkrt_integrator_name(integrator), why);
        print_kernel_cache(stderr);
        print_scene_cache(stderr, &w->scene->model_cache);
        print_memory(stderr, w->renderer, &w->ctx, w->scene);
    }
    /* A profile's times, then what the driver says of each kernel, where it says anything. */
    if (opts->profile && w->ctx.pipeline_statistics && !opts->common.quiet &&
        !vkrt_renderer_print_kernel_statistics(w->renderer, stderr, err)) {
        vkrt_renderer_destroy(w->renderer);
        gpu_context_destroy(&w->ctx);
        return false;
    }
    if (tell && integrator == VKRT_INTEGRATOR_PATH && !opts->common.quiet)
        for (uint32_t i = 0; i < cfg->light_count; ++i)
            if (cfg->lights[i].kind == VKRT_LIGHT_AMBIENT) {
                fprintf(stderr, "vkrt: note: the path integrator computes indirect light and "
                                "ignores `light ambient`, Whitted's stand-in for it\n");
                break;
            }
    vkrt_write_pool_desc pool_desc = {.width = w->desc.width,
                                      .height = w->desc.height,
                                      .exposure = opts->exposure,
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
        vkrt_renderer_destroy(w->renderer);
        gpu_context_destroy(&w->ctx);
        return false;
    }
    return true;
}

/* Renders frame f and hands it to the write pool, which writes its file (a temporary renamed
 * onto it: image_write.h); prints the frame's warnings. */
static bool frame_writer_write(frame_writer *w, uint32_t f, vkrt_frame_stats *stats,
                               vkrt_error *err)
{
    const vkrt_render_options *opts = w->opts;
    const vkrt_config *cfg = &w->scene->config;
    char path[4096];
    if (!vkrt_frame_path(path, sizeof path, w->output, f, err))
        return false;
    vkrt_image_remove_stale_temporaries(path);
    /* Motion blur towards the next frame's camera; the last frame has none and is sharp. */
    vkrt_renderer_set_next_camera(w->renderer,
                                  f + 1 < cfg->camera_count ? &cfg->cameras[f + 1] : NULL);
    float *rgb = vkrt_write_pool_buffer(w->pool, err);
    if (!rgb || !vkrt_renderer_render(w->renderer, &cfg->cameras[f], f, rgb, stats, err))
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
    bool ok = !w->desc.target_error ||
              report_convergence(opts, w->renderer, &w->desc, f, stats, err);
    if (ok && stats->dropped_rays && !quiet)
        fprintf(stderr, "vkrt: warning: frame %u: %llu rays did not fit the largest ray "
                        "buffers the device allows (%u rays) and were not traced\n",
                f, (unsigned long long)stats->dropped_rays, stats->ray_capacity);
    if (ok && stats->nonfinite && !quiet)
        fprintf(stderr, "vkrt: warning: frame %u: %u shading results were NaN or "
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

/* Waits for the files still being written, then frees what start took; after a run that went
 * well (ok), the validation layers' word too. A write that fails here makes the run fail. */
static bool frame_writer_finish(frame_writer *w, bool ok, vkrt_error *err)
{
    vkrt_error write_err = {{0}};
    if (!vkrt_write_pool_finish(w->pool, &write_err) && ok) {
        *err = write_err;
        ok = false;
    }
    vkrt_write_pool_destroy(w->pool);
    vkrt_renderer_destroy(w->renderer);
    return gpu_context_close(&w->ctx, ok, err);
}

/* The frames a run renders: --frames's (all by default), less, with --resume, those whose files
 * are complete. */
typedef struct frame_list {
    uint32_t *frames;
    uint32_t count;           /* to render */
    uint32_t total;           /* in the range, complete ones included */
    uint32_t skipped;         /* complete already (--resume) */
} frame_list;

static bool frame_list_make(const vkrt_render_options *opts, const vkrt_scene *scene,
                            const char *output, frame_list *list, vkrt_error *err)
{
    const vkrt_config *cfg = &scene->config;
    vkrt_render_desc desc = vkrt_render_desc_for(cfg, &opts->common, opts->samples);
    uint32_t first = opts->frames_given ? opts->frame_first : 0;
    uint32_t last = opts->frames_given ? opts->frame_last : cfg->camera_count - 1;
    uint32_t step = opts->frames_given ? opts->frame_step : 1;
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

typedef struct render_totals {
    double seconds;
    uint64_t rays;
    uint32_t rendered;
    bool interrupted;
    char device[256];
    vkrt_accel_stats accel;
    vkrt_renderer_startup startup; /* the renderer's steps (--verbose's start-up line) */
    vkrt_integrator integrator;   /* what the renderer computed, and why */
    char integrator_reason[256];
} render_totals;

/* The single-device run's frames as their files are written (on the write pool's threads, one
 * call at a time): counted, the first one's time kept, the progress line printed. */
typedef struct one_device_run {
    render_totals *totals;
    const frame_list *list;
    startup_clock *clock;
    bool progress, terminal;
    double start_ms;
} one_device_run;

static void one_device_written(void *user, const vkrt_written_frame *frame)
{
    one_device_run *run = user;
    uint32_t written = ++run->totals->rendered;
    if (!run->clock->image)
        run->clock->image = vkrt_clock_ms();
    if (run->progress)
        print_progress(stderr, run->list->skipped + written, run->list->total, written,
                       (vkrt_clock_ms() - run->start_ms) / 1e3, frame->path, run->terminal);
}

static bool render_on_one_device(const vkrt_render_options *opts, const vkrt_scene *scene,
                                 const char *output, const frame_list *list,
                                 render_totals *totals, startup_clock *clock,
                                 early_context *early, vkrt_error *err)
{
    bool progress = !opts->common.quiet && list->total > 1;
    bool terminal = progress && isatty(fileno(stderr));
    one_device_run run = {.totals = totals, .list = list, .clock = clock,
                          .progress = progress, .terminal = terminal};
    frame_writer w = {.opts = opts, .scene = scene, .output = output, .clear_line = terminal,
                      .clock = clock, .early = early, .sharers = 1, .frames = list->count,
                      .written = one_device_written,
                      .user = &run};
    if (!frame_writer_start(&w, opts->common.device, true, err))
        return false;
    snprintf(totals->device, sizeof totals->device, "%s", w.ctx.properties.deviceName);
    totals->accel = *vkrt_renderer_accel_stats(w.renderer);
    totals->startup = *vkrt_renderer_startup_times(w.renderer);
    const char *why;
    totals->integrator = vkrt_renderer_integrator(w.renderer, &why);
    snprintf(totals->integrator_reason, sizeof totals->integrator_reason, "%s", why);
    run.start_ms = vkrt_clock_ms();
    bool ok = true;
    for (uint32_t i = 0; ok && i < list->count; ++i) {
        /* Ctrl-C: no frame is started after it; those rendered are still written (finish). */
        if (stop_requested) {
            totals->interrupted = true;
            break;
        }
        vkrt_frame_stats stats;
        ok = frame_writer_write(&w, list->frames[i], &stats, err);
        totals->seconds += ok ? stats.seconds : 0;
        totals->rays += ok ? stats.primary_rays + stats.shadow_rays + stats.secondary_rays : 0;
    }
    ok = frame_writer_finish(&w, ok, err);
    if (terminal && totals->rendered > 0)
        fputc('\n', stderr);
    return ok;
}

/* --devices: a worker process per device (device_pool.h), each with a frame_writer. */
typedef struct pool_job {
    frame_writer writer;      /* the worker's own, in the worker's process */
    vkrt_pool_reporter *reporter; /* in the worker: where its files are reported */
    const frame_list *list;
    bool progress, terminal;
    double start_ms;
} pool_job;

/* In a worker, on its write pool's threads: a file written, or the first that failed. */
static void pool_frame_written(void *user, const vkrt_written_frame *frame)
{
    pool_job *job = user;
    vkrt_pool_report_written(job->reporter, frame->frame,
                             &(vkrt_pool_frame){.gpu_seconds = frame->gpu_seconds,
                                                .rays = frame->rays});
}

static void pool_write_failed(void *user, const vkrt_error *err)
{
    pool_job *job = user;
    vkrt_pool_report_failed(job->reporter, err);
}

static bool pool_worker_start(void *user, uint32_t worker, int device,
                              vkrt_pool_reporter *reporter, vkrt_pool_start *started,
                              vkrt_error *err)
{
    pool_job *job = user;
    job->reporter = reporter;
    frame_writer *w = &job->writer;
    if (!frame_writer_start(w, device, worker == 0, err))
        return vkrt_error_prefix(err, "device %d", device);
    const vkrt_accel_stats *accel = vkrt_renderer_accel_stats(w->renderer);
    const char *why;
    vkrt_integrator integrator = vkrt_renderer_integrator(w->renderer, &why);
    snprintf(started->device_name, sizeof started->device_name, "%s",
             w->ctx.properties.deviceName);
    snprintf(started->about, sizeof started->about,
             "vkrt: accel %s: %s\nvkrt: integrator %s: %s\n", vkrt_accel_name(accel->kind),
             accel->reason, vkrt_integrator_name(integrator), why);
    return true;
}

/* Renders frame and queues its file; returns once a buffer is free for the next frame, so that
 * the worker asks for one only when it can start it (a frame it cannot start yet is better
 * rendered by another worker). */
static bool pool_worker_render(void *user, uint32_t frame, vkrt_error *err)
{
    pool_job *job = user;
    vkrt_frame_stats stats;
    return frame_writer_write(&job->writer, frame, &stats, err) &&
           vkrt_write_pool_buffer(job->writer.pool, err) != NULL;
}

static bool pool_worker_finish(void *user, bool ok, vkrt_error *err)
{
    pool_job *job = user;
    return frame_writer_finish(&job->writer, ok, err);
}

static void pool_frame_done(void *user, uint32_t frame, uint32_t done, uint32_t worker)
{
    (void)worker;
    pool_job *job = user;
    if (!job->progress)
        return;
    char path[4096];
    vkrt_frame_path(path, sizeof path, job->writer.output, frame, NULL);
    print_progress(stderr, job->list->skipped + done, job->list->total, done,
                   (vkrt_clock_ms() - job->start_ms) / 1e3, path, job->terminal);
}

/* The per-device summary of a --devices run, and every worker that failed (even with --quiet). */
static void print_pool_summary(const vkrt_render_options *opts, const vkrt_scene *scene,
                               const frame_list *list, const vkrt_pool_result *r)
{
    for (uint32_t w = 0; w < r->worker_count; ++w) {
        const vkrt_pool_worker *k = &r->workers[w];
        if (k->failed)
            fprintf(stderr, "vkrt: device %d (%s) failed after %u frame%s: %s%s\n", k->device,
                    k->device_name[0] ? k->device_name : "not started", k->frames,
                    k->frames == 1 ? "" : "s", k->failure,
                    !k->lost_frame            ? ""
                    : k->lost_frames == 1     ? "; the frame it held went back to the others"
                                              : "; the frames it held went back to the others");
    }
    if (opts->common.quiet)
        return;
    double gpu_seconds = 0;
    uint64_t rays = 0;
    for (uint32_t w = 0; w < r->worker_count; ++w) {
        const vkrt_pool_worker *k = &r->workers[w];
        gpu_seconds += k->gpu_seconds;
        rays += k->rays;
        fprintf(stderr, "vkrt: device %d (%s): %u frame%s, %.1f ms/frame\n", k->device,
                k->device_name[0] ? k->device_name : "not started", k->frames,
                k->frames == 1 ? "" : "s", k->frames ? 1e3 * k->seconds / k->frames : 0.0);
    }
    /* The rate once a device was ready: what a longer flythrough approaches. */
    double rendering = r->seconds - r->start_seconds;
    fprintf(stderr,
            "vkrt: %u worker%s | %u triangles | %u of %u frame%s in %.2f s, the first device "
            "ready after %.2f s | %.2f frames/s after that | %.3g Mrays/s per device\n",
            r->worker_count, r->worker_count == 1 ? "" : "s", scene->model.triangle_count,
            r->rendered, list->count, list->count == 1 ? "" : "s", r->seconds, r->start_seconds,
            rendering > 0 ? r->rendered / rendering : 0.0,
            gpu_seconds > 0 ? rays / gpu_seconds * 1e-6 : 0.0);
    if (!opts->common.verbose) /* else the first worker printed its choices at its start */
        fputs(r->about, stderr);
}

/* Renders list's frames on --devices's devices. Returns the exit status. */
static int render_on_devices(const vkrt_render_options *opts, const vkrt_scene *scene,
                             const char *output, const frame_list *list)
{
    vkrt_error err = {{0}};
    char listing[4096];
    uint32_t device_count;
    int devices[VKRT_POOL_MAX_WORKERS];
    uint32_t workers;
    if (!vkrt_device_pool_list(gpu_list_devices, listing, sizeof listing, &device_count, &err) ||
        !vkrt_devices_spec_parse(opts->devices, device_count, listing, devices, &workers, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 1;
    }
    if (list->count == 0) {
        if (!opts->common.quiet)
            fprintf(stderr, "vkrt: resumed: all %u frames were already complete\n", list->total);
        return 0;
    }
    /* More workers than frames would only start devices to leave them idle. */
    if (workers > list->count)
        workers = list->count;
    pool_job job = {
        .writer = {.opts = opts, .scene = scene, .output = output, .sharers = workers,
                   .frames = list->count,
                   .written = pool_frame_written, .failed = pool_write_failed},
        .list = list,
        .progress = !opts->common.quiet && list->total > 1,
    };
    job.writer.user = &job;
    job.terminal = job.progress && isatty(fileno(stderr));
    job.writer.clear_line = job.terminal;
    job.start_ms = vkrt_clock_ms();
    vkrt_device_pool_desc desc = {
        .devices = devices,
        .worker_count = workers,
        .frames = list->frames,
        .frame_count = list->count,
        .user = &job,
        .start = pool_worker_start,
        .render = pool_worker_render,
        .finish = pool_worker_finish,
        .frame_done = pool_frame_done,
        .stop = &stop_requested,
    };
    vkrt_pool_result *result = malloc(sizeof *result);
    if (!result) {
        fprintf(stderr, "vkrt: out of memory\n");
        return 1;
    }
    if (!vkrt_device_pool_run(&desc, result, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        free(result);
        return 1;
    }
    if (job.terminal && result->rendered > 0)
        fputc('\n', stderr);
    print_pool_summary(opts, scene, list, result);
    bool suspect = false;
    for (uint32_t w = 0; w < result->worker_count; ++w)
        suspect = suspect || result->workers[w].failed_at_end;
    int status = 0;
    if (result->interrupted) {
        fprintf(stderr, "vkrt: interrupted after %u of %u frames; run again with --resume to "
                        "finish\n",
                list->skipped + result->rendered, list->total);
        status = 130;
    } else if (result->rendered < list->count) {
        fprintf(stderr, "vkrt: %u of %u frames were not rendered: every worker failed\n",
                list->count - result->rendered, list->count);
        status = 1;
    } else if (suspect) {
        status = 1;
    }
    if (!opts->common.quiet && list->skipped)
        fprintf(stderr, "vkrt: resumed: %u of %u frames were already complete\n", list->skipped,
                list->total);
    free(result);
    return status;
}

static int run_render(const vkrt_render_options *opts, double main_ms)
{
    vkrt_error err = {{0}};
    vkrt_scene scene;
    startup_clock clock = {.main = main_ms};
    /* --devices: each worker process makes its own. */
    early_context early = {.joined = true};
    if (!opts->devices)
        early_context_start(&early, opts);
    if (!vkrt_scene_load(opts->scene_path, &scene, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        early_context_discard(&early);
        return 1;
    }
    clock.scene = vkrt_clock_ms();
    if (!opts->common.quiet)
        vkrt_model_print_warnings(&scene.model, "vkrt: ", opts->common.verbose, stderr);
    const char *output = opts->output ? opts->output : scene.config.output;
    uint32_t cameras = scene.config.camera_count;
    if (opts->frames_given && opts->frame_last >= cameras) {
        fprintf(stderr, "vkrt: --frames %u:%u: %s has %u camera%s (frames 0 to %u)\n",
                opts->frame_first, opts->frame_last, opts->scene_path, cameras,
                cameras == 1 ? "" : "s", cameras - 1);
        early_context_discard(&early);
        vkrt_scene_free(&scene);
        return 1;
    }
    frame_list list;
    if (!check_output(output, scene.config.camera_count, &err) ||
        (opts->sample_count_image &&
         !check_output(opts->sample_count_image, scene.config.camera_count, &err)) ||
        !frame_list_make(opts, &scene, output, &list, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        early_context_discard(&early);
        vkrt_scene_free(&scene);
        return 1;
    }

    signal(SIGINT, request_stop);
    signal(SIGTERM, request_stop);
    if (opts->devices) {
        /* The workers are forked: none of them has the storing thread to wait for. */
        vkrt_scene_cache_finish(&scene.model_cache);
        int status = render_on_devices(opts, &scene, output, &list);
        free(list.frames);
        vkrt_scene_free(&scene);
        return status;
    }
    render_totals totals = {0};
    bool ok = render_on_one_device(opts, &scene, output, &list, &totals, &clock, &early, &err);
    early_context_discard(&early);
    free(list.frames);
    if (!ok) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        vkrt_scene_free(&scene);
        return 1;
    }
    if (totals.interrupted) {
        fprintf(stderr, "vkrt: interrupted after %u of %u frames; run again with --resume to "
                        "finish\n",
                totals.rendered + list.skipped, list.total);
        vkrt_scene_free(&scene);
        return 130;
    }
    if (!opts->common.quiet && list.skipped)
        fprintf(stderr, "vkrt: resumed: %u of %u frames were already complete\n", list.skipped,
                list.total);
    if (!opts->common.quiet) {
        uint32_t rendered = totals.rendered;
        fprintf(stderr,
                "vkrt: %s | %u triangles | accel %s | %u frame%s | %.1f ms/frame | %.3g Mrays/s\n",
                totals.device, scene.model.triangle_count, vkrt_accel_name(totals.accel.kind),
                rendered, rendered == 1 ? "" : "s",
                rendered ? 1e3 * totals.seconds / rendered : 0.0,
                totals.seconds > 0 ? totals.rays / totals.seconds * 1e-6 : 0.0);
        if (opts->common.verbose && clock.image)
            print_startup(stderr, &clock, &scene, &totals.accel, &totals.startup);
        if (opts->common.verbose && scene.model_cache.outcome == VKRT_SCENE_CACHE_STORING) {
            /* Said "being stored" before the first frame: now how it ended. */
            vkrt_scene_cache_finish(&scene.model_cache);
            print_scene_cache(stderr, &scene.model_cache);
        }
        if (!opts->common.verbose) {
            fprintf(stderr, "vkrt: accel %s: %s\n", vkrt_accel_name(totals.accel.kind),
                    totals.accel.reason);
            fprintf(stderr, "vkrt: integrator %s: %s\n", vkrt_integrator_name(totals.integrator),
                    totals.integrator_reason);
        }
    }
    vkrt_scene_free(&scene);
    return 0;
}

int main(int argc, char **argv)
{
    double main_ms = vkrt_clock_ms();
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
        return run_render(&cl.render, main_ms);
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
