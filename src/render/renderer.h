/*
 * renderer.h: the wavefront renderer. Uploads a scene once, then renders frames from cameras.
 *
 * One frame is, per sample pass: raygen (one primary ray per pixel), then per depth up to
 * max-depth: trace (closest hit) -> light (shadow rays, one visibility bit per light) -> count
 * (each material's count_rays, atomics reserve slots for the next depth) -> prepare (the next
 * depth's indirect dispatch) -> shade (materials add to pixels and cast into the slots). All
 * passes of a frame go into one command buffer: the host waits once per frame, never per bounce.
 * When a depth asked for more rays than the buffers hold, the host grows them (at least doubling,
 * never shrinking) and renders the frame again; the image is the same as with large buffers.
 * The same object serves `vkrt render`, `view` and `bench`.
 */
#ifndef VKRT_RENDERER_H
#define VKRT_RENDERER_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "../error.h"
#include "../gpu/buffer.h"
#include "../gpu/context.h"
#include "../gpu/pipeline.h"
#include "../scene/scene.h"
#include "accel_gpu.h"

/* The structs of glsl/shared.h; declared here so users of vkrt_renderer_trace need not include it. */
typedef struct Ray Ray;
typedef struct Hit Hit;
typedef struct FrameParams FrameParams;

/* How the trace kernels of the 2-wide BVH take their rays: one per invocation (static), or from
 * a counter as lanes finish (dynamic ray fetch, glsl/lib/trace_wave.glsl). */
typedef enum vkrt_ray_fetch {
    VKRT_RAY_FETCH_DEFAULT,
    VKRT_RAY_FETCH_STATIC,
    VKRT_RAY_FETCH_DYNAMIC,
} vkrt_ray_fetch;

/* How the traversal reads triangles and BVH nodes: as storage buffers, or through uniform texel
 * buffer views of the same buffers (texelFetch). The default is texel loads on CPU devices, where
 * Mesa's llvmpipe loads a storage buffer one lane and one word at a time, with a branch for each
 * (docs/performance.md), and storage loads elsewhere. */
typedef enum vkrt_loads {
    VKRT_LOADS_DEFAULT,
    VKRT_LOADS_STORAGE,
    VKRT_LOADS_TEXEL,
} vkrt_loads;

/* How the BVH's walk is laid out: one loop that visits a node or a leaf per iteration, or inner
 * nodes and leaves in two loops of their own inside a third (glsl/lib/traverse_bvh.glsl). The
 * default is the nested walk on CPU devices, where Mesa's llvmpipe runs both sides of every
 * branch any lane takes, and one loop elsewhere, where it measured faster (docs/performance.md). */
typedef enum vkrt_walk {
    VKRT_WALK_DEFAULT,
    VKRT_WALK_ONE_LOOP,
    VKRT_WALK_NESTED,
} vkrt_walk;

typedef struct vkrt_render_desc {
    uint32_t width, height;   /* required */
    uint32_t samples;         /* samples per pixel; 0 means 1 */
    uint32_t workgroup_size;  /* 0 means 64 */
    vkrt_accel_kind accel;    /* auto (0) chooses from the scene */
    float grid_density;       /* cells per triangle of a grid; 0: the default */
    uint32_t bvh_width;       /* children per node of the BVH's GPU layout, 2 or 4; 0: the default */
    uint32_t bvh_max_leaf;    /* the BVH build's largest leaf (1..16); 0: the default */
    float bvh_traversal_cost; /* the BVH build's SAH cost of a node against a triangle; 0: the default */
    vkrt_ray_fetch ray_fetch; /* how trace kernels take their rays (2-wide BVH); 0: the default */
    vkrt_loads loads;         /* how traversal reads triangles and nodes; 0: the default */
    vkrt_walk walk;           /* how the BVH's walk loops; 0: the default */
    uint32_t max_depth;       /* generations of secondary rays; 0: the scene's max-depth */
    uint32_t ray_capacity;    /* rays per buffer to start with; 0 (or below the pixel count):
                                 one per pixel. Tests start small to force growth. */
    float min_importance;     /* a cast ray weaker than this is dropped; 0: the default 1e-3 */
    bool traversal_stats;     /* the trace kernels count their work (vkrt_renderer_trace_stats);
                                 slower: never for timings */
    bool profile;             /* time every dispatch with GPU timestamps (vkrt_frame_stats):
                                 each frame is rendered, then rendered again after 300 ms of GPU
                                 warm-up profile_repeat times back to back, and the medians kept */
    uint32_t profile_repeat;  /* timed frames of a profile; 0: 11 */
    uint32_t sort_cells;      /* 2..16: compile the ray sort (vkrt_renderer_trace_sorted) over
                                 sort_cells x sort_cells direction cells; 0: no sort */
} vkrt_render_desc;

/* What the trace kernels counted for one trace (glsl/shared.h Counters.trace_*). */
typedef struct vkrt_traversal_stats {
    uint32_t rays;
    double steps_per_ray;     /* BVH records fetched */
    double tests_per_ray;     /* triangle tests */
    double simd_utilisation;  /* lane-iterations with work over those the subgroups spent */
    uint32_t subgroup_size;
} vkrt_traversal_stats;

/* The kernels of a frame, for profiles. */
enum { VKRT_KERNEL_RAYGEN, VKRT_KERNEL_TRACE, VKRT_KERNEL_LIGHT, VKRT_KERNEL_COUNT,
       VKRT_KERNEL_PREPARE, VKRT_KERNEL_SHADE, VKRT_KERNEL_KINDS };
/* Depths a profile tells apart; deeper ones are added to the last. */
#define VKRT_PROFILE_DEPTHS 17

typedef struct vkrt_frame_stats {
    double seconds;           /* GPU submission to completion, host clock, of the last attempt */
    uint64_t primary_rays;
    uint64_t shadow_rays;
    uint64_t secondary_rays;
    uint32_t attempts;        /* 1, or more when the ray buffers had to grow */
    uint32_t ray_capacity;    /* rays per buffer after the frame */
    uint64_t dropped_rays;    /* rays past the largest buffers the device allows (then 0 < ...) */
    uint32_t nonfinite;       /* NaN or infinite shading results dropped */
    bool profiled;            /* the renderer was created with desc.profile: */
    double kernel_ms[VKRT_PROFILE_DEPTHS][VKRT_KERNEL_KINDS]; /* GPU ms per depth and kernel,
                                 summed over the sample passes (raygen counts at depth 0), the
                                 median over the timed frames */
    double frame_ms;          /* GPU ms from the first dispatch to the last, the median */
    uint32_t profile_frames;  /* timed frames the medians are of */
    uint32_t profile_warmups; /* frames rendered back to back before them */
} vkrt_frame_stats;

/* Prints a profile (stats->profiled) as a table: a row per depth, a column per kernel, and the
 * frame's time over its tracing's (closest hits and shadow rays: trace + light). */
void vkrt_frame_stats_print_profile(FILE *out, const vkrt_frame_stats *stats);

typedef struct vkrt_renderer {
    gpu_context *ctx;
    gpu_storage_set set;
    vkrt_accel_gpu accel;     /* the structure, its statistics and the triangle order */
    gpu_pipeline raygen, trace, light, occlusion, count, prepare, shade;
    gpu_pipeline sort_count, sort_scan, sort_scatter; /* when sort_cells != 0 */
    uint32_t sort_cells;
    gpu_buffer rays, rays_b, hits, triangles, normals, texcoords, triangle_material, materials,
        lights, image, counters, waves, visibility, slots, texture_infos, texels;
    gpu_buffer trace_cursor;  /* per depth, the rays the trace kernels have taken (dynamic fetch) */
    uint32_t width, height, samples, max_depth;
    uint32_t triangle_count, light_count, light_words;
    uint32_t capacity, max_capacity; /* rays per ray buffer: now, and the most the device allows */
    float min_importance;
    bool profile;
    vkrt_ray_fetch ray_fetch; /* as asked in the desc */
    bool dynamic_fetch;       /* the trace kernels fetch rays from trace_cursor */
    bool texel_loads;         /* traversal reads triangles and nodes through the views below */
    bool nested_walk;         /* the BVH's walk loops over nodes and leaves apart (vkrt_walk) */
    VkBufferView triangle_view, node_view; /* texel views of triangles and accel.nodes */
    uint32_t profile_repeat;  /* timed frames of a profile */
    uint32_t *light_kinds;    /* VKRT_LIGHT_KIND_* per light, kept for the loop budget check */
    char **material_names;    /* per uploaded material, "name (file:line)", for messages */
    uint32_t material_count;
} vkrt_renderer;

/* Uploads the scene's geometry, materials and lights, compiles the kernels and creates the
 * buffers for desc's image size. On failure returns false with err set and nothing left. */
bool vkrt_renderer_create(vkrt_renderer *r, gpu_context *ctx, const vkrt_scene *scene,
                          const vkrt_render_desc *desc, vkrt_error *err);

/* Renders one frame from camera into rgb (width * height * 3 floats, linear radiance, the top row
 * first), averaged over the samples. stats may be NULL. */
bool vkrt_renderer_render(vkrt_renderer *r, const vkrt_config_camera *camera, uint32_t frame_index,
                          float *rgb, vkrt_frame_stats *stats, vkrt_error *err);

/* Progressive rendering (the viewer): adds sample passes [first, first + count) of the
 * renderer's `samples` (the stratification of raygen.comp is over all of them) to the frame's
 * image on the GPU, r->image, which holds the sum of the passes (vec4 per pixel, w unused);
 * first == 0 clears it first. One submission, one wait. When the ray buffers must grow, every
 * pass from 0 is rendered again. vkrt_renderer_render is add_samples(0, samples) + read_image. */
bool vkrt_renderer_add_samples(vkrt_renderer *r, const vkrt_config_camera *camera,
                               uint32_t frame_index, uint32_t first, uint32_t count,
                               vkrt_frame_stats *stats, vkrt_error *err);

/* Reads the image back as its sum divided by passes: width * height * 3 floats, top row first. */
bool vkrt_renderer_read_image(vkrt_renderer *r, uint32_t passes, float *rgb, vkrt_error *err);

/* Traces count rays (count <= width * height of the renderer) with the renderer's structure: to
 * their closest hits, or (any_hit) to whether anything blocks them (hit.triangle 0 or
 * VKRT_NO_HIT). Closest-hit triangles are reported as original (OBJ order) indices. The trace
 * runs `repeats` times (0 means 1) back to back in one submission; when gpu_ms is not NULL it
 * receives each run's GPU time from timestamps (repeats entries). For tests and bench. */
bool vkrt_renderer_trace(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                         Hit *hits, uint32_t repeats, double *gpu_ms, vkrt_error *err);

/* As vkrt_renderer_trace (closest hits), but each run first orders the rays on the GPU by the
 * cell of their direction on a desc.sort_cells x sort_cells octahedral map (glsl/lib/
 * ray_sort.glsl; the renderer must have been created with sort_cells). With trace false only the
 * sort runs, and gpu_ms times it alone. hits[i] belongs to sorted[i], the rays in their new order
 * (info.x tells them apart); sorted may be NULL, hits too when trace is false. */
bool vkrt_renderer_trace_sorted(vkrt_renderer *r, const Ray *rays, uint32_t count, bool trace,
                                Hit *hits, Ray *sorted, uint32_t repeats, double *gpu_ms,
                                vkrt_error *err);

/* Traces count rays once, as vkrt_renderer_trace does, with a renderer created with
 * desc.traversal_stats, and returns what the traversal counted. BVH only (the other walks count
 * nothing). */
bool vkrt_renderer_trace_stats(vkrt_renderer *r, const Ray *rays, uint32_t count, bool any_hit,
                               Hit *hits, vkrt_traversal_stats *stats, vkrt_error *err);

/* Fills params->eye, forward, right and up for camera and an image of width x height: the
 * camera frame raygen.comp reads (right and up scaled by tan(fov/2), right also by the aspect).
 * Pure CPU, so that bench_rays.c makes the very rays raygen does. */
void vkrt_camera_params(const vkrt_config_camera *camera, uint32_t width, uint32_t height,
                        FrameParams *params);

/* Frees everything the renderer created. Safe on a zeroed renderer. */
void vkrt_renderer_destroy(vkrt_renderer *r);

#endif
