/*
 * envmap.h: an equirectangular environment map as a light: its pixels, and the piecewise-constant
 * 2D distribution that importance-samples it (pbrt's Distribution2D: a marginal over rows, one
 * conditional per row).
 *
 * Convention (Mitsuba 3's `envmap` emitter, src/emitters/envmap.cpp, uv_to_direction): +y is up;
 * a map pixel at horizontal fraction u (0 at the left edge, 1 at the right) and polar angle theta
 * (0 at the top row, pi at the bottom) is seen in the direction
 *     (sin(phi) sin(theta), cos(theta), -cos(phi) sin(theta)),  phi = 2 pi u - rotate,
 * so the left edge of the map is looking down -z, a quarter across down +x, the middle down +z.
 * `rotate` turns the map about +y, as Mitsuba's to_world = rotate([0, 1, 0], angle) does. uv here
 * is the texture's uv (glsl/lib/texture.glsl): v = 0 is the bottom row, so v = 1 - theta / pi,
 * and the map's bilinear lookup at envmap_uv(d, rotate) (glsl/lib/environment.glsl, filtered as
 * texture_sample filters) is the radiance seen along d.
 *
 * The GPU buffer (binding VKRT_BINDING_ENVIRONMENT, glsl/lib/envmap.glsl), floats:
 *     [0, H]                            the marginal CDF over rows, top row first: H + 1 floats,
 *                                       0 first and 1 last
 *     [H + 1 + y (W + 1), ... + W]      row y's conditional CDF over its texels, left to right:
 *                                       W + 1 floats each, 0 first and 1 last
 * for a W x H map, (H + 1) + H (W + 1) floats in all. Row y covers theta in [y, y + 1] pi / H,
 * texel x covers u in [x, x + 1] / W. The density in uv of texel (x, y) is
 *     (M[y + 1] - M[y]) H (C_y[x + 1] - C_y[x]) W,
 * computed from the CDF steps themselves, so the density the sampler returns and the density of
 * a direction agree to the bit. A texel's weight is the mean over the texel of the luminance that
 * the bilinear lookup (as texture_sample filters, wrapping across the left and right edges
 * and clamped at the top and bottom rows: the poles) returns, times the mean of
 * sin(theta) over its row: the lookup's texels x - 1, x, x + 1 weighed 1/8, 3/4, 1/8 across, and
 * likewise down. So a texel whose radiance is anywhere non-zero has a positive weight, and its CDF
 * step is kept positive even where it is too small for a float: the estimator stays unbiased.
 *
 * Pure CPU, no Vulkan.
 */
#ifndef VKRT_ENVMAP_H
#define VKRT_ENVMAP_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "../error.h"

struct LightInfo; /* glsl/shared.h */

/* Largest radiance an environment map holds: what the texel buffer's half floats can store. */
#define VKRT_ENVMAP_MAX_RADIANCE 65504.0f

/* An environment map's pixels: width x height linear RGB, 3 floats per pixel, the top row first,
 * each channel finite and in [0, VKRT_ENVMAP_MAX_RADIANCE]. */
typedef struct vkrt_envmap_image {
    uint32_t width, height;
    float *rgb;
} vkrt_envmap_image;

/* Reads the equirectangular map at path: OpenEXR (.exr, any case; R, G, B channels, or Y for a
 * grey map, of the first part, scanline or tiled) through OpenEXRCore, anything else through
 * stb_image (Radiance .hdr as linear floats; 8-bit PNG, JPEG, TGA decoded from sRGB, exactly as
 * a colour texture is). Channels below 0 or NaN read as 0, above VKRT_ENVMAP_MAX_RADIANCE
 * (infinity too) as that maximum. On failure returns false with err set to
 * "<referrer>: environment-map '<path>': <reason>" (the referrer, e.g. "scene.cfg:4", left out
 * when NULL) and *image zeroed: a missing or unreadable file, an image of 0 or more than
 * VKRT_TEXTURE_MAX_SIZE pixels across or down, no colour channels, memory. Free with
 * vkrt_envmap_image_free. */
bool vkrt_envmap_load(const char *path, const char *referrer, vkrt_envmap_image *image,
                      vkrt_error *err);

/* Frees the pixels and zeroes *image. Safe on a zeroed struct and on NULL. */
void vkrt_envmap_image_free(vkrt_envmap_image *image);

/* The sampling distribution of a map, in the GPU layout above. */
typedef struct vkrt_envmap_distribution {
    uint32_t width, height;
    float *data;        /* float_count floats, uploaded as they are */
    size_t float_count; /* vkrt_envmap_distribution_floats(width, height) */
    double weight_sum;  /* the sum of the texel weights; 0 for a black map (whose CDFs are then
                           uniform, never sampled: LightInfo.environment_sampled is 0) */
} vkrt_envmap_distribution;

/* (height + 1) + height * (width + 1): the floats of a width x height map's distribution. */
size_t vkrt_envmap_distribution_floats(uint32_t width, uint32_t height);

/* Builds the distribution of width x height pixels rgb (3 floats each, top row first, finite and
 * >= 0 as vkrt_envmap_load leaves them). Returns false with err set and *dist zeroed for a size of
 * 0 or past VKRT_TEXTURE_MAX_SIZE, or when memory runs out. Free with
 * vkrt_envmap_distribution_free. */
bool vkrt_envmap_distribution_build(const float *rgb, uint32_t width, uint32_t height,
                                    vkrt_envmap_distribution *dist, vkrt_error *err);

/* Frees the data and zeroes *dist. Safe on a zeroed struct and on NULL. */
void vkrt_envmap_distribution_free(vkrt_envmap_distribution *dist);

/* Fills LightInfo's environment_width, _height, _scale, _rotate (radians, from degrees),
 * _integral (weight_sum) and _sampled (1 when weight_sum and scale are above 0) for the map;
 * leaves environment_pixels and the emitter fields alone. */
void vkrt_envmap_light_info(const vkrt_envmap_distribution *dist, float scale, float rotate_degrees,
                            struct LightInfo *info);

/* ---------------------------------------------------------------------------------------------
 * The CPU mirror of glsl/lib/envmap.glsl, the same float arithmetic step by step (for tests; a
 * change there belongs here too). data is a distribution's buffer for a width x height map;
 * rotate is in radians (LightInfo.environment_rotate).
 * ------------------------------------------------------------------------------------------- */

/* The unit direction that texture uv (u, v) of the map is seen in (envmap_direction). */
void vkrt_envmap_direction(float u, float v, float rotate, float dir[3]);

/* The texture uv of the map seen along unit direction dir, u in [0, 1] (envmap_uv). */
void vkrt_envmap_uv(const float dir[3], float rotate, float uv[2]);

/* Maps two uniform numbers in [0, 1) to a texture uv by the CDF walk (binary search in the
 * marginal, then in the chosen row's conditional, continuous within the texel), returning the
 * density in uv in *pdf_uv (envmap_sample). The direction is vkrt_envmap_direction of it; its
 * solid-angle density is pdf_uv / (2 pi^2 sin(theta)). */
void vkrt_envmap_sample(const float *data, uint32_t width, uint32_t height, float u1, float u2,
                        float uv[2], float *pdf_uv);

/* The density in uv of the texel holding texture uv (u, v), u wrapped into [0, 1), v clamped to
 * [0, 1]. */
float vkrt_envmap_pdf_uv(const float *data, uint32_t width, uint32_t height, float u, float v);

/* The solid-angle density with which vkrt_envmap_sample yields unit direction dir (envmap_pdf):
 * pdf_uv / (2 pi^2 sin(theta)), 0 straight up or down. */
float vkrt_envmap_pdf(const float *data, uint32_t width, uint32_t height, float rotate,
                      const float dir[3]);

#endif
