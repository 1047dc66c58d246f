/*
 * renderer_aov.c: the AOVs of --aov (vkrt_render_desc.aovs, renderer.h): their buffer, sized for
 * the AOVs asked for only, and their read-back, each plane divided as the image is. The kernels'
 * side is glsl/lib/aov.glsl; the layout of the planes is glsl/shared.h's (VKRT_AOV_*).
 */
#include <math.h>
#include <stdlib.h>

#include "renderer_private.h"

/* The plane of AOV bit a among those recorded (the set bits below it). */
static uint32_t plane_of(uint32_t aovs, uint32_t a)
{
    return (uint32_t)__builtin_popcount(aovs & (a - 1));
}

bool renderer_aov_create_buffer(vkrt_renderer *r, vkrt_error *err)
{
    size_t pixels = (size_t)r->width * r->height;
    size_t planes = (size_t)__builtin_popcount(r->aovs);
    /* raygen clears each pixel's planes at its first sample; nothing reads them before. */
    return gpu_buffer_create(r->ctx, &r->aov_planes, planes * pixels * sizeof(vec4), "AOV planes",
                             err);
}

uint32_t vkrt_renderer_aovs(const vkrt_renderer *r)
{
    return r->aovs;
}

const gpu_buffer *vkrt_renderer_aov_buffer(const vkrt_renderer *r)
{
    return &r->aov_planes;
}

/* Pixel i of one plane into out: albedo and normal are sums over the pixel's samples (scale is
 * 1 / samples), depth and position sums over the samples that hit, with their count. */
static void finish_pixel(uint32_t a, vec4 v, float scale, size_t i, float *out)
{
    switch (a) {
    case VKRT_AOV_ALBEDO:
    case VKRT_AOV_NORMAL:
        out[3 * i + 0] = v.x * scale;
        out[3 * i + 1] = v.y * scale;
        out[3 * i + 2] = v.z * scale;
        break;
    case VKRT_AOV_DEPTH:
        out[i] = v.y > 0 ? v.x / v.y : INFINITY;
        break;
    case VKRT_AOV_POSITION:
        out[3 * i + 0] = v.w > 0 ? v.x / v.w : 0.0f;
        out[3 * i + 1] = v.w > 0 ? v.y / v.w : 0.0f;
        out[3 * i + 2] = v.w > 0 ? v.z / v.w : 0.0f;
        break;
    default:
        break;
    }
}

bool vkrt_renderer_read_aovs(vkrt_renderer *r, uint32_t passes, float *albedo, float *normal,
                             float *depth, float *position, vkrt_error *err)
{
    static const char *const names[] = {"albedo", "normal", "depth", "position"};
    float *outs[] = {albedo, normal, depth, position};
    uint32_t wanted = 0;
    for (uint32_t k = 0; k < 4; ++k) {
        if (!outs[k])
            continue;
        if (!(r->aovs & (1u << k)))
            return vkrt_error_set(err, "the %s AOV was not asked of the renderer", names[k]);
        wanted |= 1u << k;
    }
    if (!wanted)
        return true;
    size_t pixels = (size_t)r->width * r->height;
    size_t planes = (size_t)__builtin_popcount(r->aovs);
    vec4 *sums = malloc(planes * pixels * sizeof *sums);
    /* Adaptive sampling: each pixel's own sample count, the image's w (adapt.comp). */
    bool adaptive = r->target_error > 0;
    vec4 *image = adaptive ? malloc(pixels * sizeof *image) : NULL;
    bool ok = sums && (!adaptive || image);
    if (!ok)
        vkrt_error_set(err, "out of memory reading back the AOVs of %zu pixels", pixels);
    ok = ok && gpu_buffer_download(r->ctx, &r->aov_planes, sums, planes * pixels * sizeof *sums,
                                   err);
    ok = ok && (!adaptive ||
                gpu_buffer_download(r->ctx, &r->image, image, pixels * sizeof *image, err));
    for (uint32_t k = 0; ok && k < 4; ++k) {
        uint32_t a = 1u << k;
        if (!(wanted & a))
            continue;
        const vec4 *plane = sums + plane_of(r->aovs, a) * pixels;
        float scale = 1.0f / (float)(passes ? passes : r->samples);
        for (size_t i = 0; i < pixels; ++i) {
            if (adaptive)
                scale = image[i].w > 0 ? 1.0f / image[i].w : 0.0f;
            finish_pixel(a, plane[i], scale, i, outs[k]);
        }
    }
    free(image);
    free(sums);
    return ok;
}
