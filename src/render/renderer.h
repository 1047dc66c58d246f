/*
 * renderer.h: the wavefront renderer. Uploads a scene once, then renders frames from cameras.
 *
 * One frame is, per sample pass: raygen (one primary ray per pixel) -> trace (closest hit) ->
 * light (direct light with shadow rays, Lambert shade, add to the pixel). All passes of a frame
 * are recorded into one command buffer: the host waits once per frame, never per dispatch.
 * The same object serves `vkrt render` (and later `view` and `bench`).
 */
#ifndef VKRT_RENDERER_H
#define VKRT_RENDERER_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "../gpu/buffer.h"
#include "../gpu/context.h"
#include "../gpu/pipeline.h"
#include "../scene/scene.h"
#include "accel_gpu.h"

/* The structs of glsl/shared.h; declared here so users of vkrt_renderer_trace need not include it. */
typedef struct Ray Ray;
typedef struct Hit Hit;

typedef struct vkrt_render_desc {
    uint32_t width, height;   /* required */
    uint32_t samples;         /* samples per pixel; 0 means 1 */
    uint32_t workgroup_size;  /* 0 means 64 */
    vkrt_accel_kind accel;    /* auto (0) chooses from the scene */
    float grid_density;       /* cells per triangle of a grid; 0: the default */
} vkrt_render_desc;

typedef struct vkrt_frame_stats {
    double seconds;           /* GPU submission to completion, host clock */
    uint64_t primary_rays;
    uint64_t shadow_rays;
} vkrt_frame_stats;

typedef struct vkrt_renderer {
    gpu_context *ctx;
    gpu_storage_set set;
    vkrt_accel_gpu accel;     /* the structure, its statistics and the triangle order */
    gpu_pipeline raygen, trace, light, occlusion;
    gpu_buffer rays, hits, triangles, normals, triangle_material, materials, lights, image,
        counters;
    uint32_t width, height, samples;
    uint32_t triangle_count, light_count;
    uint32_t *light_kinds;    /* VKRT_LIGHT_KIND_* per light, kept for the loop budget check */
    float environment[3];
} vkrt_renderer;

/* Uploads the scene's geometry, materials and lights, compiles the kernels and creates the
 * buffers for desc's image size. On failure returns false with err set and nothing left. */
bool vkrt_renderer_create(vkrt_renderer *r, gpu_context *ctx, const vkrt_scene *scene,
                          const vkrt_render_desc *desc, vkrt_error *err);

/* Renders one frame from camera into rgb (width * height * 3 floats, linear radiance, the top row
 * first), averaged over the samples. stats may be NULL. */
bool vkrt_renderer_render(vkrt_renderer *r, const vkrt_config_camera *camera, uint32_t frame_index,
                          float *rgb, vkrt_frame_stats *stats, vkrt_error *err);

/* Traces count rays (count <= width * height of the renderer) with the renderer's structure: to
 * their closest hits, or (any_hit) to whether anything blocks them (hit.triangle 0 or
 * VKRT_NO_HIT). Closest-hit triangles are reported as original (OBJ order) indices. The trace
 * runs `repeats` times (0 means 1) back to back in one submission; when gpu_ms is not NULL it
 * receives each run's GPU time from timestamps (repeats entries). For tests and bench. */
bool vkrt_renderer_trace(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                         Hit *hits, uint32_t repeats, double *gpu_ms, vkrt_error *err);

/* Fills width * height rays through the pixel centres of camera, as raygen does at one sample
 * per pixel. */
void vkrt_renderer_primary_rays(const vkrt_renderer *r, const vkrt_config_camera *camera,
                                Ray *rays);

/* Frees everything the renderer created. Safe on a zeroed renderer. */
void vkrt_renderer_destroy(vkrt_renderer *r);

#endif
