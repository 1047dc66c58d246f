/*
 * finish.h: the stage every finished frame passes through before it leaves the program: into a
 * file (image_write.h, the write pool) or onto the window (view/display.c). A render's linear
 * radiance comes in; what goes out depends on the target: a float file (EXR) keeps the linear,
 * scene-referred values, an 8-bit picture (PNG, the window) is made display-referred and encoded.
 *
 * Today the stage is the denoiser (--denoise, every target), then for 8-bit targets exposure and
 * a tone curve (tonemap.h), then the sRGB encode. A pass on the finished image is one file beside
 * finish.c and one entry in its table of passes, with its settings in vkrt_finish_desc; a pass
 * the window must show too also gets its line in glsl/display.comp, which does the 8-bit path on
 * the GPU with the parameters vkrt_finish_display gives it.
 */
#ifndef VKRT_FINISH_H
#define VKRT_FINISH_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"
#include "../scene/config.h"
#include "denoise.h"

/* What the stage does to a frame. Zero: nothing but the encode an 8-bit target needs. */
typedef struct vkrt_finish_desc {
    float exposure;       /* stops: 8-bit targets get radiance times 2^exposure before the encode;
                             float files keep the radiance (--exposure) */
    vkrt_tonemap tonemap; /* 8-bit targets: the tone curve after exposure (output/tonemap.h;
                             --tonemap, scene.cfg `tonemap`); none: clipped to [0, 1] */
    vkrt_denoiser *denoiser; /* --denoise: Open Image Denoise's RT filter on the radiance
                                (denoise.h), first, for every target; an EXR keeps the raw
                                radiance beside it as layer "noisy" (image_write.h). NULL: none.
                                Not owned: the command makes it once for all its frames */
} vkrt_finish_desc;

/* A frame as the stage gets it: its radiance and, where the renderer made them, the buffers
 * that passes on the whole picture read (the denoiser's albedo and normal). */
typedef struct vkrt_finish_frame {
    uint32_t width, height;
    const float *rgb;    /* linear radiance, 3 floats per pixel, the top row first */
    const float *albedo; /* first non-specular hit's albedo, 3 floats per pixel, or NULL */
    const float *normal; /* its normal, 3 floats per pixel, or NULL */
    bool aux_clean;      /* albedo and normal are free of noise (denoise.h: clean_aux) */
} vkrt_finish_frame;

/* Where a finished frame goes: what it must be made into. */
typedef enum vkrt_finish_target {
    VKRT_FINISH_LINEAR = 0, /* float RGB, scene-referred (EXR) */
    VKRT_FINISH_SRGB8,      /* 8-bit sRGB codes, display-referred (PNG, the window) */
} vkrt_finish_target;

/* Finishes a frame's width x height x 3 linear values for a float file. Returns frame->rgb
 * itself when no pass changes it, else a copy in *scratch (the caller frees it; NULL otherwise)
 * with the passes applied. NULL with err set when out of memory or a pass failed (the
 * denoiser's message). frame->rgb is never written. */
const float *vkrt_finish_linear(const vkrt_finish_desc *d, const vkrt_finish_frame *frame,
                                float **scratch, vkrt_error *err);

/* Finishes a frame's linear values for an 8-bit picture into codes (width x height x 3 bytes):
 * the passes (denoise, exposure, the tone curve), then the sRGB encode of srgb8.h (clamped, NaN
 * black). False with err set when out of memory or a pass failed. frame->rgb is never written. */
bool vkrt_finish_srgb8(const vkrt_finish_desc *d, const vkrt_finish_frame *frame, uint8_t *codes,
                       vkrt_error *err);

/* The parameters glsl/display.comp applies on the GPU for the window, from the same
 * description, so that the window shows what a PNG of the frame holds. */
typedef struct vkrt_finish_display {
    float scale;      /* radiance times this before the curve: 2^exposure */
    uint32_t tonemap; /* then this curve: glsl/tone_curves.h's VKRT_TONE_CURVE_* */
} vkrt_finish_display;

vkrt_finish_display vkrt_finish_display_params(const vkrt_finish_desc *d);

#endif
