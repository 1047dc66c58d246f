/*
 * profile.h: GPU timestamps around every dispatch of a frame (`vkrt render --profile`): which
 * kernel at which depth each timestamp closes, and the medians over several timed frames.
 */
#ifndef VKRT_PROFILE_H
#define VKRT_PROFILE_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "../error.h"
#include "../gpu/timer.h"

/* The kernels of a frame, for profiles. */
enum { VKRT_KERNEL_RAYGEN, VKRT_KERNEL_TRACE, VKRT_KERNEL_ORDER, VKRT_KERNEL_LIGHT,
       VKRT_KERNEL_COUNT, VKRT_KERNEL_PREPARE, VKRT_KERNEL_SHADE, VKRT_KERNEL_KINDS };
/* Depths a profile tells apart; deeper ones are added to the last. */
#define VKRT_PROFILE_DEPTHS 17

/* What a profile measured. */
typedef struct vkrt_frame_profile {
    bool profiled;            /* the renderer was created with desc.profile: */
    double kernel_ms[VKRT_PROFILE_DEPTHS][VKRT_KERNEL_KINDS]; /* GPU ms per depth and kernel,
                                 summed over the sample passes (raygen counts at depth 0), the
                                 median over the timed frames */
    double frame_ms;          /* GPU ms from the first dispatch to the last, the median */
    uint32_t frames;          /* timed frames the medians are of */
    uint32_t warmups;         /* frames rendered back to back before them */
} vkrt_frame_profile;

/* Prints a profile as a table: a row per depth, a column per kernel, and the frame's time over
 * its tracing's (closest hits and shadow rays: trace + light). */
void vkrt_frame_profile_print(FILE *out, const vkrt_frame_profile *p);

/* The recording side: a timestamp after every kernel, and which frame (of the timed ones),
 * kernel and depth each one closes. */
typedef struct profile_mark {
    uint32_t frame;
    uint8_t depth, kernel;
} profile_mark;

typedef struct profile_recorder {
    gpu_timer timer;
    profile_mark *marks;
    uint32_t count;           /* marks so far; timestamp 0 opens the first timed frame */
    uint32_t capacity;        /* marks there is room for */
    bool overflow;            /* a mark found no room (a miscount of the caller's: an error) */
    uint32_t frame;           /* the timed frame being recorded */
    uint32_t *frame_end;      /* per timed frame, its last timestamp */
} profile_recorder;

/* Room for `marks` timestamps over `frames` timed frames. On failure nothing is left. */
bool profile_recorder_create(gpu_context *ctx, profile_recorder *p, uint32_t marks,
                             uint32_t frames, vkrt_error *err);
void profile_recorder_destroy(gpu_context *ctx, profile_recorder *p);

/* Resets the timer and writes timestamp 0 (before the first timed frame). */
void profile_recorder_begin(VkCommandBuffer cmd, profile_recorder *p);

/* A timestamp closing `kernel` at `depth` of the frame being recorded. p may be NULL (no-op). */
void profile_recorder_mark(VkCommandBuffer cmd, profile_recorder *p, uint32_t depth,
                           uint32_t kernel);

/* Ends the timed frame being recorded. */
void profile_recorder_end_frame(profile_recorder *p);

/* After the submission: the medians over the timed frames into out. */
bool profile_recorder_read(gpu_context *ctx, profile_recorder *p, vkrt_frame_profile *out,
                           vkrt_error *err);

#endif
