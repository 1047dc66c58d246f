/* timer.c: timestamp queries (see timer.h). */
#include "timer.h"

#include <stdlib.h>
#include <string.h>

#include "vk_check.h"

bool gpu_timer_create(gpu_context *ctx, gpu_timer *t, uint32_t count, vkrt_error *err)
{
    memset(t, 0, sizeof *t);
    uint32_t families = 0;
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &families, NULL);
    VkQueueFamilyProperties *props = calloc(families ? families : 1, sizeof *props);
    if (!props)
        return vkrt_error_set(err, "out of memory");
    vkGetPhysicalDeviceQueueFamilyProperties(ctx->physical, &families, props);
    uint32_t valid_bits = ctx->queue_family < families ? props[ctx->queue_family].timestampValidBits : 0;
    free(props);
    if (valid_bits == 0)
        return vkrt_error_set(err, "%s: the compute queue has no timestamps",
                              ctx->properties.deviceName);
    VkQueryPoolCreateInfo info = {
        .sType = VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO,
        .queryType = VK_QUERY_TYPE_TIMESTAMP,
        .queryCount = count,
    };
    GPU_CHECK(vkCreateQueryPool(ctx->device, &info, NULL, &t->pool));
    t->count = count;
    t->ns_per_tick = ctx->properties.limits.timestampPeriod;
    return true;
fail:
    return false;
}

void gpu_timer_destroy(gpu_context *ctx, gpu_timer *t)
{
    /* The device may still be running work that uses it (see gpu_context.lost). */
    if (ctx->lost) {
        memset(t, 0, sizeof *t);
        return;
    }
    if (t->pool)
        vkDestroyQueryPool(ctx->device, t->pool, NULL);
    memset(t, 0, sizeof *t);
}

void gpu_timer_reset(VkCommandBuffer cmd, gpu_timer *t)
{
    vkCmdResetQueryPool(cmd, t->pool, 0, t->count);
}

void gpu_timer_write(VkCommandBuffer cmd, gpu_timer *t, uint32_t index)
{
    vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, t->pool, index);
}

bool gpu_timer_ms(gpu_context *ctx, gpu_timer *t, uint32_t first, uint32_t second, double *ms,
                  vkrt_error *err)
{
    uint64_t ticks[2];
    GPU_CHECK(vkGetQueryPoolResults(ctx->device, t->pool, first, 1, sizeof ticks[0], &ticks[0],
                                    sizeof ticks[0], VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    GPU_CHECK(vkGetQueryPoolResults(ctx->device, t->pool, second, 1, sizeof ticks[1], &ticks[1],
                                    sizeof ticks[1], VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT));
    *ms = (double)(ticks[1] - ticks[0]) * t->ns_per_tick * 1e-6;
    return true;
fail:
    return false;
}
