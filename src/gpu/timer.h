/*
 * timer.h: GPU timestamps around recorded work, for benchmarks (never for tests' verdicts).
 */
#ifndef VKRT_GPU_TIMER_H
#define VKRT_GPU_TIMER_H

#include <stdbool.h>
#include <stdint.h>
#include <vulkan/vulkan.h>

#include "context.h"

typedef struct gpu_timer {
    VkQueryPool pool;
    uint32_t count;       /* timestamps the pool holds */
    double ns_per_tick;   /* VkPhysicalDeviceLimits::timestampPeriod */
} gpu_timer;

/* Creates a pool of count timestamps. Fails with a message when the compute queue has no
 * timestamps (timestampValidBits == 0). */
bool gpu_timer_create(gpu_context *ctx, gpu_timer *t, uint32_t count, vkrt_error *err);

/* Frees the pool. Safe on a zeroed timer. */
void gpu_timer_destroy(gpu_context *ctx, gpu_timer *t);

/* Records a reset of all timestamps; call once per command buffer, before any write. */
void gpu_timer_reset(VkCommandBuffer cmd, gpu_timer *t);

/* Records timestamp index once all earlier work has finished. */
void gpu_timer_write(VkCommandBuffer cmd, gpu_timer *t, uint32_t index);

/* After the command buffer completed: milliseconds between timestamps first and second. */
bool gpu_timer_ms(gpu_context *ctx, gpu_timer *t, uint32_t first, uint32_t second, double *ms,
                  vkrt_error *err);

#endif
