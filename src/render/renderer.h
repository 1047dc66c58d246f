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
 * The same object serves `vkrt render`, `view` and `bench`; it is opaque: what its users need
 * of it they get through the functions below (and trace_api.h for bench and tests).
 *
 * Where each part lives: renderer.c (create, destroy), renderer_upload.c (scene to GPU buffers),
 * renderer_plastic.c (@roughplastic's coat tables), renderer_buffers.c (ray buffers: sizing,
 * growth, binding), renderer_kernels.c (kernel compilation, specialization), renderer_frame.c
 * (recording and running a frame), profile.c (GPU timestamps of a frame), trace_api.c (tracing
 * given rays), camera_frame.c (the camera's frame for raygen), tuning.c (device-dependent
 * defaults).
 */
#ifndef VKRT_RENDERER_H
#define VKRT_RENDERER_H

#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>

#include "../error.h"
#include "../gpu/buffer.h"
#include "../gpu/context.h"
#include "../scene/scene.h"
#include "accel_gpu.h"
#include "profile.h"
#include "tuning.h"

typedef struct vkrt_renderer vkrt_renderer;

/* What the renderer renders and how. Fields left zero where the scene has a setting take the
 * scene's (render_desc.h: resolution, samples, integrator, max-depth); the commands resolve theirs
 * in one place, cmd/render_desc.h. */
/* Where instances (vkrt_model.instances) live on the GPU: auto (0) puts each mesh once under a
 * two-level BVH where that pays (render/accel_instanced.h: the instances hold at least twice the
 * triangles of their meshes, or the flattened scene would not fit the device) and the structure
 * is a BVH, else flattens them into world-space triangles; flat always flattens; two_level
 * always builds the two-level BVH (an error for a scene with emissive triangles, which the light
 * sampling reads in world space). */
typedef enum vkrt_instancing {
    VKRT_INSTANCING_AUTO,
    VKRT_INSTANCING_FLAT,
    VKRT_INSTANCING_TWO_LEVEL,
} vkrt_instancing;

typedef struct vkrt_render_desc {
    uint32_t width, height;   /* 0: the scene's resolution */
    uint32_t samples;         /* samples per pixel; 0: the scene's `samples` (at least 1) */
    vkrt_accel_kind accel;    /* auto (0) chooses from the scene */
    vkrt_bvh_splits bvh_splits; /* auto (0): spatial splits where they pay (accel_gpu.h) */
    vkrt_instancing instancing; /* auto (0): a two-level BVH where instancing pays */
    uint32_t max_depth;       /* generations of secondary rays; 0: the scene's max-depth */
    uint32_t ray_capacity;    /* rays per buffer to start with; 0 (or below the pixel count):
                                 one per pixel. Tests start small to force growth. */
    float min_importance;     /* a cast ray weaker than this is dropped; 0: tuning.c's */
    bool profile;             /* time every dispatch with GPU timestamps (vkrt_frame_stats):
                                 each frame is rendered, then rendered again after
                                 VKRT_WARMUP_MS of GPU warm-up profile_repeat times back to
                                 back, and the medians kept */
    uint32_t profile_repeat;  /* timed frames of a profile; 0: 11 */
    bool traversal_stats;     /* the trace kernels count their work (vkrt_renderer_trace_stats);
                                 slower: never for timings */
    vkrt_integrator integrator; /* auto (0): the scene's, chosen from its lights if that is auto */
    uint32_t light_sampling;  /* path: VKRT_SAMPLING_* of glsl/shared.h, 0 (MIS) but in tests */
    float clamp;              /* > 0: every contribution added to a pixel is scaled so that its
                                 largest channel is at most this (biased: fewer fireflies,
                                 lib/pixel.glsl); 0: no limit */
    float shutter;            /* motion blur: the share of the interval to the next camera
                                 (vkrt_renderer_set_next_camera) each frame's samples are spread
                                 over; 0: none (scene.cfg `shutter`) */
    float target_error;       /* > 0: sample each pixel until its estimated relative error
                                 (glsl/lib/adaptive.glsl) is at most this, or it has `samples`
                                 (the cap); path integrator only. 0: every pixel gets
                                 `samples` (--target-error; vkrt_renderer_convergence) */
    uint32_t aovs;            /* --aov: VKRT_AOV_* of glsl/shared.h, the AOVs each frame records
                                 besides the image (vkrt_renderer_read_aovs); 0: none, and the
                                 kernels are those of a render without (glsl/lib/aov.glsl) */
    uint32_t seed;            /* the random numbers' seed: frame f of seed s draws other numbers than
                                 of seed s' (--seed; 0: the default) */
    vkrt_tuning_overrides tuning; /* zero: the device's defaults (tuning.h) */
} vkrt_render_desc;

typedef struct vkrt_frame_stats {
    double seconds;           /* GPU submission to completion, host clock, of the last attempt */
    uint64_t primary_rays;
    uint64_t shadow_rays;
    uint64_t secondary_rays;
    uint32_t attempts;        /* 1, or more when the ray buffers had to grow */
    uint32_t ray_capacity;    /* rays per buffer after the frame */
    uint64_t dropped_rays;    /* rays past the largest buffers the device allows (then 0 < ...) */
    uint32_t nonfinite;       /* NaN or infinite shading results dropped */
    uint32_t active_pixels;   /* with a target error: pixels that will take more samples (0: the
                                 frame is done before its `samples`) */
    vkrt_frame_profile profile; /* with desc.profile: GPU ms per depth and kernel (profile.h) */
} vkrt_frame_stats;

/* Uploads the scene's geometry, materials and lights, compiles the kernels and creates the
 * buffers for desc's image size. On failure returns false with err set and nothing left;
 * otherwise *out is the renderer, to be freed with vkrt_renderer_destroy. */
bool vkrt_renderer_create(vkrt_renderer **out, gpu_context *ctx, const vkrt_scene *scene,
                          const vkrt_render_desc *desc, vkrt_error *err);

/* The camera of the next frame, towards which the frames rendered from now on move while their
 * shutter is open (vkrt_render_desc.shutter); NULL (the default): no next frame, no motion
 * blur. The camera is copied. */
void vkrt_renderer_set_next_camera(vkrt_renderer *r, const vkrt_config_camera *next);

/* Renders one frame from camera into rgb (width * height * 3 floats, linear radiance, the top row
 * first), averaged over the samples. stats may be NULL. */
bool vkrt_renderer_render(vkrt_renderer *r, const vkrt_config_camera *camera, uint32_t frame_index,
                          float *rgb, vkrt_frame_stats *stats, vkrt_error *err);

/* Progressive rendering (the viewer): adds sample passes [first, first + count) of the
 * renderer's `samples` (the stratification of raygen.comp is over all of them) to the frame's
 * image on the GPU (vkrt_renderer_image), which holds the sum of the passes (vec4 per pixel, w
 * unused; with a target error, w is the pixel's sample count, vkrt_renderer_per_pixel_counts);
 * first == 0 clears it first. One submission, one wait. When the ray buffers must
 * grow, every pass from 0 is rendered again. vkrt_renderer_render is add_samples(0, samples) +
 * read_image. */
bool vkrt_renderer_add_samples(vkrt_renderer *r, const vkrt_config_camera *camera,
                               uint32_t frame_index, uint32_t first, uint32_t count,
                               vkrt_frame_stats *stats, vkrt_error *err);

/* What adaptive sampling reached in the frame rendered last (estimates as glsl/lib/adaptive.glsl
 * defines them). */
typedef struct vkrt_convergence {
    float target; /* the renderer's target error */
    uint32_t pixels;
    uint32_t converged;  /* pixels whose estimate is at most the target */
    double rms_error;    /* root mean square of the pixels' estimates */
    float p99_error;     /* the 99th percentile of the estimates */
    float max_error;     /* the largest (a pixel at the cap, or dark and noisy) */
    uint32_t unestimated; /* pixels with fewer than 2 samples, whose error cannot be estimated:
                             rms, p99 and max are over the others (0 when there are none) */
    double mean_samples; /* samples per pixel, mean, fewest and most */
    uint32_t min_samples, max_samples;
} vkrt_convergence;

struct PixelStats; /* glsl/shared.h */

/* What vkrt_renderer_convergence reports, from pixels' statistics already on the host (sorted:
 * room for pixels floats), each pixel's estimate and samples copied out where those are not
 * NULL (a pixel of fewer than 2 samples has adaptive.glsl's sentinel there, and counts in
 * out->unestimated, not in the rms, p99 or max). */
void vkrt_convergence_of(const struct PixelStats *stats, size_t pixels, float target,
                         vkrt_convergence *out, float *sorted, float *estimates,
                         uint32_t *samples);

/* Reads the pixels' statistics back (once: width * height * 16 bytes) into out, and when not
 * NULL each pixel's estimate and sample count (width * height, top row first). False with err set
 * for a renderer without a target error. */
bool vkrt_renderer_convergence(vkrt_renderer *r, vkrt_convergence *out, float *estimates,
                               uint32_t *samples, vkrt_error *err);

/* Reads the image back as its sum divided by passes (with a target error: by each pixel's own
 * sample count): width * height * 3 floats, top row first. */
bool vkrt_renderer_read_image(vkrt_renderer *r, uint32_t passes, float *rgb, vkrt_error *err);

/* Reads the frame's AOVs back (those of vkrt_render_desc.aovs; glsl/shared.h and
 * docs/scene-format.md, "AOVs", say what each is), width * height pixels, the top row first,
 * each averaged over the pixel's samples as the image is (passes as for read_image; 0: the
 * renderer's samples, what vkrt_renderer_render rendered):
 *   albedo    3 floats in [0, 1]: the albedo at each sample's first non-delta hit
 *   normal    3 floats: the world-space shading normal there, facing the arriving ray (the
 *             mean of unit vectors, so shorter at edges; 0 where every sample escaped)
 *   depth     1 float: the camera ray's hit distance, over the samples that hit; +inf where none
 *   position  3 floats: the camera ray's world-space hit point, likewise; 0 where none hit
 * Each pointer may be NULL (not read); one whose AOV the renderer does not record is an error. */
bool vkrt_renderer_read_aovs(vkrt_renderer *r, uint32_t passes, float *albedo, float *normal,
                             float *depth, float *position, vkrt_error *err);

/* The AOVs the renderer records (VKRT_AOV_*), and their GPU buffer (planes as glsl/shared.h's
 * VKRT_AOV_* comment lays them out; a minimal buffer without any), for a pass that reads them on
 * the device. */
uint32_t vkrt_renderer_aovs(const vkrt_renderer *r);
const gpu_buffer *vkrt_renderer_aov_buffer(const vkrt_renderer *r);

/* Whether the image's w holds each pixel's sample count (a target error), by which it is divided,
 * rather than every pixel having the passes added. */
bool vkrt_renderer_per_pixel_counts(const vkrt_renderer *r);

/* The GPU buffer of the image add_samples accumulates into (the viewer's display pass reads it). */
const gpu_buffer *vkrt_renderer_image(const vkrt_renderer *r);

/* The integrator the renderer computes (never auto), and why: the auto rule's sentence or
 * "asked for". */
vkrt_integrator vkrt_renderer_integrator(const vkrt_renderer *r, const char **reason);

/* The acceleration structure the renderer built, why, and its statistics. */
const vkrt_accel_stats *vkrt_renderer_accel_stats(const vkrt_renderer *r);

/* Device memory the renderer's buffers hold, in bytes, by what they are for (--verbose). */
typedef struct vkrt_renderer_memory {
    uint64_t triangles; /* vertices, normals, texture coordinates, triangle materials */
    uint64_t nodes;     /* the acceleration structure */
    uint64_t textures;  /* texels and their table */
    uint64_t rays;      /* rays, hits, shadow-ray visibility, ray slots */
    uint64_t image;     /* the accumulated image and its AOVs (--aov) */
    uint64_t other;     /* materials, lights, emitters, environment map, counters */
    uint64_t total;
} vkrt_renderer_memory;

/* What vkrt_renderer_memory says the renderer holds now. */
vkrt_renderer_memory vkrt_renderer_memory_use(const vkrt_renderer *r);

/* Which arrays are split over several buffers, and into how many ("triangles in 2 buffers,
 * normals in 2"), into text; "" when every array fits one buffer (--verbose). */
void vkrt_renderer_split_text(const vkrt_renderer *r, char *text, size_t size);

/* The settings the renderer resolved for its device (tuning.h), and whether traversal reads
 * through texel views (the setting, where the views could hold the buffers). */
const vkrt_tuning *vkrt_renderer_tuning(const vkrt_renderer *r);
bool vkrt_renderer_texel_loads(const vkrt_renderer *r);

/* Wall-clock ms of the steps of vkrt_renderer_create, for --verbose's start-up line:
 * the structure (build, layout and upload of its nodes), the per-triangle arrays' upload, the
 * materials and textures, the lights and their sampling tables, the frame's buffers, and the
 * wait for the kernels at the end (compiled on threads alongside the rest, renderer_kernels.c). */
typedef struct vkrt_renderer_startup {
    double structure_ms, geometry_ms, materials_ms, lights_ms, buffers_ms, kernels_ms;
    bool kernels_recompiled; /* compiled for a layout the build did not make (or not known before
                                it), so compiled again after it: the wait is their whole time */
} vkrt_renderer_startup;

const vkrt_renderer_startup *vkrt_renderer_startup_times(const vkrt_renderer *r);

/* Frees everything the renderer created. Safe on NULL. */
void vkrt_renderer_destroy(vkrt_renderer *r);

#endif
