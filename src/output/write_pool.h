/*
 * write_pool.h: a flythrough's frames written on other threads while the next ones render.
 *
 * The render loop takes a buffer (vkrt_write_pool_buffer), renders a frame's linear RGB into it
 * and hands it back with the frame's path (vkrt_write_pool_submit); a writer thread turns it into
 * the file (vkrt_image_write: a temporary renamed when complete) while the loop renders the
 * next. The pool owns threads + 2 buffers of width x height pixels: at most that many frames are
 * in flight (one being rendered, one waiting, one per writer thread), and the loop waits for a
 * free buffer when the writers fall behind, so memory stays bounded. With 0 threads the frame is
 * written inside vkrt_write_pool_submit, on the caller's thread, as vkrt did before the pool.
 *
 * A failed write stops the pool: the frames still queued are dropped (never half-written), the
 * next call of the loop returns the failure, which names the file. Writer threads block SIGINT
 * and SIGTERM, so the render loop's thread sees them.
 */
#ifndef VKRT_WRITE_POOL_H
#define VKRT_WRITE_POOL_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "finish.h"

typedef struct vkrt_write_pool vkrt_write_pool;

/* A frame handed to the pool, given back to the callbacks when its file is written. */
typedef struct vkrt_written_frame {
    uint32_t frame;
    const char *path;   /* copied by submit */
    double gpu_seconds; /* the caller's numbers, passed through */
    uint64_t rays;
} vkrt_written_frame;

typedef struct vkrt_write_pool_desc {
    uint32_t threads; /* writer threads, at most VKRT_WRITE_POOL_MAX_THREADS; 0: no threads */
    uint32_t width, height;
    vkrt_finish_desc finish; /* the finish stage every frame passes through (finish.h) */
    uint32_t aovs;    /* the AOVs each frame carries (--aov): VKRT_AOV_* of glsl/shared.h, 1
                         albedo, 2 normal, 4 depth, 8 position; 0: the beauty alone */
    uint32_t aovs_written; /* of aovs, those written beside the beauty (--aov); the others are
                              the denoiser's guides, handed to the finish stage only */
    /* Called once a frame's file is complete (renamed into place), on the thread that wrote it;
     * calls of both callbacks never overlap. May be NULL. */
    void (*written)(void *user, const vkrt_written_frame *frame);
    /* Called once, for the first write that failed, on its thread; err names the file. May be
     * NULL. */
    void (*failed)(void *user, const vkrt_error *err);
    void *user;
} vkrt_write_pool_desc;

enum { VKRT_WRITE_POOL_MAX_THREADS = 16 };

/* How many writer threads a render should use when sharers processes share the cores it may run
 * on (its affinity: a Slurm task's, a taskset's; sharers: the workers of --devices):
 * VKRT_WRITE_THREADS if set (0 to 16; 0 writes on the render thread), else one core a process
 * left to rendering and the rest, at most 4, to writing, at least 1. False with err set for a VKRT_WRITE_THREADS that is not such a number. */
bool vkrt_write_pool_threads(uint32_t sharers, uint32_t *threads, vkrt_error *err);

/* Makes the pool: its buffers and threads. False with err set (out of memory, no threads); then
 * nothing is left. */
bool vkrt_write_pool_create(vkrt_write_pool **pool, const vkrt_write_pool_desc *desc,
                            vkrt_error *err);

/* The buffer to render the next frame into (width * height * 3 floats): the one taken before and
 * not yet submitted, else a free one, waiting for a writer to free one. NULL with err set when a
 * write has failed. */
float *vkrt_write_pool_buffer(vkrt_write_pool *pool, vkrt_error *err);

/* The AOV buffers of the frame held since vkrt_write_pool_buffer, for the render loop to read the
 * frame's AOVs into: aovs[k] for the AOV of bit 1 << k of desc.aovs (albedo, normal, depth,
 * position, laid out as image_write.h's vkrt_frame_image says), NULL for those it lacks or when
 * no frame is held. They are written with the frame's beauty. */
void vkrt_write_pool_aovs(vkrt_write_pool *pool, float *aovs[4]);

/* Queues the buffer taken by vkrt_write_pool_buffer, holding frame's pixels, to be written to
 * frame->path. With 0 threads writes it now. False with err set when this or an earlier write
 * failed (or no buffer was taken). */
bool vkrt_write_pool_submit(vkrt_write_pool *pool, const vkrt_written_frame *frame,
                            vkrt_error *err);

/* Waits until every submitted frame is written. False with err set (the first failure) when a
 * write failed. */
bool vkrt_write_pool_finish(vkrt_write_pool *pool, vkrt_error *err);

/* Writes the frames still queued (unless a write failed), stops the threads, frees everything.
 * NULL does nothing. */
void vkrt_write_pool_destroy(vkrt_write_pool *pool);

#endif
