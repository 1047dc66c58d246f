/*
 * frame_writer.h: one device rendering a scene's frames into their files, for `vkrt render`: the
 * single-device loop and each worker of --devices (device_pool.h) use it. Files are written by a
 * pool of threads while the next frame renders (output/write_pool.h), every frame through the
 * finish stage (output/finish.h); the callbacks hear of each file written.
 */
#ifndef VKRT_CMD_FRAME_WRITER_H
#define VKRT_CMD_FRAME_WRITER_H

#include <pthread.h>
#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "../gpu/context.h"
#include "../output/write_pool.h"
#include "../render/renderer.h"
#include "../scene/scene.h"
#include "cli.h"
#include "report.h"

/* The single device's Vulkan context, made on a thread of its own while the scene loads: making
 * the instance and the device takes about as long as loading a small scene, so the two overlap. */
typedef struct early_context {
    gpu_context_desc desc;
    gpu_context ctx;
    vkrt_error err;
    bool ok;
    bool started; /* the thread runs, to be joined */
    bool joined;
    pthread_t thread;
} early_context;

/* Starts making the context the options ask for (made at the join if no thread can start). */
void early_context_start(early_context *e, const vkrt_render_options *opts);

/* For the ways out before the context is taken: joins the thread and frees what it made. Does
 * nothing once the context was taken (or on {.joined = true}). */
void early_context_discard(early_context *e);

typedef struct frame_writer {
    const vkrt_command_line *cl; /* a render command's */
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
    vkrt_denoiser *denoiser; /* --denoise: the finish stage's (output/denoise.h); else NULL */
} frame_writer;

/* Creates the device's context (or takes early's) and the renderer; tell says whether to print
 * the choices (--verbose) and notes about the scene. On failure err says why and nothing is
 * left. */
bool frame_writer_start(frame_writer *w, int device, bool tell, vkrt_error *err);

/* Renders frame f and hands it to the write pool, which writes its file (a temporary renamed
 * onto it: image_write.h); prints the frame's warnings, and with a target error what it reached. */
bool frame_writer_write(frame_writer *w, uint32_t f, vkrt_frame_stats *stats, vkrt_error *err);

/* Waits for the files still being written, then frees what start took; after a run that went
 * well (ok), the validation layers' word too. A write that fails here makes the run fail. */
bool frame_writer_finish(frame_writer *w, bool ok, vkrt_error *err);

/* The frames a run renders: --frames's (all by default), less, with --resume, those whose files
 * are complete. */
typedef struct frame_list {
    uint32_t *frames; /* to be freed */
    uint32_t count;   /* to render */
    uint32_t total;   /* in the range, complete ones included */
    uint32_t skipped; /* complete already (--resume) */
} frame_list;

bool frame_list_make(const vkrt_command_line *cl, const vkrt_scene *scene, const char *output,
                     frame_list *list, vkrt_error *err);

#endif
