/*
 * rtpipe_trace.h: the ray tracing pipeline over one scene's structures: raygen, two miss shaders
 * (closest hit; shadow) and one triangle hit group, its shader binding table, and buffers for
 * `capacity` rays and hits. Traces arrays of glsl/shared.h Rays as vkrt_renderer_trace does.
 */
#ifndef RTPIPE_TRACE_H
#define RTPIPE_TRACE_H

#include <stdbool.h>
#include <stdint.h>

#include "error.h"
#include "gpu/buffer.h"
#include "rtpipe_accel.h"
#include "rtpipe_device.h"
#include "rtpipe_shaders.h"

typedef struct Ray Ray;
typedef struct Hit Hit;

typedef struct rtpipe_tracer {
    VkDescriptorSetLayout set_layout;
    VkPipelineLayout layout;
    VkDescriptorPool pool;
    VkDescriptorSet set;
    VkPipeline pipeline;
    gpu_buffer sbt, rays, hits;
    VkStridedDeviceAddressRegionKHR raygen_region, miss_region, hit_region, callable_region;
    uint32_t capacity;
    uint32_t max_width, max_height; /* the launch limits (maxComputeWorkGroupCount x Size) */
} rtpipe_tracer;

/* Creates the pipeline from compiled shaders, its SBT, and buffers for capacity rays, bound to
 * accel's top-level structure and instance_first, its hit numbering built into closest.rchit. On failure returns false with err set and nothing left. */
bool rtpipe_tracer_create(rtpipe_device *dev, const rtpipe_shaders *shaders,
                          const rtpipe_accel *accel, uint32_t capacity, rtpipe_tracer *t,
                          vkrt_error *err);

/* Traces count rays (at most the capacity): to their closest hits (Hit as vkrt's: t, the
 * barycentrics of vertices 1 and 2, the triangle's index in vkrt_model_world's order), or (any_hit) to whether
 * anything blocks them (triangle 0) or not (VKRT_NO_HIT). The trace runs repeats times (0 means
 * 1) back to back in one submission; gpu_ms, when not NULL, receives each run's GPU time from
 * timestamps (repeats entries). */
bool rtpipe_tracer_trace(rtpipe_device *dev, rtpipe_tracer *t, const Ray *rays, uint32_t count,
                         bool any_hit, Hit *hits, uint32_t repeats, double *gpu_ms,
                         vkrt_error *err);

/* Frees everything the tracer created. Safe on a zeroed one. */
void rtpipe_tracer_destroy(rtpipe_device *dev, rtpipe_tracer *t);

#endif
