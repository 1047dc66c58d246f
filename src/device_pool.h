/*
 * device_pool.h: a flythrough spread over several devices (`vkrt render --devices`), one worker
 * process per device, frames handed out from one queue.
 *
 * The parent process holds the scene (loaded before vkrt_device_pool_run, so every worker shares
 * it copy-on-write) and never touches a device: it forks the workers, gives each a frame number
 * through a pipe whenever the worker says it is ready for one, and collects what each reports. A
 * fast device thus takes more frames than a slow one. A worker asks for the next frame as soon as
 * it can render it, while its threads still write the files of the frames before (the caller's
 * business: main.c's write pool), so it may hold several frames; each is done when its file is
 * reported written. A worker that fails (its device lost, its
 * driver crashing, a `kill -9`) costs only itself: its pipe closes, the frames it held go back
 * to the queue for the others, and it is reported. The module knows nothing of Vulkan or scenes:
 * what a worker does is the caller's, through the three callbacks below, which run in the worker
 * process (docs/architecture.md, "Several devices").
 */
#ifndef VKRT_DEVICE_POOL_H
#define VKRT_DEVICE_POOL_H

#include <signal.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "error.h"

/* At most this many workers (devices, or the same device listed again). */
enum { VKRT_POOL_MAX_WORKERS = 64 };

/* What a worker says after starting (vkrt_device_pool_desc.start). */
typedef struct vkrt_pool_start {
    char device_name[256];
    char about[768]; /* lines the parent prints once in its summary (the first worker's),
                        e.g. which structure and integrator were chosen and why */
} vkrt_pool_start;

/* What a worker says after a frame (vkrt_device_pool_desc.render). */
typedef struct vkrt_pool_frame {
    double gpu_seconds; /* the renderer's time on the device */
    uint64_t rays;
} vkrt_pool_frame;

/* How a worker tells the parent about its frames' files, from any of its threads (a report is
 * one write() of less than PIPE_BUF bytes, so reports of several threads never mix). Valid for
 * the worker's life; given to the start callback. */
typedef struct vkrt_pool_reporter {
    int fd;
    atomic_int failed; /* set by vkrt_pool_report_failed */
} vkrt_pool_reporter;

/* In a worker: frame's file is complete (renamed into place). */
void vkrt_pool_report_written(vkrt_pool_reporter *reporter, uint32_t frame,
                              const vkrt_pool_frame *result);

/* In a worker: a file failed to be written on another thread than the one that renders (err
 * names it). The parent hands the worker no more frames; the frames it holds go back to the
 * queue when it ends, which it does when its render callback next returns false or its frame
 * pipe ends. */
void vkrt_pool_report_failed(vkrt_pool_reporter *reporter, const vkrt_error *err);

typedef struct vkrt_device_pool_desc {
    const int *devices;     /* the device index of each worker */
    uint32_t worker_count;  /* 1 to VKRT_POOL_MAX_WORKERS */
    const uint32_t *frames; /* the frames to render, handed out in this order */
    uint32_t frame_count;
    void *user; /* given to every callback */
    /* In the worker: prepare to render on device (e.g. create a context and a renderer); worker is
     * its index in devices; reporter is where its frames' files are reported. False with err set:
     * the worker fails, the others go on. */
    bool (*start)(void *user, uint32_t worker, int device, vkrt_pool_reporter *reporter,
                  vkrt_pool_start *started, vkrt_error *err);
    /* In the worker: render frame and see its file written (atomically: a worker may be killed at
     * any moment), then or later on another thread, calling vkrt_pool_report_written when it is.
     * Returns when the worker can take another frame: a worker holds the frames it was given
     * until their files are reported. False with err set: the worker fails and every frame it
     * holds goes back to the queue. */
    bool (*render)(void *user, uint32_t frame, vkrt_error *err);
    /* In the worker, when the queue is empty or the run stops: wait for the files still being
     * written (reporting them), free what start took. ok says whether the worker's run went
     * well; false with err set reports a failure found at the end (e.g. a validation message).
     * May be NULL. */
    bool (*finish)(void *user, bool ok, vkrt_error *err);
    /* In the parent, after each frame written: done frames of frame_count so far. May be NULL. */
    void (*frame_done)(void *user, uint32_t frame, uint32_t done, uint32_t worker);
    /* Set (by a signal handler) to stop: no frame is handed out after, the frames being rendered
     * and written finish. May be NULL. */
    volatile sig_atomic_t *stop;
} vkrt_device_pool_desc;

/* How one worker's run went. */
typedef struct vkrt_pool_worker {
    int device;
    char device_name[256]; /* empty when it failed before saying */
    uint32_t frames;       /* frames it wrote */
    double seconds;        /* from its start (ready) to its last file written: its frames took
                              seconds / frames each, rendering and writing overlapped */
    double gpu_seconds;
    uint64_t rays;
    bool failed;
    char failure[1024]; /* why: its error, or how the process ended ("killed by signal 9") */
    bool failed_at_end; /* its finish callback failed after its frames (e.g. validation
                           messages): the frames it wrote are suspect */
    bool lost_frame;    /* it failed holding frames, which went back to the queue */
    uint32_t lost_frame_number; /* the first of them */
    uint32_t lost_frames;       /* how many */
} vkrt_pool_worker;

typedef struct vkrt_pool_result {
    vkrt_pool_worker workers[VKRT_POOL_MAX_WORKERS];
    uint32_t worker_count;
    uint32_t rendered; /* frames written, of desc.frame_count */
    bool interrupted;  /* desc.stop was set before every frame was handed out */
    char about[768];   /* the first started worker's vkrt_pool_start.about */
    double seconds;    /* the run's wall time */
    double start_seconds;     /* from the run's start until the first worker was ready (its
                                 device's context, structure and kernels made) */
} vkrt_pool_result;

/* Runs the flythrough: forks the workers, hands out every frame, waits for all of them. Returns
 * true when the pool ran (every frame written, or stopped by desc.stop, or some frames left
 * because every worker failed: result says which); false with err set when it could not start
 * (no pipes, no processes). Ignores SIGPIPE in the calling process (a worker's pipe may close
 * under a write). */
bool vkrt_device_pool_run(const vkrt_device_pool_desc *desc, vkrt_pool_result *result,
                          vkrt_error *err);

/* Runs list (e.g. gpu_list_devices) in a child process and returns what it printed in text (size
 * bytes; one line per device, each starting with its index) and the number of devices: the
 * parent of a pool must not load a Vulkan driver before it forks. False with err set when list
 * failed or the child could not run. */
bool vkrt_device_pool_list(bool (*list)(FILE *out, vkrt_error *err), char *text, size_t size,
                           uint32_t *device_count, vkrt_error *err);

/* Checks the form of a --devices value: "all", or device indices separated by commas ("0,2",
 * "0,0": one device may take several workers). */
bool vkrt_devices_spec_check(const char *spec, vkrt_error *err);

/* The device index of each worker --devices spec asks for, of device_count devices (listing:
 * vkrt_device_pool_list's text, quoted when an index does not exist). */
bool vkrt_devices_spec_parse(const char *spec, uint32_t device_count, const char *listing,
                             int *devices, uint32_t *worker_count, vkrt_error *err);

#endif
