/*
 * render.c: `vkrt render` (render.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "render.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "../clock.h"
#include "../device_pool.h"
#include "../output/image_write.h"
#include "../scene/scene.h"
#include "frame_writer.h"
#include "render_desc.h"
#include "report.h"
#include "scene_options.h"

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
    if (!*output)
        return vkrt_error_set(err, "the output file name is empty: give -o PATH, a .png or .exr");
    char first[4096];
    if (!vkrt_frame_path(first, sizeof first, output, 0, err))
        return false;
    if (vkrt_image_format_of(first) == VKRT_IMAGE_UNKNOWN)
        return vkrt_error_set(err, "%s: unknown image format (use .png or .exr)", output);
    if (frames > 1 && !vkrt_frame_pattern_has_number(output))
        return vkrt_error_set(err,
                              "%s: the scene has %u cameras (frames) but the output has no "
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
        report_progress(stderr, run->list->skipped + written, run->list->total, written,
                        (vkrt_clock_ms() - run->start_ms) / 1e3, frame->path, run->terminal);
}

static bool render_on_one_device(const vkrt_command_line *cl, const vkrt_scene *scene,
                                 const char *output, const frame_list *list, render_totals *totals,
                                 startup_clock *clock, early_context *early, vkrt_error *err)
{
    const vkrt_render_options *opts = &cl->render;
    bool progress = !opts->common.quiet && list->total > 1;
    bool terminal = progress && isatty(fileno(stderr));
    one_device_run run = {
        .totals = totals, .list = list, .clock = clock, .progress = progress, .terminal = terminal};
    frame_writer w = {.cl = cl,
                      .scene = scene,
                      .output = output,
                      .clear_line = terminal,
                      .clock = clock,
                      .early = early,
                      .sharers = 1,
                      .frames = list->count,
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
    frame_writer writer;          /* the worker's own, in the worker's process */
    vkrt_pool_reporter *reporter; /* in the worker: where its files are reported */
    const frame_list *list;
    bool progress, terminal;
    double start_ms;
} pool_job;

/* In a worker, on its write pool's threads: a file written, or the first that failed. */
static void pool_frame_written(void *user, const vkrt_written_frame *frame)
{
    pool_job *job = user;
    vkrt_pool_report_written(
        job->reporter, frame->frame,
        &(vkrt_pool_frame){.gpu_seconds = frame->gpu_seconds, .rays = frame->rays});
}

static void pool_write_failed(void *user, const vkrt_error *err)
{
    pool_job *job = user;
    vkrt_pool_report_failed(job->reporter, err);
}

static bool pool_worker_start(void *user, uint32_t worker, int device, vkrt_pool_reporter *reporter,
                              vkrt_pool_start *started, vkrt_error *err)
{
    pool_job *job = user;
    job->reporter = reporter;
    frame_writer *w = &job->writer;
    if (!frame_writer_start(w, device, worker == 0, err))
        return vkrt_error_prefix(err, "device %d", device);
    const vkrt_accel_stats *accel = vkrt_renderer_accel_stats(w->renderer);
    const char *why;
    vkrt_integrator integrator = vkrt_renderer_integrator(w->renderer, &why);
    snprintf(started->device_name, sizeof started->device_name, "%s", w->ctx.properties.deviceName);
    snprintf(started->about, sizeof started->about, "vkrt: accel %s: %s\nvkrt: integrator %s: %s\n",
             vkrt_accel_name(accel->kind), accel->reason, vkrt_integrator_name(integrator), why);
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
    report_progress(stderr, job->list->skipped + done, job->list->total, done,
                    (vkrt_clock_ms() - job->start_ms) / 1e3, path, job->terminal);
}

/* Renders list's frames on --devices's devices. Returns the exit status. */
static int render_on_devices(const vkrt_command_line *cl, const vkrt_scene *scene,
                             const char *output, const frame_list *list)
{
    const vkrt_render_options *opts = &cl->render;
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
        .writer = {.cl = cl,
                   .scene = scene,
                   .output = output,
                   .sharers = workers,
                   .frames = list->count,
                   .written = pool_frame_written,
                   .failed = pool_write_failed},
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
    report_pool_summary(opts, scene, list->count, result);
    bool suspect = false;
    for (uint32_t w = 0; w < result->worker_count; ++w)
        suspect = suspect || result->workers[w].failed_at_end;
    int status = 0;
    if (result->interrupted) {
        fprintf(stderr,
                "vkrt: interrupted after %u of %u frames; run again with --resume to "
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

int vkrt_cmd_render(const vkrt_command_line *cl, double main_ms)
{
    const vkrt_render_options *opts = &cl->render;
    vkrt_error err = {{0}};
    vkrt_scene scene;
    startup_clock clock = {.main = main_ms};
    /* --denoise without its library stops here, before any work. */
    if (vkrt_denoise_asked(cl, NULL) && !vkrt_denoise_library_check(&err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        return 1;
    }
    /* --devices: each worker process makes its own. */
    early_context early = {.joined = true};
    if (!opts->devices)
        early_context_start(&early, opts);
    vkrt_load_options load = {.fps = opts->scene_options.fps};
    if (!vkrt_scene_load_with(opts->scene_path, &load, &scene, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        early_context_discard(&early);
        return 1;
    }
    if (!vkrt_scene_options_apply(&opts->scene_options, &scene,
                                  opts->common.quiet ? NULL : stderr, &err)) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        early_context_discard(&early);
        vkrt_scene_free(&scene);
        return 1;
    }
    /* `denoise on` in the scene file: its library is checked as soon as the file is read. */
    if (vkrt_denoise_asked(cl, &scene.config) && !vkrt_denoise_library_check(&err)) {
        fprintf(stderr, "vkrt: %s: denoise on: %s\n", opts->scene_path, err.msg);
        early_context_discard(&early);
        vkrt_scene_free(&scene);
        return 1;
    }
    clock.scene = vkrt_clock_ms();
    if (!opts->common.quiet)
        vkrt_model_print_warnings(&scene.model, "vkrt: ", opts->common.verbose, stderr);
    const char *output = opts->output ? opts->output : scene.config.output;
    uint32_t cameras = scene.camera_count;
    if (opts->frames_given && opts->frame_last >= cameras) {
        fprintf(stderr, "vkrt: --frames %u:%u: %s has %u camera%s (frames 0 to %u)\n",
                opts->frame_first, opts->frame_last, opts->scene_path, cameras,
                cameras == 1 ? "" : "s", cameras - 1);
        early_context_discard(&early);
        vkrt_scene_free(&scene);
        return 1;
    }
    frame_list list;
    if (!check_output(output, scene.camera_count, &err) ||
        (opts->sample_count_image &&
         !check_output(opts->sample_count_image, scene.camera_count, &err)) ||
        !frame_list_make(cl, &scene, output, &list, &err)) {
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
        int status = render_on_devices(cl, &scene, output, &list);
        free(list.frames);
        vkrt_scene_free(&scene);
        return status;
    }
    render_totals totals = {0};
    bool ok = render_on_one_device(cl, &scene, output, &list, &totals, &clock, &early, &err);
    early_context_discard(&early);
    free(list.frames);
    if (!ok) {
        fprintf(stderr, "vkrt: %s\n", err.msg);
        vkrt_scene_free(&scene);
        return 1;
    }
    if (totals.interrupted) {
        fprintf(stderr,
                "vkrt: interrupted after %u of %u frames; run again with --resume to "
                "finish\n",
                totals.rendered + list.skipped, list.total);
        vkrt_scene_free(&scene);
        return 130;
    }
    if (!opts->common.quiet && list.skipped)
        fprintf(stderr, "vkrt: resumed: %u of %u frames were already complete\n", list.skipped,
                list.total);
    report_render_summary(opts, &scene, &totals, &clock);
    vkrt_scene_free(&scene);
    return 0;
}
