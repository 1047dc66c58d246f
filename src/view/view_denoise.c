/*
 * view_denoise.c: the viewer's image denoised on its way to the window (view_denoise.h).
 */
#include "view_denoise.h"

#include <stdlib.h>

#include "../clock.h"

/* Buffers for width x height, the old ones freed once the GPU is done with them (a display pass
 * in flight may read the old image). */
static bool resize(view_denoise *vd, gpu_context *ctx, uint32_t width, uint32_t height,
                   vkrt_error *err)
{
    view_denoise_free(vd, ctx);
    size_t pixels = (size_t)width * height;
    vd->linear = malloc(pixels * 3 * sizeof *vd->linear);
    vd->packed = malloc(pixels * 4 * sizeof *vd->packed);
    if (!vd->linear || !vd->packed) {
        view_denoise_free(vd, ctx);
        return vkrt_error_set(err, "out of memory for the denoised %ux%u image", width, height);
    }
    if (!gpu_buffer_create(ctx, &vd->image, pixels * 4 * sizeof(float), "denoised image", err)) {
        view_denoise_free(vd, ctx);
        return false;
    }
    vd->width = width;
    vd->height = height;
    return true;
}

bool view_denoise_update(view_denoise *vd, gpu_context *ctx, vkrt_renderer *renderer,
                         vkrt_denoiser *denoiser, uint32_t width, uint32_t height, uint32_t passes,
                         vkrt_error *err)
{
    if ((vd->width != width || vd->height != height) && !resize(vd, ctx, width, height, err))
        return false;
    double start = vkrt_clock_ms();
    if (!vkrt_renderer_read_image(renderer, passes ? passes : 1, vd->linear, err))
        return false;
    double read = vkrt_clock_ms();
    vkrt_denoise_input in = {.width = width, .height = height, .rgb = vd->linear};
    if (!vkrt_denoiser_run(denoiser, &in, vd->linear, err))
        return false;
    double denoised = vkrt_clock_ms();
    size_t pixels = (size_t)width * height;
    for (size_t i = 0; i < pixels; ++i) {
        vd->packed[4 * i + 0] = vd->linear[3 * i + 0];
        vd->packed[4 * i + 1] = vd->linear[3 * i + 1];
        vd->packed[4 * i + 2] = vd->linear[3 * i + 2];
        vd->packed[4 * i + 3] = 1.0f;
    }
    if (!gpu_buffer_upload(ctx, &vd->image, vd->packed, pixels * 4 * sizeof(float), err))
        return false;
    vd->read_ms = read - start;
    vd->denoise_ms = denoised - read;
    vd->upload_ms = vkrt_clock_ms() - denoised;
    return true;
}

void view_denoise_free(view_denoise *vd, gpu_context *ctx)
{
    /* A failed wait leaves the device lost or hung; gpu_buffer_destroy then frees nothing. */
    if (vd->image.buffer && ctx->device && !ctx->lost)
        (void)vkQueueWaitIdle(ctx->queue);
    gpu_buffer_destroy(ctx, &vd->image);
    free(vd->linear);
    free(vd->packed);
    *vd = (view_denoise){0};
}
