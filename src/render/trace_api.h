/*
 * trace_api.h: the renderer's structure and trace kernels on rays given by the caller, outside
 * any frame: `vkrt bench` times them, tests hold them against references.
 */
#ifndef VKRT_TRACE_API_H
#define VKRT_TRACE_API_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "renderer.h"

/* The structs of glsl/shared.h; declared here so callers need not include it. */
typedef struct Ray Ray;
typedef struct Hit Hit;

/* What the trace kernels counted for one trace (glsl/shared.h Counters.trace_*). */
typedef struct vkrt_traversal_stats {
    uint32_t rays;
    double steps_per_ray;     /* BVH records fetched */
    double tests_per_ray;     /* triangle tests */
    double simd_utilisation;  /* lane-iterations with work over those the subgroups spent */
    uint32_t subgroup_size;
} vkrt_traversal_stats;

/* Traces count rays (count <= width * height of the renderer) with the renderer's structure: to
 * their closest hits, or (any_hit) to whether anything blocks them (hit.triangle 0 or
 * VKRT_NO_HIT; the any-hit kernel compiles on the first such call: a render never needs it). Closest-hit triangles are reported as original (OBJ order) indices; under a
 * two-level BVH as indices into vkrt_model_world's order (their low 32 bits). The trace
 * runs `repeats` times (0 means 1) back to back in one submission; when gpu_ms is not NULL it
 * receives each run's GPU time from timestamps (repeats entries). */
bool vkrt_renderer_trace(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                         Hit *hits, uint32_t repeats, double *gpu_ms, vkrt_error *err);

/* Traces count rays once, as vkrt_renderer_trace does, with a renderer created with
 * desc.traversal_stats, and returns what the traversal counted. BVH only (the other walks count
 * nothing). */
bool vkrt_renderer_trace_stats(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                               Hit *hits, vkrt_traversal_stats *stats, vkrt_error *err);

/* The driver's statistics of the closest-hit and any-hit trace kernels as JSON pairs (for a
 * context created with pipeline_statistics; gpu_pipeline_statistics says what they hold). */
bool vkrt_renderer_trace_kernel_statistics(vkrt_renderer *r, char *closest, size_t closest_size,
                                           char *any, size_t any_size, vkrt_error *err);

/* Prints the driver's statistics (registers, spills, instructions: whatever it reports) of each
 * kernel a frame dispatches, a line per kernel, for `vkrt render --profile`: a kernel's time
 * alone does not say whether it waits on memory or runs few threads for want of registers.
 * Needs a context created with pipeline_statistics (the device has to report them). */
bool vkrt_renderer_print_kernel_statistics(vkrt_renderer *r, FILE *out, vkrt_error *err);

#endif
