/*
 * report.h: what `vkrt render` prints on stderr besides errors: the choices the renderer made and
 * their statistics (--verbose), a flythrough's progress, and the summary at the end. Printing
 * only: nothing here decides how a run goes.
 */
#ifndef VKRT_CMD_REPORT_H
#define VKRT_CMD_REPORT_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "../device_pool.h"
#include "../gpu/context.h"
#include "../render/renderer.h"
#include "../scene/scene.h"
#include "cli.h"

/* The structure the renderer uses, why, and its build (or cache read) statistics. */
void report_accel_stats(FILE *out, const vkrt_accel_stats *s);

/* Where the kernels came from: glslang, or the cache of earlier starts (gpu/spirv_cache.h). */
void report_kernel_cache(FILE *out);

/* Where the model came from: the scene file parsed, or the scene cache (scene/scene_cache.h); nothing
 * when the cache was off. */
void report_scene_cache(FILE *out, const vkrt_scene_cache_report *c);

/* A flythrough's progress after a frame: frames done of the run's, frames per second and the
 * time left at that rate. On a terminal one line, rewritten in place (the caller ends it); else a
 * line per frame, for logs. */
void report_progress(FILE *out, uint32_t done, uint32_t total, uint32_t rendered, double seconds,
                     const char *path, bool terminal);

/* Device memory by what it is for, against what the device has, and host memory: the mesh's
 * arrays and the process's peak (--verbose). */
void report_memory(FILE *out, const vkrt_renderer *renderer, const gpu_context *ctx,
                   const vkrt_scene *scene);

/* Wall-clock ms of the stages of a render's start, printed with --verbose: the clock read when
 * main began, when the scene was loaded, the Vulkan device opened, the renderer made (structure,
 * upload, kernels), the first frame traced and its image written. */
typedef struct startup_clock {
    double main, scene, vulkan, renderer, frame, image;
} startup_clock;

void report_startup(FILE *out, const startup_clock *t, const vkrt_scene *scene,
                    const vkrt_accel_stats *accel, const vkrt_renderer_startup *steps);

/* The per-device summary of a --devices run of frame_count frames, and every worker that failed
 * (even with --quiet). */
void report_pool_summary(const vkrt_render_options *opts, const vkrt_scene *scene,
                         uint32_t frame_count, const vkrt_pool_result *r);

/* What a single-device run did, for its summary. */
typedef struct render_totals {
    double seconds;
    uint64_t rays;
    uint32_t rendered;
    bool interrupted;
    char device[256];
    vkrt_accel_stats accel;
    vkrt_renderer_startup startup; /* the renderer's steps (--verbose's start-up line) */
    vkrt_integrator integrator;    /* what the renderer computed, and why */
    char integrator_reason[256];
} render_totals;

/* The summary line of a single-device run, and with --verbose its start-up and the scene cache's
 * outcome (waiting for a mesh still being stored); without it the structure and integrator
 * chosen. Nothing with --quiet. */
void report_render_summary(const vkrt_render_options *opts, vkrt_scene *scene,
                           const render_totals *totals, const startup_clock *clock);

#endif
