/*
 * finish.c: the stage after the frame (finish.h): its table of passes, run in order on a copy of
 * the linear image, then the target's encode.
 */
#include "finish.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "srgb8.h"
#include "tonemap.h"

/* One pass on the finished linear image. */
typedef struct finish_pass {
    const char *name;
    bool for_linear; /* runs for float files too; else for 8-bit targets alone */
    bool (*wanted)(const vkrt_finish_desc *d);
    /* rgb: the frame's values so far (width x height x 3), changed in place */
    bool (*run)(const vkrt_finish_desc *d, const vkrt_finish_frame *frame, float *rgb,
                vkrt_error *err);
} finish_pass;

/* The denoiser (denoise.h) on the radiance, before anything a display needs: OIDN's HDR
 * filter expects scene-referred values, and a float file gets the denoised beauty too. */
static bool denoise_wanted(const vkrt_finish_desc *d)
{
    return d->denoiser != NULL;
}

static bool denoise_run(const vkrt_finish_desc *d, const vkrt_finish_frame *frame, float *rgb,
                        vkrt_error *err)
{
    vkrt_denoise_input in = {.width = frame->width,
                             .height = frame->height,
                             .rgb = rgb,
                             .albedo = frame->albedo,
                             .normal = frame->normal,
                             .clean_aux = frame->aux_clean};
    return vkrt_denoiser_run(d->denoiser, &in, rgb, err);
}

/* Exposure: a display choice, so float files keep the radiance the renderer computed. */
static bool exposure_wanted(const vkrt_finish_desc *d)
{
    return d->exposure != 0.0f;
}

static bool exposure_run(const vkrt_finish_desc *d, const vkrt_finish_frame *frame, float *rgb,
                         vkrt_error *err)
{
    (void)err;
    float scale = exp2f(d->exposure);
    size_t count = (size_t)frame->width * frame->height * 3;
    for (size_t i = 0; i < count; ++i)
        rgb[i] *= scale;
    return true;
}

/* The tone curve: a display choice too; it takes exposed radiance (tonemap.h). */
static bool tonemap_wanted(const vkrt_finish_desc *d)
{
    return d->tonemap != VKRT_TONEMAP_NONE;
}

static bool tonemap_run(const vkrt_finish_desc *d, const vkrt_finish_frame *frame, float *rgb,
                        vkrt_error *err)
{
    (void)err;
    tonemap_image(d->tonemap, rgb, (size_t)frame->width * frame->height);
    return true;
}

/* The passes, in the order a frame goes through them. A new pass is one entry here. */
static const finish_pass passes[] = {
    {"denoise", true, denoise_wanted, denoise_run},
    {"exposure", false, exposure_wanted, exposure_run},
    {"tonemap", false, tonemap_wanted, tonemap_run},
};
enum { PASS_COUNT = sizeof passes / sizeof *passes };

static bool pass_runs(const finish_pass *p, const vkrt_finish_desc *d, vkrt_finish_target target)
{
    return (p->for_linear || target != VKRT_FINISH_LINEAR) && p->wanted(d);
}

/* The frame's values with every pass for target applied: frame->rgb itself when none runs,
 * else *scratch. */
static const float *run_passes(const vkrt_finish_desc *d, vkrt_finish_target target,
                               const vkrt_finish_frame *frame, float **scratch, vkrt_error *err)
{
    *scratch = NULL;
    float *image = NULL;
    size_t count = (size_t)frame->width * frame->height * 3;
    for (size_t i = 0; i < PASS_COUNT; ++i) {
        if (!pass_runs(&passes[i], d, target))
            continue;
        if (!image) {
            image = malloc(count * sizeof *image);
            if (!image) {
                vkrt_error_set(err, "out of memory for the finished frame (%s)", passes[i].name);
                return NULL;
            }
            memcpy(image, frame->rgb, count * sizeof *image);
        }
        if (!passes[i].run(d, frame, image, err)) {
            free(image);
            return NULL;
        }
    }
    *scratch = image;
    return image ? image : frame->rgb;
}

const float *vkrt_finish_linear(const vkrt_finish_desc *d, const vkrt_finish_frame *frame,
                                float **scratch, vkrt_error *err)
{
    return run_passes(d, VKRT_FINISH_LINEAR, frame, scratch, err);
}

bool vkrt_finish_srgb8(const vkrt_finish_desc *d, const vkrt_finish_frame *frame, uint8_t *codes,
                       vkrt_error *err)
{
    float *scratch;
    const float *image = run_passes(d, VKRT_FINISH_SRGB8, frame, &scratch, err);
    srgb8_table *table = image ? malloc(sizeof *table) : NULL;
    if (!table) {
        free(scratch);
        return image ? vkrt_error_set(err, "out of memory for the sRGB table") : false;
    }
    srgb8_table_init(table);
    /* Scale 1: exposure was a pass; x * 1 is x, so the codes are those of the fused loop. */
    srgb8_encode_array(table, image, 1.0f, (size_t)frame->width * frame->height * 3, codes);
    free(table);
    free(scratch);
    return true;
}

vkrt_finish_display vkrt_finish_display_params(const vkrt_finish_desc *d)
{
    return (vkrt_finish_display){.scale = exp2f(d->exposure), .tonemap = (uint32_t)d->tonemap};
}
