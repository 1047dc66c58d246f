/*
 * view_denoise.h: `vkrt view --denoise`: what the window shows, denoised. The renderer's
 * accumulated image is read back to the host (its mean per pixel), denoised there by
 * output/denoise.h (OIDN's own device: the CPU, or a GPU it supports, through its buffers) and
 * uploaded into a buffer laid out as the renderer's image (vec4 per pixel, one pass), which the
 * display pass shows in its stead. Each traced frame pays a read-back, the filter and an
 * upload, all waited for.
 */
#ifndef VKRT_VIEW_DENOISE_H
#define VKRT_VIEW_DENOISE_H

#include <stdbool.h>
#include <stdint.h>

#include "../error.h"
#include "../gpu/buffer.h"
#include "../gpu/context.h"
#include "../output/denoise.h"
#include "../render/renderer.h"

typedef struct view_denoise {
    uint32_t width, height; /* of the buffers below; 0 before the first image */
    float *linear;          /* the image's mean, width x height x 3, denoised in place */
    float *packed;          /* the same as vec4s (w = 1) for the upload */
    gpu_buffer image;       /* what the display pass reads: a one-pass image */
    double read_ms, denoise_ms, upload_ms; /* the last image's costs, for --verbose */
} view_denoise;

/* Denoises the renderer's current image (width x height, passes added; with a target error
 * each pixel divided by its own count, as vkrt_renderer_read_image does) into vd->image, made or
 * remade at that size. vd starts zeroed. False with err set. */
bool view_denoise_update(view_denoise *vd, gpu_context *ctx, vkrt_renderer *renderer,
                         vkrt_denoiser *denoiser, uint32_t width, uint32_t height, uint32_t passes,
                         vkrt_error *err);

/* Frees the buffers (the GPU's idle first) and zeroes vd. Safe on a zeroed one. */
void view_denoise_free(view_denoise *vd, gpu_context *ctx);

#endif
